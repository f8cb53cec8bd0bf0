"""``tirefric tire fit-mf``: the .tir file read back and evaluated by an independent Magic
Formula written here (it imports nothing of tire_brush.magic_formula, tire_brush.mf_fit or
tire_brush.tir), against the brush model recomputed here.

Tolerances: the file's numbers are exact (shortest repr), so the round trip is compared
exactly; the independent evaluator repeats the fitter's arithmetic in another order, so the
errors it finds agree with the reported ones to 1e-9 (round-off); the MF agrees with the brush
only within the reported fit error (the MF form cannot follow the brush exactly: docs/mf-fit.md).
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import re
import time

import numpy as np
import pytest

from tire_brush.cli import load_friction
from tire_brush.params import load_tire
from tire_brush.steady import SteadyBrush
from tirefric import __version__
from tirefric.cli import main

T_C, VX = 20.0, 20.0
CHANNELS = ("Fx_pure", "Fy_pure", "Mz_pure", "Fx_combined", "Fy_combined", "Mz_combined")

# MF 6.1 / PAC2002 key names of the coefficient sections (MF-Tyre 6.1 property file, Pacejka
# 2012 sec. 4.3.2 and appendix 3), for the check that the file uses no invented names.
KNOWN = {
    "LONGITUDINAL_COEFFICIENTS": "PCX1 PDX1 PDX2 PDX3 PEX1 PEX2 PEX3 PEX4 PKX1 PKX2 PKX3 PHX1 "
    "PHX2 PVX1 PVX2 PPX1 PPX2 PPX3 PPX4 RBX1 RBX2 RBX3 RCX1 REX1 REX2 RHX1 PTX1 PTX2 PTX3",
    "OVERTURNING_COEFFICIENTS": "QSX1 QSX2 QSX3 QSX4 QSX5 QSX6 QSX7 QSX8 QSX9 QSX10 QSX11 "
    "QSX12 QSX13 QSX14 PPMX1",
    "LATERAL_COEFFICIENTS": "PCY1 PDY1 PDY2 PDY3 PEY1 PEY2 PEY3 PEY4 PEY5 PKY1 PKY2 PKY3 "
    "PKY4 PKY5 PKY6 PKY7 PHY1 PHY2 PHY3 PVY1 PVY2 PVY3 PVY4 PPY1 PPY2 PPY3 PPY4 PPY5 RBY1 "
    "RBY2 RBY3 RBY4 RCY1 REY1 REY2 RHY1 RHY2 RVY1 RVY2 RVY3 RVY4 RVY5 RVY6 PTY1 PTY2",
    "ROLLING_COEFFICIENTS": "QSY1 QSY2 QSY3 QSY4 QSY5 QSY6 QSY7 QSY8",
    "ALIGNING_COEFFICIENTS": "QBZ1 QBZ2 QBZ3 QBZ4 QBZ5 QBZ6 QBZ9 QBZ10 QCZ1 QDZ1 QDZ2 QDZ3 "
    "QDZ4 QDZ6 QDZ7 QDZ8 QDZ9 QDZ10 QDZ11 QEZ1 QEZ2 QEZ3 QEZ4 QEZ5 QHZ1 QHZ2 QHZ3 QHZ4 PPZ1 "
    "PPZ2 SSZ1 SSZ2 SSZ3 SSZ4",
    "SCALING_COEFFICIENTS": "LFZO LCX LMUX LEX LKX LHX LVX LCY LMUY LEY LKY LKYC LKZC LHY LVY "
    "LTR LRES LXAL LYKA LVYKA LS LMX LVMX LMY LMP LMUV LGAX LGAY LGAZ LSGKP LSGAL LGYR",
}
REQUIRED_FITTED = ("PCX1 PDX1 PDX2 PEX1 PKX1 PKX2 PKX3 PCY1 PDY1 PDY2 PEY1 PKY1 PKY2 QBZ1 "
                   "QCZ1 QDZ1 QEZ1 RBX1 RBX2 RCX1 RBY1 RBY2 RCY1").split()


# -- an independent .tir reader --------------------------------------------------------------
def parse_tir(text: str) -> tuple[dict[str, dict[str, object]], list[str]]:
    """Sections -> {KEY: float or str}, and the '!' comment lines."""
    sections: dict[str, dict[str, object]] = {}
    comments: list[str] = []
    current = None
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line.startswith("$"):
            continue
        if line.startswith("!"):
            comments.append(line[1:].strip())
            continue
        m = re.fullmatch(r"\[(\w+)\]", line)
        if m:
            current = sections.setdefault(m[1], {})
            continue
        key, _, rest = line.partition("=")
        value = rest.split("$", 1)[0].strip()
        assert current is not None and key.strip(), f"data line outside a section: {raw!r}"
        current[key.strip()] = value.strip("'") if value.startswith("'") else float(value)
    return sections, comments


# -- an independent Magic Formula 6.1 (nominal pressure, all lambda = 1) ---------------------
def mf_point(c: dict[str, float], kappa: float, alpha: float, Fz: float,
             gamma: float = 0.0) -> tuple:
    """(Fx, Fy, Mz) in ISO-W at one point, Pacejka 2012 eqs. (4.E1)-(4.E78) (MF-Tyre form of
    the equivalent slip angles; alpha used as is, not tan(alpha)). Camber acts on Fy through
    eqs. (4.E4), (4.E27)-(4.E30) (camber stiffness PKY6, PKY7 and shift PVY3, PVY4; the other
    camber coefficients are 0 in the file); Mz takes Fy0 at gamma = 0 (MF-Tyre 6.1 form)."""
    g = lambda k: c.get(k, 0.0)  # noqa: E731 (local shorthand)
    Fz0, R0 = c["FNOMIN"], c["UNLOADED_RADIUS"]
    dz = Fz / Fz0 - 1.0

    def magic(B, C, D, E, x):
        return D * math.sin(C * math.atan(B * x - E * (B * x - math.atan(B * x))))

    # pure longitudinal
    kx = kappa + g("PHX1") + g("PHX2") * dz
    Ex = min(1.0, (g("PEX1") + g("PEX2") * dz + g("PEX3") * dz * dz)
             * (1.0 - g("PEX4") * (kx > 0) + g("PEX4") * (kx < 0)))
    Kx = Fz * (g("PKX1") + g("PKX2") * dz) * math.exp(g("PKX3") * dz)
    Dx = (g("PDX1") + g("PDX2") * dz) * Fz
    Fx0 = magic(Kx / (g("PCX1") * Dx), g("PCX1"), Dx, Ex, kx) + Fz * (g("PVX1")
                                                                      + g("PVX2") * dz)
    # pure lateral
    Ky = g("PKY1") * Fz0 * math.sin(c.get("PKY4", 2.0) * math.atan(Fz / (g("PKY2") * Fz0)))
    ay = alpha + g("PHY1") + g("PHY2") * dz
    Svy = Fz * (g("PVY1") + g("PVY2") * dz)
    Dy = (g("PDY1") + g("PDY2") * dz) * Fz
    Ey = min(1.0, (g("PEY1") + g("PEY2") * dz) * (1.0 - g("PEY3") * np.sign(ay)))
    By, Cy = Ky / (g("PCY1") * Dy), g("PCY1")
    Fy0 = magic(By, Cy, Dy, Ey, ay) + Svy
    gs = math.sin(gamma)
    Kyg = Fz * (g("PKY6") + g("PKY7") * dz)
    Svyg = Fz * (g("PVY3") + g("PVY4") * dz) * gs
    ayg = ay + (Kyg * gs - Svyg) / Ky
    Eyg = min(1.0, (g("PEY1") + g("PEY2") * dz) * (1.0 - g("PEY3") * np.sign(ayg)))
    Fy0g = magic(By, Cy, Dy, Eyg, ayg) + Svy + Svyg
    # combined weights
    Bxa = g("RBX1") * math.cos(math.atan(g("RBX2") * kappa))
    Exa = min(1.0, g("REX1") + g("REX2") * dz)

    def G(B, C, E, x):
        return math.cos(C * math.atan(B * x - E * (B * x - math.atan(B * x))))

    Gxa = G(Bxa, g("RCX1"), Exa, alpha + g("RHX1")) / G(Bxa, g("RCX1"), Exa, g("RHX1"))
    Byk = g("RBY1") * math.cos(math.atan(g("RBY2") * (alpha - g("RBY3"))))
    Eyk = min(1.0, g("REY1") + g("REY2") * dz)
    Shyk = g("RHY1") + g("RHY2") * dz
    Gyk = G(Byk, g("RCY1"), Eyk, kappa + Shyk) / G(Byk, g("RCY1"), Eyk, Shyk)
    Fx, Fy = Gxa * Fx0, Gyk * Fy0g
    # aligning moment: trail at the equivalent slip angle, residual moment, Fx arm
    at = alpha + g("QHZ1") + g("QHZ2") * dz
    ar = alpha + g("PHY1") + g("PHY2") * dz + Svy / Ky
    r2 = (Kx / Ky * kappa) ** 2
    at_eq = math.copysign(math.atan(math.sqrt(math.tan(at) ** 2 + r2)), at) if at else 0.0
    ar_eq = math.copysign(math.atan(math.sqrt(math.tan(ar) ** 2 + r2)), ar) if ar else 0.0
    Bt = g("QBZ1") + g("QBZ2") * dz + g("QBZ3") * dz * dz
    Ct = g("QCZ1")
    Dt = Fz * R0 / Fz0 * (g("QDZ1") + g("QDZ2") * dz)
    Et = min(1.0, (g("QEZ1") + g("QEZ2") * dz + g("QEZ3") * dz * dz)
             * (1.0 + g("QEZ4") * 2.0 / math.pi * math.atan(Bt * Ct * at_eq)))
    t = Dt * math.cos(Ct * math.atan(Bt * at_eq - Et * (Bt * at_eq - math.atan(Bt * at_eq))))
    t *= math.cos(alpha)
    Dr = Fz * R0 * (g("QDZ6") + g("QDZ7") * dz) * math.cos(alpha)
    Br = g("QBZ9") + g("QBZ10") * By * Cy
    Mzr = Dr * math.cos(math.atan(Br * ar_eq)) * math.cos(alpha)
    s = R0 * (g("SSZ1") + g("SSZ2") * Fy / Fz0)
    return Fx, Fy, -t * Gyk * Fy0 + Mzr + s * Fx


def mx_point(c: dict[str, float], Fy: float, Fz: float, gamma: float = 0.0) -> float:
    """Overturning moment, ISO-W, Pacejka 2012 eq. (4.E69) with QSX4.. = 0."""
    return c["UNLOADED_RADIUS"] * Fz * (c["QSX1"] - c["QSX2"] * gamma
                                        + c["QSX3"] * Fy / c["FNOMIN"])


def my_point(c: dict[str, float], Fz: float, Vx: float, v_ref: float) -> float:
    """Rolling-resistance moment at Fx = 0, gamma = 0, nominal pressure, ISO-W (negative
    rolling forward), Pacejka 2012 eq. (4.E70) with the MF-Tyre sign."""
    v = Vx / v_ref
    return -c["UNLOADED_RADIUS"] * Fz * (c["QSY1"] + c["QSY3"] * abs(v) + c["QSY4"] * v**4) \
        * (Fz / c["FNOMIN"]) ** c["QSY7"]


def mf_points(c: dict[str, float], kappa, alpha, Fz) -> np.ndarray:
    return np.array([mf_point(c, k, a, f) for k, a, f in zip(kappa, alpha, Fz, strict=True)])


def coefficients(sections: dict) -> dict[str, float]:
    out = {"FNOMIN": sections["VERTICAL"]["FNOMIN"],
           "UNLOADED_RADIUS": sections["DIMENSION"]["UNLOADED_RADIUS"]}
    for name in ("LONGITUDINAL_COEFFICIENTS", "LATERAL_COEFFICIENTS", "ALIGNING_COEFFICIENTS",
                 "OVERTURNING_COEFFICIENTS", "ROLLING_COEFFICIENTS"):
        out.update(sections[name])
    return out


def errors(points: dict, mf: np.ndarray) -> dict[str, dict[str, float]]:
    """RMS and max of |MF - brush| / Fz per channel (pure channels on the pure sweeps)."""
    out = {}
    for ch in CHANNELS:
        q, kind = ch.split("_")
        col = ("Fx", "Fy", "Mz").index(q)
        sel = points["kind"] == ("combined" if kind == "combined" else
                                 "kappa" if q == "Fx" else "alpha")
        rel = np.abs(mf[sel, col] - points[q][sel]) / points["Fz"][sel]
        out[ch] = {"rms": float(np.sqrt(np.mean(rel**2))), "max": float(rel.max())}
    return out


# -- the fit, run once ------------------------------------------------------------------------
def _run(argv: list[str]) -> tuple[int, str, float]:
    buf = io.StringIO()
    t0 = time.perf_counter()
    with contextlib.redirect_stdout(buf):
        rc = main(argv)
    return rc, buf.getvalue(), time.perf_counter() - t0


@pytest.fixture(scope="module")
def fit(tmp_path_factory) -> dict:
    d = tmp_path_factory.mktemp("mf")
    tir, pts = d / "passenger.tir", d / "points.csv"
    rc, out, seconds = _run(["tire", "fit-mf", "--T", str(T_C), "--vx", str(VX), "-o",
                             str(tir), "--points", str(pts), "--json"])
    assert rc == 0
    result = json.loads(out)
    sections, comments = parse_tir(tir.read_text())
    rows = list(csv.reader(pts.read_text().splitlines()[1:]))
    head, body = rows[0], rows[1:]
    points = {h: np.array([r[i] for r in body]) for i, h in enumerate(head)}
    for h in head[1:]:
        points[h] = points[h].astype(float)
    # the brush recomputed here at the fit points (adapted SAE -> ISO-W by hand: same slip
    # angle, Fy and Mz flipped)
    model = SteadyBrush(load_tire("passenger"), load_friction("default"))
    b = model.solve(points["kappa"], points["alpha_rad"], VX, points["Fz_N"], T_C + 273.15)
    brush = {"kind": points["kind"], "Fz": points["Fz_N"], "Fx": np.asarray(b.Fx),
             "Fy": -np.asarray(b.Fy), "Mz": -np.asarray(b.Mz), "Mx": np.asarray(b.Mx)}
    # the camber check points of the report, recomputed here (Mx keeps its sign in ISO-W)
    cp = result["camber"]["points"]
    a, g, F = (np.array(cp[k]) for k in ("alpha_rad", "gamma_rad", "Fz_N"))
    bc = model.solve(0.0, a, VX, F, T_C + 273.15, gamma=g)
    camber = {"alpha": a, "gamma": g, "Fz": F, "Fy": -np.asarray(bc.Fy),
              "Mz": -np.asarray(bc.Mz), "Mx": np.asarray(bc.Mx)}
    return {"result": result, "sections": sections, "comments": comments, "tir": tir,
            "points": points, "brush": brush, "camber": camber, "model": model,
            "seconds": seconds, "dir": d}


def test_fit_is_fast(fit) -> None:
    assert fit["seconds"] < 120.0, f"the default fit took {fit['seconds']:.0f} s (limit 2 min)"


def test_file_layout_units_and_model(fit) -> None:
    s = fit["sections"]
    assert s["MDI_HEADER"] == {"FILE_TYPE": "tir", "FILE_VERSION": 3.0, "FILE_FORMAT": "ASCII"}
    assert s["UNITS"] == {"LENGTH": "meter", "FORCE": "newton", "ANGLE": "radian",
                          "MASS": "kg", "TIME": "second"}
    assert s["MODEL"]["FITTYP"] == 61.0 and s["MODEL"]["USE_MODE"] == 4.0
    assert s["MODEL"]["LONGVL"] == VX
    dim = s["DIMENSION"]
    assert (dim["WIDTH"], dim["ASPECT_RATIO"]) == (0.205, 0.55), "205/55 R16"
    assert dim["RIM_RADIUS"] == pytest.approx(16 * 0.0254 / 2, rel=1e-12)
    assert dim["UNLOADED_RADIUS"] == pytest.approx(
        dim["RIM_RADIUS"] + dim["ASPECT_RATIO"] * dim["WIDTH"], abs=1e-3), \
        "R0 = rim radius + section height (the tire file's provenance)"
    tire = load_tire("passenger")
    assert s["VERTICAL"] == {"FNOMIN": tire.Fz_nom, "VERTICAL_STIFFNESS": tire.patch.C_z}
    op = s["OPERATING_CONDITIONS"]
    assert op["INFLPRES"] == op["NOMPRES"] == 2.3e5, "'~2.3 bar' in the tire's description"
    assert s["INCLINATION_ANGLE_RANGE"] == {"CAMMIN": -0.1, "CAMMAX": 0.1}, "checked range"
    assert s["VERTICAL_FORCE_RANGE"] == {"FZMIN": 2000.0, "FZMAX": 6000.0}
    for key, value in s["SCALING_COEFFICIENTS"].items():
        assert value == (0.0 if key == "LMUV" else 1.0), key


def test_key_names_and_fitted_coefficients(fit) -> None:
    s = fit["sections"]
    for section, names in KNOWN.items():
        unknown = set(s[section]) - set(names.split())
        assert not unknown, f"[{section}] has keys MF readers do not know: {unknown}"
    keys = set(coefficients(s))
    assert set(REQUIRED_FITTED) <= keys
    assert set(REQUIRED_FITTED) <= set(fit["result"]["fitted"])


def test_round_trip_exact(fit) -> None:
    c = coefficients(fit["sections"])
    for k, v in fit["result"]["coefficients"].items():
        assert c[k] == v, f"{k}: file {c[k]!r} against fit {v!r}"
    for k, v in c.items():
        if k not in fit["result"]["coefficients"]:
            assert v == (2.0 if k == "PKY4" else 0.0), f"{k} is not fitted and must be 0"


def test_provenance_comments(fit) -> None:
    text = "\n".join(fit["comments"])
    grid_hash = load_friction("default").describe()["grid"]["hash"]
    for needle in (f"tirefric {__version__}", grid_hash, f"T = {T_C:g} C", "summer",
                   "asphalt", "passenger", "ISO-W", f"vx = {VX:g} m/s"):
        assert needle in text, f"provenance lacks {needle!r}"


def test_iso_signs(fit) -> None:
    """ISO-W: cornering stiffness negative, positive slip angle gives Fy < 0 and Mz > 0."""
    c = coefficients(fit["sections"])
    assert c["PKY1"] < 0, "ISO-W: PKY1 < 0"
    assert c["PDX1"] > 0 and c["PDY1"] > 0 and c["PKX1"] > 0 and c["QDZ1"] > 0
    Fx, Fy, Mz = mf_point(c, 0.0, math.radians(3), c["FNOMIN"])
    assert Fy < 0 and Mz > 0 and Fx == 0.0
    assert mf_point(c, -0.05, 0.0, c["FNOMIN"])[0] < 0, "braking gives Fx < 0"


def test_csv_brush_is_the_brush(fit) -> None:
    p, b = fit["points"], fit["brush"]
    for q, col in (("Fx", "Fx_brush_N"), ("Fy", "Fy_brush_N"), ("Mz", "Mz_brush_Nm")):
        np.testing.assert_allclose(p[col], b[q], rtol=1e-12, atol=1e-9,
                                   err_msg=f"{q}: --points brush column against the brush")


def test_file_reproduces_brush_within_reported_error(fit) -> None:
    """The file, evaluated here, matches the brush as well as the fitter says, channel by
    channel; and the fit is good where the MF form can follow the brush."""
    c = coefficients(fit["sections"])
    b = fit["brush"]
    got = errors(b, mf_points(c, fit["points"]["kappa"], fit["points"]["alpha_rad"], b["Fz"]))
    rep = fit["result"]["errors"]
    for ch in CHANNELS:
        assert got[ch]["rms"] == pytest.approx(rep[ch]["rms"], rel=1e-9), ch
        assert got[ch]["max"] == pytest.approx(rep[ch]["max"], rel=1e-9), ch
    # measured (passenger, default grid, 20 C, 20 m/s): forces 2.5-4 % rms of Fz (max 9 %
    # pure, 22 % combined Fy: the twisted belt's combined slip is beyond the MF weighting
    # functions), pure Mz 1.2 mm; the bounds leave room for grid or solver changes, not for a
    # broken fit
    for ch in ("Fx_pure", "Fy_pure", "Fx_combined", "Fy_combined"):
        assert rep[ch]["rms"] < 0.05 and rep[ch]["max"] < (0.3 if "comb" in ch else 0.12), ch
    assert rep["Mz_pure"]["rms"] < 2e-3 and rep["Mz_combined"]["rms"] < 5e-3


@pytest.mark.parametrize("mutation", ["PKY1 sign", "no load dependence", "FNOMIN doubled"])
def test_wrong_physics_fails(fit, mutation) -> None:
    """The comparison above catches a wrong sign of the cornering stiffness or a wrong load
    dependence: each mutation of the file makes the error several times the reported one.
    Without the load terms (x and y) the pure lateral channel's rms error doubles (measured
    2.1x); the pure longitudinal one rises only 1.5x (its peak friction hardly changes with
    load on the default grid: 1.076 / 1.053 / 1.049 at 2 / 4 / 6 kN)."""
    c = coefficients(fit["sections"])
    if mutation == "PKY1 sign":
        c["PKY1"] = -c["PKY1"]
        channel = "Fy_pure"
    elif mutation == "no load dependence":
        for k in ("PDX2", "PEX2", "PEX3", "PKX2", "PKX3", "PDY2", "PEY2"):
            c[k] = 0.0
        channel = "Fy_pure"
    else:
        c["FNOMIN"] *= 2.0
        channel = "Fy_pure"
    b = fit["brush"]
    got = errors(b, mf_points(c, fit["points"]["kappa"], fit["points"]["alpha_rad"], b["Fz"]))
    assert got[channel]["rms"] > 2.0 * fit["result"]["errors"][channel]["rms"], mutation


def test_load_dependence_report(fit) -> None:
    """The reported MF slip stiffnesses are the file's (independent evaluation), the brush's
    are its slope at small slip, and the brush's peak friction is that of its sweeps."""
    c = coefficients(fit["sections"])
    model = SteadyBrush(load_tire("passenger"), load_friction("default"))
    h, e = 1e-3, 1e-6      # the report's step for the brush; a finer one for the MF slope
    for row in fit["result"]["load_dependence"]:
        F = row["Fz_N"]
        Ky = (mf_point(c, 0.0, e, F)[1] - mf_point(c, 0.0, -e, F)[1]) / (2 * e)
        assert -Ky / F == pytest.approx(row["C_Falpha_per_Fz_mf"], rel=1e-6)
        Kx = (mf_point(c, e, 0.0, F)[0] - mf_point(c, -e, 0.0, F)[0]) / (2 * e)
        assert Kx / F == pytest.approx(row["C_Fkappa_per_Fz_mf"], rel=1e-6)
        out = model.solve(0.0, np.array([h, -h]), VX, F, T_C + 273.15)
        assert (out.Fy[0] - out.Fy[1]) / (2 * h) / F == pytest.approx(
            row["C_Falpha_per_Fz_brush"], rel=1e-9), "dFy/dalpha of the brush (adapted SAE)"


