"""Tire parameters of the brush model: frozen dataclasses, validated on construction.

A tire is read from a TOML file under ``models/tires/`` (:func:`load_tire`, shipped name
``"passenger"``); every field carries its SI unit in its doc. The groups follow the physics:

* :class:`PatchLaw` -- contact-patch half-length ``a`` and width ``b`` from the load, the
  MF-Tyre 6.1 relations (Pacejka 2012, *Tire and Vehicle Dynamics*, 3rd ed., eqs. (A3.7) and
  (A3.8)) with the vertical deflection ``rho = Fz / C_z``;
* :class:`TreadParams` -- brush elements: shear stiffness, tip mass and damping per unit area,
  and the void (groove) fraction of the footprint;
* :class:`CarcassParams` -- translational compliance of the belt against the rim (what makes
  forces build up over a relaxation length);
* :class:`ThermalParams` -- the optional lumped tread temperature.

This module imports only the standard library (and the stdlib-only :mod:`tirefric.errors`) at
module level: it runs inside an FMU. :func:`load_tire` imports the TOML reader on call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from pathlib import Path

from tirefric.errors import InputError, InputErrors
from tirefric.units import si_unit


def _check(obj: object, name: str, *, positive: bool = False, nonnegative: bool = False,
           maximum: float | None = None, problems: list[InputError]) -> None:
    """Append an :class:`InputError` to ``problems`` if field ``name`` of ``obj`` is bad."""
    x = getattr(obj, name)
    where = f"{type(obj).__name__}.{name}"
    if isinstance(x, bool) or not isinstance(x, int | float) or not math.isfinite(x):
        problems.append(InputError("must be a finite number", field=where, value=x))
        return
    if positive and not x > 0:
        problems.append(InputError("must be > 0", field=where, value=x))
    if nonnegative and not x >= 0:
        problems.append(InputError("must be >= 0", field=where, value=x))
    if maximum is not None and not x <= maximum:
        problems.append(InputError(f"must be <= {maximum:g}", field=where, value=x))


def _param(dimension: str | None, description: str, *,
           positive: bool = False, nonnegative: bool = False,
           maximum: float | None = None, toml_default: bool | None = None,
           default: float | None = None) -> object:
    """A parameter field carrying, once, what every user of it needs: its dimension in
    :mod:`tirefric.units` (``None`` for a boolean), from which the TOML value is read and the
    FMU unit follows (:func:`tirefric.units.si_unit`), the description (FMU variable table,
    docs) and the bounds (validation, TOML loader). ``default`` is the value when the class is
    built in code without it (a tire file must still give it)."""
    extra = {} if default is None else {"default": default}
    unit = None if dimension is None else si_unit(dimension)
    return field(**extra, metadata={
        "unit": unit, "dimension": dimension, "description": description,
        "bounds": {"positive": positive, "nonnegative": nonnegative, "maximum": maximum},
        "toml_default": toml_default})


def _validate(obj: object) -> list[InputError]:
    """Problems of the number fields of ``obj`` against their metadata bounds."""
    problems: list[InputError] = []
    for f in fields(obj):
        if f.metadata.get("unit") is None:
            continue
        b = f.metadata["bounds"]
        _check(obj, f.name, positive=b["positive"], nonnegative=b["nonnegative"],
               maximum=b["maximum"], problems=problems)
    return problems


def parameter_fields(cls: type) -> list:
    """The parameter fields (with metadata) of a parameter class, in order."""
    return [f for f in fields(cls) if "description" in f.metadata]


def _raise(problems: list[InputError]) -> None:
    if len(problems) == 1:
        raise problems[0]
    if problems:
        raise InputErrors(problems)


@dataclass(frozen=True)
class PatchLaw:
    """Contact-patch size and pressure shape from the load and the inflation pressure.

    Size: Pacejka 2012, eqs. (A3.7)-(A3.8), with the vertical stiffness at the inflation
    pressure ``C_z' = C_z (1 + p_fz1 (p_inflation - p_nom) / p_nom)`` (MF 6.2; Pacejka 2012,
    sec. 4.3.2) and the vertical deflection ``rho = min(Fz, Fz_max) / C_z'``:

    * half-length ``a = R0 (q_ra2 rho/R0 + q_ra1 sqrt(rho/R0))``  (A3.7),
    * width ``b = 2 W (q_rb2 rho/R0 + q_rb1 (rho/R0)^(1/3))``  (twice the half-width of A3.8).

    Above ``Fz_max`` the patch keeps its size at ``Fz_max`` and only the pressure grows.

    Pressure along the patch (docs/tire-core.md, "pressure along the patch"): a flat centre
    at the peak pressure over ``|x| <= c`` with parabolic ends, ``p = p_peak (1 - t^2)``,
    ``t = (|x| - c)/(a - c)``. The flat part is where the inflation pressure carries the
    flattened tread band (membrane equilibrium: the gross contact pressure of a radial tire
    is close to its inflation pressure, Clark (ed.), *Mechanics of Pneumatic Tires*, 1981,
    ch. 5); its share ``c/a = 3 Fz / (2 a b p_inflation) - 2`` makes the mean pressure
    of the shape, ``p_peak (2 + c/a) / 3``, equal to ``Fz / (2 a b)`` with ``p_peak =
    p_inflation``, clipped to ``[0, 1 - end_zone]``: below ``c = 0`` (light load) the
    distribution is Pacejka's parabola, above the clip the peak exceeds the inflation
    pressure (the carcass carries the rest). ``end_zone = 1`` gives the parabola at every
    load (Pacejka's closed forms).

    Attributes
    ----------
    R0 : float
        Unloaded radius [m].
    width : float
        Nominal section width W [m].
    C_z : float
        Vertical stiffness [N/m].
    q_ra1, q_ra2 : float
        Square-root and linear coefficients of the length law [1].
    q_rb1, q_rb2 : float
        Cube-root and linear coefficients of the width law [1].
    Fz_max : float
        Load up to which the law is used [N]; the law must give a growing patch up to it.
    p_inflation, p_nom : float
        Inflation pressure and the nominal one of ``C_z`` [Pa].
    p_fz1 : float
        Pressure coefficient of the vertical stiffness [1] (MF 6.2 PFZ1).
    end_zone : float
        Smallest share of the half-length over which the pressure falls to zero at each end
        [1] (1: parabola).
    """

    R0: float = _param(
        "length", "Unloaded radius [m] (patch-size law, Pacejka 2012 eqs. (A3.7)-(A3.8))",
        positive=True)
    width: float = _param(
        "length", "Nominal section width W [m] (patch-width law)", positive=True)
    C_z: float = _param(
        "stiffness", "Vertical stiffness [N/m] (deflection Fz / C_z of the patch laws)",
        positive=True)
    q_ra1: float = _param(
        "dimensionless", "Square-root coefficient of the patch-length law [1]", positive=True)
    q_ra2: float = _param("dimensionless", "Linear coefficient of the patch-length law [1]")
    q_rb1: float = _param(
        "dimensionless", "Cube-root coefficient of the patch-width law [1]", positive=True)
    q_rb2: float = _param("dimensionless", "Linear coefficient of the patch-width law [1]")
    Fz_max: float = _param(
        "force", "Load [N] above which the patch keeps its size", positive=True)
    p_inflation: float = _param(
        "pressure", "Inflation pressure [Pa] (vertical stiffness and pressure shape)",
        positive=True)
    p_nom: float = _param(
        "pressure", "Nominal inflation pressure [Pa] of C_z (MF 6.2 NOMPRES)",
        positive=True)
    p_fz1: float = _param(
        "dimensionless",
        "Pressure coefficient of the vertical stiffness [1] (MF 6.2 PFZ1)", nonnegative=True)
    end_zone: float = _param(
        "dimensionless", "Smallest share of the patch half-length over which the pressure "
        "falls to zero at each end [1] (1: parabolic pressure)", positive=True, maximum=1.0)

    def __post_init__(self) -> None:
        _raise(_validate(self))
        # the laws must give a positive patch that grows with the load up to Fz_max
        prev_a = prev_b = 0.0
        for i in range(1, 65):
            a, b = self.size(self.Fz_max * i / 64)
            if not (a > prev_a and b > prev_b):
                raise InputError(
                    f"the contact-patch law must give a length and width growing with the load "
                    f"up to Fz_max (at Fz = {self.Fz_max * i / 64:g} N: a = {a:g} m, "
                    f"b = {b:g} m); lower Fz_max or check q_ra*/q_rb*",
                    field="PatchLaw.Fz_max", value=self.Fz_max)
            prev_a, prev_b = a, b

    @property
    def vertical_stiffness(self) -> float:
        """Vertical stiffness at the inflation pressure [N/m] (MF 6.2)."""
        return self.C_z * (1.0 + self.p_fz1 * ((self.p_inflation - self.p_nom) / self.p_nom))

    def flat_share(self, Fz: float) -> float:
        """Share ``c/a`` of the half-length over which the pressure is flat (class doc)."""
        a, b = self.size(Fz)
        if not (a > 0 and b > 0):
            return 0.0
        f = 3.0 * (Fz / (2.0 * a * b * self.p_inflation)) - 2.0
        return min(max(f, 0.0), 1.0 - self.end_zone)

    def size(self, Fz: float) -> tuple[float, float]:
        """Half-length ``a`` [m] and width ``b`` [m] at load ``Fz`` [N] (0 for Fz <= 0)."""
        if not Fz > 0:
            return 0.0, 0.0
        r = min(Fz, self.Fz_max) / (self.vertical_stiffness * self.R0)
        a = self.R0 * (self.q_ra2 * r + self.q_ra1 * math.sqrt(r))
        b = 2.0 * self.width * (self.q_rb2 * r + self.q_rb1 * r ** (1.0 / 3.0))
        return a, b


@dataclass(frozen=True)
class TreadParams:
    """Brush (tread) elements, per unit area of the gross footprint.

    Each element is a tip of mass ``mass`` on a Kelvin-Voigt shear spring (``k_x``, ``k_y``;
    ``d_x``, ``d_y``) to the belt. ``k`` times the patch width is Pacejka's ``c_p`` (stiffness
    per unit length), so the slip stiffnesses of the rigid-carcass brush are
    ``C_Fkappa = 2 k_x b a^2`` and ``C_Falpha = 2 k_y b a^2`` (Pacejka 2012, sec. 3.2).

    Attributes
    ----------
    k_x, k_y : float
        Longitudinal and lateral shear stiffness per unit area [N/m^3].
    mass : float
        Tip mass per unit area [kg/m^2] (0 = massless brush of Pacejka ch. 3).
    d_x, d_y : float
        Viscous damping per unit area [N s/m^3].
    void_ratio : float
        Groove (void) fraction of the footprint [1]; the friction tables are read at the
        pressure on the rubber, ``p / (1 - void_ratio)``.
    depth : float
        Groove depth [m]: with the void ratio, the water the grooves hold under the footprint
        (``void_ratio * depth`` per unit area), which sets the water depth at which dynamic
        hydroplaning starts (:mod:`tire_brush.hydroplaning`).
    contact_ageing : bool
        Contact age of the elements (docs/tire-core.md, "contact age"): an element carries
        the age ``theta`` of its contact, ``d theta/dt = 1 - |w| theta / D`` (the ageing law of
        rate-and-state friction: J.H. Dieterich, J. Geophys. Res. 84 (1979) 2161; A. Ruina,
        J. Geophys. Res. 88 (1983) 10359), 0 when it enters the patch, and reads the grid's
        friction at ``D / theta`` instead of ``|w|`` (our closure; ``D = s0 / 0.2``, the
        macro-asperity contact size of eq. (28); review sec. 5.1, ``tau = d / v``, and
        sec. 5.3, contact-time-dependent bond formation). Steady sliding reads ``|w|``
        exactly; false (the default in code and when a tire file omits it) reads ``|w|``
        always.
    """

    k_x: float = _param(
        "stiffness_per_area",
        "Longitudinal tread shear stiffness per unit footprint area [N/m3]", positive=True)
    k_y: float = _param(
        "stiffness_per_area",
        "Lateral tread shear stiffness per unit footprint area [N/m3]", positive=True)
    mass: float = _param(
        "mass_per_area", "Tread element tip mass per unit footprint area [kg/m2]",
        nonnegative=True)
    d_x: float = _param(
        "damping_per_area", "Longitudinal tread damping per unit footprint area [N.s/m3]",
        nonnegative=True)
    d_y: float = _param(
        "damping_per_area", "Lateral tread damping per unit footprint area [N.s/m3]",
        nonnegative=True)
    void_ratio: float = _param(
        "dimensionless", "Groove (void) fraction of the footprint [1]", nonnegative=True,
        maximum=0.9)
    depth: float = _param(
        "length", "Groove (tread) depth [m]: the grooves hold void_ratio * depth of water "
        "(hydroplaning)", nonnegative=True, default=8e-3)
    contact_ageing: bool = _param(
        None, "Contact age: the element reads the friction at D / theta, theta its contact "
        "age (Dieterich's ageing law), instead of at its slip speed", toml_default=False,
        default=False)

    def __post_init__(self) -> None:
        _raise(_validate(self))

    @property
    def isotropic(self) -> bool:
        """Whether stiffness and damping are equal in x and y."""
        return self.k_x == self.k_y and self.d_x == self.d_y


@dataclass(frozen=True)
class CarcassParams:
    """Translational compliance of the belt (massless) against the rim.

    The belt carries the tread; it is held by springs ``k_x``, ``k_y`` and dampers ``d_x``,
    ``d_y``. In steady state the belt translation is at rest relative to the rim and does not
    change the forces; in transients it adds ``C_F / k`` to the relaxation length (Pacejka
    2012, sec. 7.2). The belt also yaws (twists) about the vertical axis against ``k_psi``,
    ``d_psi``: the aligning moment of the tread turns it by ``psi = Mz / k_psi``, which
    lowers the slip angle the tread sees, ``alpha' = alpha - Mz / k_psi`` in steady state
    (the carcass twist of Pacejka 2012, sec. 3.3, Fig. 3.33), so the cornering stiffness
    ``C / (1 + C t / k_psi)`` saturates and then falls as the load grows. ``rigid = true``
    removes both.

    Camber: the base line of a thin disk tilted by ``gamma`` and pressed on the road curves
    with ``sin(gamma) / R``, so the base of the tread spins at ``-omega sin(gamma)`` as the
    wheel rolls and the brush produces the camber thrust ``(2/3) c_py a^3 sin(gamma) / R_e``
    (parabolic pressure, no sliding; Pacejka 2012, ch. 3, the brush model with camber). A
    real belt does not follow that curvature in full; the share it does not follow is the
    camber reduction ``eps`` (Pacejka's ``epsilon_gamma``, ch. 4): the spin is ``-(1 - eps)
    omega sin(gamma)``.

    Attributes
    ----------
    rigid : bool
        Rigid carcass (no belt deflection).
    k_x, k_y : float
        Longitudinal and lateral stiffness [N/m].
    d_x, d_y : float
        Longitudinal and lateral damping [N s/m].
    k_psi, d_psi : float
        Yaw (twist) stiffness [N m/rad] and damping [N m s/rad].
    camber_reduction : float
        Camber reduction ``eps`` in [0, 1] [1]: 0 is the thin disk (Pacejka's brush).
    """

    rigid: bool = _param(None, "Rigid carcass: no belt deflection", toml_default=False)
    k_x: float = _param(
        "stiffness", "Longitudinal belt (carcass) stiffness [N/m]", positive=True)
    k_y: float = _param("stiffness", "Lateral belt (carcass) stiffness [N/m]", positive=True)
    d_x: float = _param(
        "damping", "Longitudinal belt (carcass) damping [N.s/m]", nonnegative=True)
    d_y: float = _param(
        "damping", "Lateral belt (carcass) damping [N.s/m]", nonnegative=True)
    k_psi: float = _param(
        "rotational_stiffness", "Yaw (twist) stiffness of the belt [N.m/rad]",
        positive=True)
    d_psi: float = _param(
        "rotational_damping", "Yaw (twist) damping of the belt [N.m.s/rad]",
        nonnegative=True)
    camber_reduction: float = _param(
        "dimensionless", "Camber reduction eps: the base of the tread spins at "
        "-(1 - eps) omega sin(gamma) [1]", nonnegative=True, maximum=1.0, default=0.0)

    def __post_init__(self) -> None:
        _raise(_validate(self))


@dataclass(frozen=True)
class ThermalParams:
    """Lumped tread temperature (optional state of the transient model).

    ``C dT/dt = eta P_fric - G (T - T_surface)``: heated by the fraction ``eta`` of the
    frictional power in the footprint, cooled towards the background temperature.

    Attributes
    ----------
    enabled : bool
        Whether the transient model carries the state (else T0 = T_surface).
    heat_capacity : float
        Heat capacity C of the tread rubber [J/K].
    conductance : float
        Heat conductance G to the surroundings [W/K].
    heat_fraction : float
        Fraction eta of the frictional heat that enters the tread [1].
    """

    enabled: bool = _param(
        None, "Carry the lumped tread temperature (else T_tread = T_surface)")
    heat_capacity: float = _param(
        "heat_capacity_total", "Heat capacity of the tread [J/K]", positive=True)
    conductance: float = _param(
        "conductance", "Heat conductance from the tread to the surroundings [W/K]",
        nonnegative=True)
    heat_fraction: float = _param(
        "dimensionless", "Fraction of the frictional heat entering the tread [1]",
        nonnegative=True, maximum=1.0)

    def __post_init__(self) -> None:
        _raise(_validate(self))


@dataclass(frozen=True)
class TireParams:
    """All parameters of one tire.

    Attributes
    ----------
    name : str
        Short name (the shipped file's stem).
    R_e : float
        Effective rolling radius [m]: the rolling speed is ``omega R_e``.
    Fz_nom : float
        Nominal load [N]; the transient model spaces its elements on the patch at this load.
    patch : PatchLaw
        Contact-patch size from the load.
    tread : TreadParams
        Brush elements.
    carcass : CarcassParams
        Belt compliance.
    thermal : ThermalParams
        Lumped tread temperature.
    description, provenance : str
        What the tire is and where its numbers come from.
    source : str
        The file it was read from ("" if built in code).
    """

    name: str
    R_e: float = _param(
        "length", "Effective rolling radius [m]: the rolling speed is omega * R_e",
        positive=True)
    Fz_nom: float = _param(
        "force", "Nominal load [N]: the tread elements are spaced on the patch at this load",
        positive=True)
    patch: PatchLaw
    tread: TreadParams
    carcass: CarcassParams
    thermal: ThermalParams
    description: str = ""
    provenance: str = ""
    source: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        _raise(_validate(self))
        if self.Fz_nom > self.patch.Fz_max:
            raise InputError(f"nominal load above the patch law's Fz_max = "
                             f"{self.patch.Fz_max:g} N", field="TireParams.Fz_nom",
                             value=self.Fz_nom)

    def slip_stiffness(self, Fz: float) -> tuple[float, float]:
        """Rigid-carcass brush slip stiffnesses ``(C_Fkappa [N], C_Falpha [N/rad])`` at ``Fz``:
        ``C_F = 2 c_p a^2`` with ``c_p = k b`` (Pacejka 2012, ch. 3; docs/review-notes.md)."""
        a, b = self.patch.size(Fz)
        return 2.0 * self.tread.k_x * b * a * a, 2.0 * self.tread.k_y * b * a * a

    def describe(self) -> dict:
        """Parameters as a JSON-able dict (for provenance of results and FMU metadata)."""
        out: dict = {"name": self.name, "R_e_m": self.R_e, "Fz_nom_N": self.Fz_nom,
                     "source": self.source}
        for group in GROUPS:
            g = getattr(self, group)
            out[group] = {f.name: getattr(g, f.name) for f in fields(g)}
        return out


#: The parameter groups of :class:`TireParams`: field name (the tire file's table, the FMU
#: variables' prefix ``tire.<group>.``) -> class.
GROUPS: dict[str, type] = {"patch": PatchLaw, "tread": TreadParams, "carcass": CarcassParams,
                           "thermal": ThermalParams}


# -- TOML -------------------------------------------------------------------------------------
# Units of every field come from its dimension in the one unit table, tirefric.units.


def load_tire(name_or_path: str | Path) -> TireParams:
    """Read tire parameters from a TOML file or a shipped name (``"passenger"``).

    Errors name the file, the field and the value (:class:`~tirefric.errors.InputError`);
    unknown (misspelt) keys are refused.
    """
    from tirefric.config import Table
    from tirefric.paths import resolve_model_file

    path = resolve_model_file(name_or_path, "tires")
    t = Table.load(path)
    name = t.string("name")
    description = t.string("description", "")
    provenance = t.string("provenance", "")
    R_e, Fz_nom = (_read(t, f) for f in parameter_fields(TireParams))
    groups = {}
    for name_, cls in GROUPS.items():
        tab = t.table(name_)
        groups[name_] = (tab, _build(tab, cls, **{f.name: _read(tab, f)
                                                  for f in parameter_fields(cls)}))
    for tab, _ in groups.values():
        tab.check_unknown()
    # [rolling_resistance] is read by tire_brush.rolling_resistance (its own parameters)
    t.check_unknown(extra_allowed=("rolling_resistance",))
    try:
        return TireParams(name=name, R_e=R_e, Fz_nom=Fz_nom,
                          **{g: obj for g, (_, obj) in groups.items()},
                          description=description, provenance=provenance, source=str(path))
    except InputError as exc:
        raise InputError(exc.message, source=path, field=exc.field, value=exc.value) from None


def field_table() -> dict[str, tuple[str | None, str]]:
    """Every tire parameter: dotted path (``"tread.k_x"``) -> (FMU unit, description), from the
    fields' metadata (the FMU's variable table and the docs read it here)."""
    out: dict[str, tuple[str | None, str]] = {}
    for f in parameter_fields(TireParams):
        out[f.name] = (f.metadata["unit"], f.metadata["description"])
    for group, cls in GROUPS.items():
        for f in parameter_fields(cls):
            out[f"{group}.{f.name}"] = (f.metadata["unit"], f.metadata["description"])
    return out


def parameters_markdown() -> str:
    """docs/tire-parameters.md: the table of tire parameters, written from the fields'
    metadata (``python -c "from tire_brush.params import parameters_markdown as m;
    print(m(), end='')" > docs/tire-parameters.md``; a test keeps the file equal to it)."""
    lines = ["# Tire parameters", "",
             "Written from the fields of `tire_brush/params.py` (their metadata is the one "
             "source of the unit, the bounds and the description: the TOML loader, the "
             "validation and the FMU's variables read it too). TOML files under "
             "`models/tires/` give each as a number in SI or as `\"<number> <unit>\"`.", "",
             "| parameter | unit | bounds | description |", "|---|---|---|---|"]
    classes = {"": TireParams, "patch.": PatchLaw, "tread.": TreadParams,
               "carcass.": CarcassParams, "thermal.": ThermalParams}
    for prefix, cls in classes.items():
        for f in parameter_fields(cls):
            m = f.metadata
            b = m["bounds"]
            bounds = ", ".join(t for t in (
                "> 0" if b["positive"] else "", ">= 0" if b["nonnegative"] else "",
                f"<= {b['maximum']:g}" if b["maximum"] is not None else "") if t)
            unit = "true/false" if m["unit"] is None else m["unit"]
            lines.append(f"| `{prefix}{f.name}` | {unit} | {bounds} | {m['description']} |")
    return "\n".join(lines) + "\n"


def _read(tab, f):
    """Field ``f`` of a parameter class from TOML table ``tab``, by its metadata (dimension,
    bounds; a boolean may have a default)."""
    m = f.metadata
    if m["unit"] is None:
        return tab.boolean(f.name, *(() if m["toml_default"] is None else (m["toml_default"],)))
    b = m["bounds"]
    return tab.quantity(f.name, m["dimension"], positive=b["positive"],
                        nonnegative=b["nonnegative"], maximum=b["maximum"])


def _build(table, cls, **kwargs):
    """Construct ``cls(**kwargs)``, re-raising validation errors with the file named."""
    try:
        return cls(**kwargs)
    except InputErrors as exc:
        raise InputErrors([InputError(e.message, source=table.source, field=e.field,
                                      value=e.value) for e in exc.errors]) from None
    except InputError as exc:
        raise InputError(exc.message, source=table.source, field=exc.field,
                         value=exc.value) from None
