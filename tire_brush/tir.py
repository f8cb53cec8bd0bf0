"""Write Magic Formula coefficients as a TYDEX / MF-Tyre tire property file (``.tir``).

The layout follows the public MF-Tyre 6.1 and PAC2002 property files (sections
``[MDI_HEADER]``, ``[UNITS]``, ``[MODEL]``, ``[DIMENSION]``, ``[OPERATING_CONDITIONS]``,
``[VERTICAL]``, the validity ranges, ``[SCALING_COEFFICIENTS]`` and the coefficient sections):
``KEY = value $comment`` lines with a blank on each side of ``=`` and before ``$`` (some
readers cut the key and the value at those blanks), ``!`` comment lines, SI units
(``[UNITS]``: meter, newton, radian, kg, second) and the ISO-W (TYDEX W) sign convention of
:mod:`tire_brush.axes`. Numbers are written with Python's shortest exact ``repr``, so reading
the file back gives the fitted values bit for bit.

Every coefficient the fit does not set (the camber terms other than the camber stiffness
``PKY6, PKY7``, pressure, turn slip, the overturning moment other than ``QSX3``, the rolling
resistance other than ``QSY1, QSY3, QSY7``, relaxation) is written as 0 rather than left out,
so no reader falls back on a default from another tire; ``LMUV`` (friction decay with slip speed)
is 0 because the brush's own speed dependence is already in the fitted curves at the fitted
speed; every other scaling factor is 1.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from tirefric.errors import InputError

#: Coefficient sections: (section, [(key, description)]). Fitted or fixed values come from the
#: fit; keys it does not set are written as 0 (``PKY4``: 2).
COEFFICIENT_SECTIONS: list[tuple[str, list[tuple[str, str]]]] = [
    ("LONGITUDINAL_COEFFICIENTS", [
        ("PCX1", "Shape factor Cfx for longitudinal force"),
        ("PDX1", "Longitudinal friction Mux at Fznom"),
        ("PDX2", "Variation of friction Mux with load"),
        ("PDX3", "Variation of friction Mux with camber squared"),
        ("PEX1", "Longitudinal curvature Efx at Fznom"),
        ("PEX2", "Variation of curvature Efx with load"),
        ("PEX3", "Variation of curvature Efx with load squared"),
        ("PEX4", "Factor in curvature Efx while driving"),
        ("PKX1", "Longitudinal slip stiffness Kfx/Fz at Fznom"),
        ("PKX2", "Variation of slip stiffness Kfx/Fz with load"),
        ("PKX3", "Exponent in slip stiffness Kfx/Fz with load"),
        ("PHX1", "Horizontal shift Shx at Fznom"),
        ("PHX2", "Variation of shift Shx with load"),
        ("PVX1", "Vertical shift Svx/Fz at Fznom"),
        ("PVX2", "Variation of shift Svx/Fz with load"),
        ("PPX1", "Linear influence of inflation pressure on slip stiffness"),
        ("PPX2", "Quadratic influence of inflation pressure on slip stiffness"),
        ("PPX3", "Linear influence of inflation pressure on peak friction"),
        ("PPX4", "Quadratic influence of inflation pressure on peak friction"),
        ("RBX1", "Slope factor for combined slip Fx reduction"),
        ("RBX2", "Variation of slope Fx reduction with kappa"),
        ("RBX3", "Influence of camber on stiffness for Fx combined"),
        ("RCX1", "Shape factor for combined slip Fx reduction"),
        ("REX1", "Curvature factor of combined Fx"),
        ("REX2", "Curvature factor of combined Fx with load"),
        ("RHX1", "Shift factor for combined slip Fx reduction"),
    ]),
    ("OVERTURNING_COEFFICIENTS", [
        ("QSX1", "Vertical shift of overturning moment"),
        ("QSX2", "Camber induced overturning couple"),
        ("QSX3", "Fy induced overturning couple"),
    ]),
    ("LATERAL_COEFFICIENTS", [
        ("PCY1", "Shape factor Cfy for lateral forces"),
        ("PDY1", "Lateral friction Muy"),
        ("PDY2", "Variation of friction Muy with load"),
        ("PDY3", "Variation of friction Muy with squared camber"),
        ("PEY1", "Lateral curvature Efy at Fznom"),
        ("PEY2", "Variation of curvature Efy with load"),
        ("PEY3", "Zero order camber dependency of curvature Efy"),
        ("PEY4", "Variation of curvature Efy with camber"),
        ("PEY5", "Variation of curvature Efy with camber squared"),
        ("PKY1", "Maximum value of stiffness Kfy/Fznom"),
        ("PKY2", "Load at which Kfy reaches maximum value"),
        ("PKY3", "Variation of Kfy/Fznom with camber"),
        ("PKY4", "Curvature of stiffness Kfy"),
        ("PKY5", "Peak stiffness variation with camber squared"),
        ("PKY6", "Fy camber stiffness factor"),
        ("PKY7", "Vertical load dependency of camber stiffness"),
        ("PHY1", "Horizontal shift Shy at Fznom"),
        ("PHY2", "Variation of shift Shy with load"),
        ("PVY1", "Vertical shift in Svy/Fz at Fznom"),
        ("PVY2", "Variation of shift Svy/Fz with load"),
        ("PVY3", "Variation of shift Svy/Fz with camber"),
        ("PVY4", "Variation of shift Svy/Fz with camber and load"),
        ("PPY1", "Pressure effect on cornering stiffness magnitude"),
        ("PPY2", "Pressure effect on location of cornering stiffness peak"),
        ("PPY3", "Linear pressure effect on lateral friction"),
        ("PPY4", "Quadratic pressure effect on lateral friction"),
        ("PPY5", "Influence of inflation pressure on camber stiffness"),
        ("RBY1", "Slope factor for combined Fy reduction"),
        ("RBY2", "Variation of slope Fy reduction with alpha"),
        ("RBY3", "Shift term for alpha in slope Fy reduction"),
        ("RBY4", "Influence of camber on stiffness of Fy combined"),
        ("RCY1", "Shape factor for combined Fy reduction"),
        ("REY1", "Curvature factor of combined Fy"),
        ("REY2", "Curvature factor of combined Fy with load"),
        ("RHY1", "Shift factor for combined Fy reduction"),
        ("RHY2", "Shift factor for combined Fy reduction with load"),
        ("RVY1", "Kappa induced side force Svyk/Muy*Fz at Fznom"),
        ("RVY2", "Variation of Svyk/Muy*Fz with load"),
        ("RVY3", "Variation of Svyk/Muy*Fz with camber"),
        ("RVY4", "Variation of Svyk/Muy*Fz with alpha"),
        ("RVY5", "Variation of Svyk/Muy*Fz with kappa"),
        ("RVY6", "Variation of Svyk/Muy*Fz with atan(kappa)"),
    ]),
    ("ROLLING_COEFFICIENTS", [
        ("QSY1", "Rolling resistance torque coefficient"),
        ("QSY2", "Rolling resistance torque depending on Fx"),
        ("QSY3", "Rolling resistance torque depending on speed"),
        ("QSY4", "Rolling resistance torque depending on speed ^4"),
        ("QSY5", "Rolling resistance torque depending on camber squared"),
        ("QSY6", "Rolling resistance torque depending on load and camber squared"),
        ("QSY7", "Rolling resistance torque coefficient load dependency"),
        ("QSY8", "Rolling resistance torque coefficient pressure dependency"),
    ]),
    ("ALIGNING_COEFFICIENTS", [
        ("QBZ1", "Trail slope factor for trail Bpt at Fznom"),
        ("QBZ2", "Variation of slope Bpt with load"),
        ("QBZ3", "Variation of slope Bpt with load squared"),
        ("QBZ4", "Variation of slope Bpt with camber"),
        ("QBZ5", "Variation of slope Bpt with absolute camber"),
        ("QBZ9", "Factor for scaling factors of slope factor Br of Mzr"),
        ("QBZ10", "Factor for dimensionless cornering stiffness of Br of Mzr"),
        ("QCZ1", "Shape factor Cpt for pneumatic trail"),
        ("QDZ1", "Peak trail Dpt = Dpt*(Fz/Fznom*R0)"),
        ("QDZ2", "Variation of peak Dpt with load"),
        ("QDZ3", "Variation of peak Dpt with camber"),
        ("QDZ4", "Variation of peak Dpt with camber squared"),
        ("QDZ6", "Peak residual torque Dmr = Dmr/(Fz*R0)"),
        ("QDZ7", "Variation of peak factor Dmr with load"),
        ("QDZ8", "Variation of peak factor Dmr with camber"),
        ("QDZ9", "Variation of peak factor Dmr with camber and load"),
        ("QDZ10", "Variation of peak factor Dmr with camber squared"),
        ("QDZ11", "Variation of Dmr with camber squared and load"),
        ("QEZ1", "Trail curvature Ept at Fznom"),
        ("QEZ2", "Variation of curvature Ept with load"),
        ("QEZ3", "Variation of curvature Ept with load squared"),
        ("QEZ4", "Variation of curvature Ept with sign of Alpha-t"),
        ("QEZ5", "Variation of Ept with camber and sign Alpha-t"),
        ("QHZ1", "Trail horizontal shift Sht at Fznom"),
        ("QHZ2", "Variation of shift Sht with load"),
        ("QHZ3", "Variation of shift Sht with camber"),
        ("QHZ4", "Variation of shift Sht with camber and load"),
        ("PPZ1", "Effect of inflation pressure on length of pneumatic trail"),
        ("PPZ2", "Influence of inflation pressure on residual aligning torque"),
        ("SSZ1", "Nominal value of s/R0: effect of Fx on Mz"),
        ("SSZ2", "Variation of distance s/R0 with Fy/Fznom"),
        ("SSZ3", "Variation of distance s/R0 with camber"),
        ("SSZ4", "Variation of distance s/R0 with load and camber"),
    ]),
]

#: Scaling factors, all written as 1 except ``LMUV`` (0: no friction decay with slip speed).
SCALING = [
    ("LFZO", "Scale factor of nominal (rated) load"),
    ("LCX", "Scale factor of Fx shape factor"),
    ("LMUX", "Scale factor of Fx peak friction coefficient"),
    ("LEX", "Scale factor of Fx curvature factor"),
    ("LKX", "Scale factor of Fx slip stiffness"),
    ("LHX", "Scale factor of Fx horizontal shift"),
    ("LVX", "Scale factor of Fx vertical shift"),
    ("LCY", "Scale factor of Fy shape factor"),
    ("LMUY", "Scale factor of Fy peak friction coefficient"),
    ("LEY", "Scale factor of Fy curvature factor"),
    ("LKY", "Scale factor of Fy cornering stiffness"),
    ("LKYC", "Scale factor of Fy camber stiffness"),
    ("LKZC", "Scale factor of Mz camber stiffness"),
    ("LHY", "Scale factor of Fy horizontal shift"),
    ("LVY", "Scale factor of Fy vertical shift"),
    ("LTR", "Scale factor of peak of pneumatic trail"),
    ("LRES", "Scale factor for offset of residual torque"),
    ("LXAL", "Scale factor of alpha influence on Fx"),
    ("LYKA", "Scale factor of kappa influence on Fy"),
    ("LVYKA", "Scale factor of kappa induced Fy"),
    ("LS", "Scale factor of moment arm of Fx"),
    ("LMX", "Scale factor of overturning couple"),
    ("LVMX", "Scale factor of Mx vertical shift"),
    ("LMY", "Scale factor of rolling resistance torque"),
    ("LMP", "Scale factor of parking moment"),
    ("LMUV", "Friction decay with slip speed (0: none; the fit holds the brush's own)"),
]


@dataclass(frozen=True)
class TireSize:
    """ISO metric size designation (``205/55 R16``).

    Attributes
    ----------
    width : float
        Nominal section width [m].
    aspect_ratio : float
        Nominal aspect ratio [1].
    rim_radius : float
        Nominal rim radius [m].
    """

    width: float
    aspect_ratio: float
    rim_radius: float


_SIZE = re.compile(r"\b(\d{3})\s*/\s*(\d{2,3})\s*Z?R\s*(\d{2}(?:\.\d)?)\b", re.I)


def parse_size(text: str, source: str = "--size") -> TireSize:
    """The first ISO metric size designation (``"205/55 R16"``, ``"205/55R16"``) in ``text``."""
    m = _SIZE.search(text)
    if not m:
        raise InputError("no tire size designation like '205/55 R16' found", source=source,
                         value=text)
    w, ar, rim_in = int(m[1]) / 1000.0, int(m[2]) / 100.0, float(m[3])
    return TireSize(width=w, aspect_ratio=ar, rim_radius=rim_in * 0.0254 / 2.0)


_PRESSURE = re.compile(r"(\d+(?:\.\d+)?)\s*bar\b", re.I)


def parse_pressure_bar(text: str, source: str) -> float:
    """The first ``<number> bar`` in ``text``, in Pa."""
    m = _PRESSURE.search(text)
    if not m:
        raise InputError("no inflation pressure like '2.3 bar' found", source=source,
                         value=text)
    return float(m[1] + "e5")                # exact decimal: 2.3 bar -> 230000.0 Pa


def _num(x: float) -> str:
    return repr(float(x))


def tir_text(coefficients: dict[str, float], *, fittyp: int, size: TireSize,
             pressure: float, vertical_stiffness: float, vx: float,
             ranges: dict[str, float], provenance: list[str]) -> str:
    """The ``.tir`` file as text.

    Parameters
    ----------
    coefficients
        ``FNOMIN``, ``UNLOADED_RADIUS`` and MF coefficients (ISO-W); missing ones are 0.
    fittyp
        61 (MF-Tyre 6.1) or 6 (PAC2002); the force and ``Mz`` coefficients are the same (the
        fit keeps ``PKY4 = 2``, the PAC2002 value); PAC2002 readers do not evaluate ``PKY6,
        PKY7`` or ``QSY7`` (:func:`tire_brush.mf_fit.fit_mf` with ``fittyp=6``).
    size
        Width, aspect ratio, rim radius.
    pressure
        Inflation pressure written as both nominal and operating pressure [Pa] (no
        coefficient depends on it).
    vertical_stiffness
        [N/m].
    vx
        Speed of the fit [m/s] (``LONGVL``).
    ranges
        ``KPUMIN, KPUMAX, ALPMIN, ALPMAX, CAMMIN, CAMMAX, FZMIN, FZMAX``: the fitted ranges
        (``CAMMIN = CAMMAX = 0`` when the camber fit does not apply).
    provenance
        Comment lines (without the leading ``!``).
    """
    if fittyp not in (6, 61):
        raise InputError("must be 61 (MF 6.1) or 6 (PAC2002)", field="FITTYP", value=fittyp)
    lines: list[str] = []

    def kv(key: str, value: str, comment: str = "") -> None:
        line = f"{key:<24} = {value:<24}"
        lines.append(f"{line} ${comment}" if comment else line.rstrip())

    def section(name: str) -> None:
        lines.append(f"${'-' * 60}{name.lower()}")
        lines.append(f"[{name}]")

    lines += ["[MDI_HEADER]"]
    kv("FILE_TYPE", "'tir'")
    kv("FILE_VERSION", "3.0")
    kv("FILE_FORMAT", "'ASCII'")
    lines += [f"! {t}" for t in provenance]
    lines += ["!",
              "! USE_MODE: 4 = Fx, Fy, Mx, My, Mz with combined slip (no relaxation).",
              "! Sign convention: ISO-W (TYDEX W): positive slip angle gives negative Fy."]
    section("UNITS")
    for k, v in (("LENGTH", "'meter'"), ("FORCE", "'newton'"), ("ANGLE", "'radian'"),
                 ("MASS", "'kg'"), ("TIME", "'second'")):
        kv(k, v)
    section("MODEL")
    if fittyp == 6:
        kv("PROPERTY_FILE_FORMAT", "'PAC2002'")
    kv("FITTYP", str(fittyp), "Magic Formula version: 61 = MF 6.1, 6 = PAC2002")
    kv("USE_MODE", "4", "Tyre use switch: combined slip, no relaxation")
    kv("TYRESIDE", "'LEFT'", "Mounted side (the fitted tire is symmetric)")
    kv("LONGVL", _num(vx), "Reference speed: the speed of the fit [m/s]")
    kv("VXLOW", "1.0", "Lower boundary of slip calculation [m/s]")
    section("DIMENSION")
    kv("UNLOADED_RADIUS", _num(coefficients["UNLOADED_RADIUS"]), "Free tyre radius [m]")
    kv("WIDTH", _num(size.width), "Nominal section width of the tyre [m]")
    kv("ASPECT_RATIO", _num(size.aspect_ratio), "Nominal aspect ratio [1]")
    kv("RIM_RADIUS", _num(size.rim_radius), "Nominal rim radius [m]")
    section("OPERATING_CONDITIONS")
    kv("INFLPRES", _num(pressure), "Tyre inflation pressure [Pa]")
    kv("NOMPRES", _num(pressure), "Nominal pressure used in MF equations [Pa]")
    section("VERTICAL")
    kv("FNOMIN", _num(coefficients["FNOMIN"]), "Nominal wheel load [N]")
    kv("VERTICAL_STIFFNESS", _num(vertical_stiffness), "Tyre vertical stiffness [N/m]")
    section("LONG_SLIP_RANGE")
    kv("KPUMIN", _num(ranges["KPUMIN"]), "Minimum valid wheel slip (fitted range)")
    kv("KPUMAX", _num(ranges["KPUMAX"]), "Maximum valid wheel slip (fitted range)")
    section("SLIP_ANGLE_RANGE")
    kv("ALPMIN", _num(ranges["ALPMIN"]), "Minimum valid slip angle [rad] (fitted range)")
    kv("ALPMAX", _num(ranges["ALPMAX"]), "Maximum valid slip angle [rad] (fitted range)")
    section("INCLINATION_ANGLE_RANGE")
    kv("CAMMIN", _num(ranges["CAMMIN"]), "Minimum valid camber angle [rad] (fitted range)")
    kv("CAMMAX", _num(ranges["CAMMAX"]), "Maximum valid camber angle [rad] (fitted range)")
    section("VERTICAL_FORCE_RANGE")
    kv("FZMIN", _num(ranges["FZMIN"]), "Minimum allowed wheel load [N] (fitted range)")
    kv("FZMAX", _num(ranges["FZMAX"]), "Maximum allowed wheel load [N] (fitted range)")
    section("SCALING_COEFFICIENTS")
    for k, desc in SCALING:
        kv(k, "0.0" if k == "LMUV" else "1.0", desc)
    for name, keys in COEFFICIENT_SECTIONS:
        section(name)
        for k, desc in keys:
            kv(k, _num(coefficients.get(k, 2.0 if k == "PKY4" else 0.0)), desc)
    return "\n".join(lines) + "\n"


def write_tir(path: str | Path, text: str) -> None:
    """Write ``text`` (from :func:`tir_text`) to ``path``."""
    Path(path).write_text(text)