def test_brush_symmetries_behind_the_zero_shifts() -> None:
    """Why PHY, PVY, QHZ, RHX1, RBY3, PEY3, QEZ4, RVY, QDZ6/7 and SSZ1 are 0: the brush is odd
    in the slip angle, Fx is even in it, and zero slip gives no force (to round-off)."""
    model = SteadyBrush(load_tire("passenger"), load_friction("default"))
    a = np.radians([1.0, 4.0, 9.0])
    for k in (0.0, -0.1, 0.2):
        p, m = (model.solve(k, s * a, VX, 4000.0, 293.15) for s in (1, -1))
        np.testing.assert_allclose(m.Fy, -p.Fy, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(m.Mz, -p.Mz, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(m.Fx, p.Fx, rtol=1e-9, atol=1e-9)
    z = model.solve(np.array([0.0, 0.1]), 0.0, VX, 4000.0, 293.15)
    assert z.Fx[0] == 0.0 and (z.Fy == 0).all() and (z.Mz == 0).all()


def test_constant_friction_fit_recovers_mu_and_brush_stiffness(tmp_path, capsys) -> None:
    """With flat friction mu = 1 the brush saturates at mu Fz (Pacejka 2012 sec. 3.2), so the
    MF's friction coefficients are 1 (5 %: the MF's D is a peak, the brush has none); its
    slip stiffness at the nominal load is the rigid-carcass closed form 2 k_x b a^2 within 10 %
    (the least-squares fit trades the slope at zero slip for the whole curve)."""
    out = tmp_path / "c.tir"
    assert main(["tire", "fit-mf", "--T", "20", "--vx", "20", "--grid", "constant:1.0",
                 "-o", str(out), "--fittyp", "6", "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    s, _ = parse_tir(out.read_text())
    assert s["MODEL"]["FITTYP"] == 6.0 and s["MODEL"]["PROPERTY_FILE_FORMAT"] == "PAC2002"
    c = coefficients(s)
    assert c["PKY4"] == 2.0, "PAC2002 form of the cornering stiffness"
    assert c["PDX1"] == pytest.approx(1.0, abs=0.05) and c["PDY1"] == pytest.approx(1.0, abs=0.05)
    tire = load_tire("passenger")
    C_kappa, _ = tire.slip_stiffness(tire.Fz_nom)
    assert c["PKX1"] * tire.Fz_nom == pytest.approx(C_kappa, rel=0.10)
    assert res["friction"]["kind"] == "constant"
    # no compound behind constant friction: no rolling-resistance fit, and said why; PAC2002
    # readers do not evaluate PKY6, PKY7: no camber range
    assert res["rolling"]["fitted"] == [] and "compound" in res["rolling"]["why"]
    assert all(c[k] == 0.0 for k in ("QSY1", "QSY3", "QSY7"))
    assert s["INCLINATION_ANGLE_RANGE"] == {"CAMMIN": 0.0, "CAMMAX": 0.0}


@pytest.mark.parametrize("args,match", [
    (["--loads", "1"], "two different loads"),
    (["--loads", "0.5,1,3"], "Fz_max"),
    (["--vx", "0"], "vx"),
    (["--size", "big"], "size"),
    (["--T", "400"], "kelvin"),
])
def test_input_errors(tmp_path, capsys, args, match) -> None:
    argv = ["tire", "fit-mf", "--T", "20", "--vx", "20", "-o", str(tmp_path / "x.tir"), *args]
    assert main(argv) == 2, "argparse keeps the last of a repeated option"
    assert match in capsys.readouterr().err
    assert not (tmp_path / "x.tir").exists()


def test_points_in_sae(fit, tmp_path) -> None:
    """--axes sae: Fz negative, the slip angle and Fy, Mz flipped against ISO-W, Fx kept."""
    pts = tmp_path / "sae.csv"
    rc, _, _ = _run(["tire", "fit-mf", "--T", str(T_C), "--vx", str(VX), "-o",
                     str(tmp_path / "s.tir"), "--points", str(pts), "--axes", "sae",
                     "--grid", "constant:1.0", "--loads", "1,1.2"])
    assert rc == 0
    rows = list(csv.reader(pts.read_text().splitlines()))
    assert rows[0] == ["# axes: sae"]
    head = rows[1]
    data = np.array([[float(x) for x in r[1:]] for r in rows[2:]])
    col = {h: i - 1 for i, h in enumerate(head)}
    assert (data[:, col["Fz_N"]] < 0).all(), "SAE: Fz negative under load"
    a = data[:, col["alpha_rad"]]
    side = np.array([r[0] == "alpha" for r in rows[2:]])
    small = side & (a > 0.01) & (a < 0.1)          # below the Mz sign reversal
    assert small.sum() >= 4
    assert (data[small, col["Fy_brush_N"]] < 0).all(), "SAE: alpha > 0 gives Fy < 0"
    assert (data[small, col["Mz_brush_Nm"]] > 0).all(), "SAE: alpha > 0 gives Mz > 0"
    assert (data[small, col["Fy_mf_N"]] < 0).all(), "the MF in SAE too"


# -- camber, overturning moment, rolling resistance --------------------------------------------
def camber_errors(c: dict[str, float], cam: dict) -> dict[str, dict[str, float]]:
    """|MF - brush| / Fz of Fy over the camber grid, of its camber part Fy(a, g) - Fy(a, 0),
    and the brush's own camber part of Mz (the file's Mz has none)."""
    a, g, F = cam["alpha"], cam["gamma"], cam["Fz"]
    mf = np.array([mf_point(c, 0.0, x, f, y) for x, f, y in zip(a, F, g, strict=True)])
    i0 = np.array([np.flatnonzero((a == x) & (F == f) & (g == 0.0))[0]
                   for x, f in zip(a, F, strict=True)])

    def stats(x):
        return {"rms": float(np.sqrt(np.mean(x**2))), "max": float(np.abs(x).max())}

    return {"Fy": stats((mf[:, 1] - cam["Fy"]) / F),
            "Fy_camber_part": stats(((mf[:, 1] - mf[i0, 1]) - (cam["Fy"] - cam["Fy"][i0])) / F),
            "Mz_camber_part_brush": stats((cam["Mz"] - cam["Mz"][i0]) / F)}


def test_camber_stiffness_per_load(fit) -> None:
    """The file's camber stiffness (its Fy slope in sin(gamma) at zero slip, evaluated here)
    is the brush's at every fit load within the reported largest error; that error is small
    because the brush's K_yg / Fz is nearly linear in the load, as PKY6 + PKY7 dfz is
    (measured: 0.16 %)."""
    c = coefficients(fit["sections"])
    cam = fit["result"]["camber"]
    tol = cam["stiffness_rel_error_max"]
    assert tol < 0.01
    assert {"PKY6", "PKY7"} <= set(fit["result"]["fitted"])
    assert c["PVY3"] == c["PVY4"] == 0.0, "camber acts through S_Hy only"
    h, e = 0.01, 1e-6   # the report's step for the brush; a finer one for the MF slope
    for row in cam["loads"]:
        F = row["Fz_N"]
        K_mf = (mf_point(c, 0.0, 0.0, F, e)[1] - mf_point(c, 0.0, 0.0, F, -e)[1]) / (2 * e)
        b = fit["model"].solve(0.0, 0.0, VX, F, T_C + 273.15, gamma=np.array([h, -h]))
        K_b = -(b.Fy[0] - b.Fy[1]) / (2 * math.sin(h))          # adapted SAE -> ISO-W
        assert K_b / F == pytest.approx(row["K_ygamma_per_Fz_brush"], rel=1e-9)
        assert K_mf / F == pytest.approx(row["K_ygamma_per_Fz_mf"], rel=1e-6)
        assert abs(K_mf - K_b) <= (tol + 1e-6) * abs(K_b), f"camber stiffness at {F:g} N"


def test_camber_sign_iso_w(fit) -> None:
    """ISO-W: gamma > 0 leans the wheel's top to the right (-y); the camber thrust points to
    the lean side, Fy < 0, so PKY6 < 0 -- in the file, in the MF and in the brush."""
    c = coefficients(fit["sections"])
    assert c["PKY6"] < 0 and c["PKY6"] + c["PKY7"] * (-0.5) < 0 and \
        c["PKY6"] + c["PKY7"] * 0.5 < 0, "K_yg0 < 0 over the fitted loads"
    F = c["FNOMIN"]
    assert mf_point(c, 0.0, 0.0, F, 0.05)[1] < 0 < mf_point(c, 0.0, 0.0, F, -0.05)[1]
    b = fit["model"].solve(0.0, 0.0, VX, F, T_C + 273.15, gamma=0.05)
    assert -b.Fy < 0, "the brush (adapted SAE Fy = -ISO-W Fy) agrees"
    assert mf_point(c, 0.0, 0.0, F, 0.0) == (0.0, 0.0, 0.0)


def test_camber_range_within_reported_error(fit) -> None:
    """Over |gamma| <= CAMMAX at the check slip angles the file matches the brush as the fitter
    reports. The camber part is exact in slope at zero slip; off it the MF turns camber into a
    slip-angle shift K_yg0 gamma / K_ya on its own Fy curve, whose cornering stiffness is up to
    16 % off the brush's (docs/mf-fit.md), so the camber part is off by about that share
    (measured 2.5 % of Fz RMS, 9 % max at 6 kN, 2 deg); the brush's camber Mz, which the file
    leaves out (QDZ8.. = 0), is below a millimetre of arm (measured 0.7 mm RMS, 4.5 mm max)."""
    c = coefficients(fit["sections"])
    got = camber_errors(c, fit["camber"])
    rep = fit["result"]["camber"]["errors"]
    for ch in got:
        assert got[ch]["rms"] == pytest.approx(rep[ch]["rms"], rel=1e-9), ch
        assert got[ch]["max"] == pytest.approx(rep[ch]["max"], rel=1e-9), ch
    assert np.abs(fit["camber"]["gamma"]).max() == fit["sections"][
        "INCLINATION_ANGLE_RANGE"]["CAMMAX"]
    assert rep["Fy_camber_part"]["rms"] < 0.04 and rep["Fy_camber_part"]["max"] < 0.15
    assert rep["Fy"]["rms"] < 0.05 and rep["Fy"]["max"] < 0.2
    assert rep["Mz_camber_part_brush"]["rms"] < 2e-3


@pytest.mark.parametrize("mutation", ["PKY6 sign", "PKY7 dropped"])
def test_wrong_camber_fails(fit, mutation) -> None:
    """A flipped camber thrust or a camber stiffness without its load dependence is caught:
    the stiffness error goes far past the reported one, and for the flipped sign the camber
    part of the Fy error grows several-fold. (Dropping PKY7 does not raise the latter: off
    zero slip the MF's low cornering stiffness at high load already overstates the camber
    part there, docs/mf-fit.md; the stiffness at each load catches it.)"""
    c = coefficients(fit["sections"])
    if mutation == "PKY6 sign":
        c["PKY6"] = -c["PKY6"]
    else:
        c["PKY7"] = 0.0
    got = camber_errors(c, fit["camber"])
    rep = fit["result"]["camber"]
    if mutation == "PKY6 sign":
        assert got["Fy_camber_part"]["rms"] > 2.0 * rep["errors"]["Fy_camber_part"]["rms"]
    e = 1e-6
    worst = max(abs((mf_point(c, 0.0, 0.0, r["Fz_N"], e)[1]
                     - mf_point(c, 0.0, 0.0, r["Fz_N"], -e)[1]) / (2 * e) / r["Fz_N"]
                    - r["K_ygamma_per_Fz_brush"]) / abs(r["K_ygamma_per_Fz_brush"])
                for r in rep["loads"])
    assert worst > 10.0 * rep["stiffness_rel_error_max"], mutation


def test_overturning_qsx3_exact(fit) -> None:
    """QSX3 = Fz0 / (R0 k_y): the file's Mx (eq. (4.E69)) is the brush's Mx = Fy Fz / k_y
    (ISO-W) to round-off, at the slip points and over the camber range."""
    c = coefficients(fit["sections"])
    tire = load_tire("passenger")
    assert c["QSX3"] == pytest.approx(tire.Fz_nom / (tire.patch.R0 * tire.carcass.k_y),
                                      rel=1e-15)
    assert c["QSX3"] > 0 and c["QSX1"] == c["QSX2"] == 0.0
    for pts in (fit["brush"], fit["camber"]):
        g = pts.get("gamma", np.zeros_like(pts["Fz"]))
        mx = np.array([mx_point(c, y, f, a) for y, f, a in zip(pts["Fy"], pts["Fz"], g,
                                                                 strict=True)])
        np.testing.assert_allclose(mx, pts["Mx"], rtol=1e-12, atol=1e-12 * np.abs(
            pts["Mx"]).max())
    assert np.abs(fit["camber"]["Mx"]).max() > 100.0, "a real check (Mx up to ~270 N m)"


def test_rolling_resistance_within_reported_error(fit) -> None:
    """QSY1, QSY3, QSY7 against tire_brush.rolling_resistance at the fit temperature (the
    grid's compound): the file's My (eq. (4.E70)) matches My = -f_r Fz R_e as reported; the
    error is the MF's linear speed law and separable load power against the model's curves
    (measured 0.019 % of R0 Fz RMS, 2.7 % of My at most; docs/mf-fit.md). The speed term
    QSY3 has the sign of the model's own trend over the fitted speeds: at 20 C the summer
    tread's footprint loss, its compliance in series with the belt's, rises with the
    frequency (4.46 -> 5.09 N/kN from 5 to 40 m/s at 4 kN), and the sidewalls', belt's and
    tread band's losses with it (6.11 -> 6.64), so f_r rises slightly with the speed
    (QSY3 > 0; before the belt term it fell)."""
    from lookup.compound import load_compound
    from tire_brush.rolling_resistance import rolling_resistance

    c = coefficients(fit["sections"])
    rr = fit["result"]["rolling"]
    assert rr["fitted"] == ["QSY1", "QSY3", "QSY7"] and rr["compound"] == "summer"
    assert c["QSY1"] > 0, "ISO-W: My < 0 rolling forward"
    V, F = (x.ravel() for x in np.meshgrid(rr["speeds_m_s"], rr["loads_N"]))
    model = rolling_resistance(load_tire("passenger"), load_compound("summer"), V, F,
                               T_C + 273.15)
    assert (model.My < 0).all()
    # the least-squares speed slope of the model's f_r, all loads pooled: QSY3's sign
    slope = np.polyfit(V, model.f_r, 1)[0]
    assert np.sign(c["QSY3"]) == np.sign(slope), (c["QSY3"], slope)
    v_ref = fit["sections"]["MODEL"]["LONGVL"]
    my = np.array([my_point(c, f, v, v_ref) for f, v in zip(F, V, strict=True)])
    rel = np.abs(my - model.My) / (c["UNLOADED_RADIUS"] * F)
    assert float(np.sqrt(np.mean(rel**2))) == pytest.approx(rr["errors"]["rms"], rel=1e-9)
    assert float(rel.max()) == pytest.approx(rr["errors"]["max"], rel=1e-9)
    assert rr["errors"]["rms"] < 1e-3 and rr["errors"]["rel_max"] < 0.25
    c["QSY7"] += 0.083       # mutation: the load power of the model before the belt term
    my0 = np.array([my_point(c, f, v, v_ref) for f, v in zip(F, V, strict=True)])
    rel0 = np.abs(my0 - model.My) / (c["UNLOADED_RADIUS"] * F)
    # QSY7 is fitted, not left at a default: the model's f_r falls slightly with the load
    # at 20 C (QSY7 = -0.045: the belt's bending and the tread's footprint, which grow more
    # slowly than the load, offset the sidewalls', which grow faster), and the load power 0.083
    # of the model before the belt term in its place raises the RMS error more than 1.3-fold
    assert float(np.sqrt(np.mean(rel0**2))) > 1.3 * rr["errors"]["rms"]
