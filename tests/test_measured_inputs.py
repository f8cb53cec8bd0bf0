"""Measured data as users have it: master curves, shift tables and strain sweeps in the common
layouts, the reference-temperature check, the extrapolation accounting and softening per
temperature.

The data are synthetic: a Prony series (a log-normal relaxation spectrum) and a Kraus-type
Payne law, written in each layout; each layout must load to the same numbers.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from conftest import T20, make_compound, make_surface

from lookup.adhesion import NoAdhesion
from lookup.compound import load_compound
from lookup.friction import OUTSIDE_WARNING_SHARE, EngineSettings, PerssonFriction
from lookup.modulus import Prony, TabulatedMasterCurve
from lookup.roughness import CutoffRule
from lookup.shift import WLF
from lookup.softening import KrausSoftening, StrainSweepSoftening, TabulatedSoftening
from tirefric.cli import main
from tirefric.errors import ExtrapolationWarning, InputError
from tirefric.paths import models_dir

# the shipped summer compound as text; its relative data paths (the softening table,
# data/filled_tread_softening.csv) made absolute, so that the copies written to tmp_path load
SUMMER = (models_dir() / "compounds" / "summer.toml").read_text().replace(
    'file = "data/', f'file = "{(models_dir() / "compounds" / "data").as_posix()}/')
REF = Prony.lognormal(5e6, 1e9, 1e-6, 2.0)  # the "measured" compound
W = np.logspace(-4, 12, 129)  # rad/s, 8 points per decade
ER, EI = REF.storage_loss(W)


def names_all(err: pytest.ExceptionInfo, *parts: str) -> None:
    text = str(err.value)
    for part in parts:
        assert part in text, f"error should name {part!r}: {text}"


def compound_file(tmp_path: Path, modulus: str = "", shift: str = "", softening: str = "",
                  name: str = "c.toml") -> Path:
    """The summer compound with some of its tables replaced (TOML text of the table)."""
    head, rest = SUMMER.split("[modulus]")
    mod, rest = ("[modulus]" + rest).split("[shift]")
    sh, rest = ("[shift]" + rest).split("[softening]")
    soft, rest = ("[softening]" + rest).split("[adhesion]")
    text = (head + (modulus or mod) + (shift or sh) + (softening or soft) + "[adhesion]" + rest)
    p = tmp_path / name
    p.write_text(text)
    return p


def tabulated(file: str, T_ref: str = "20 degC", extra: str = "") -> str:
    return f'[modulus]\nT_ref = "{T_ref}"\nmodel = "tabulated"\nfile = "{file}"\n{extra}\n'


def rows(*cols: np.ndarray, sep: str = ",") -> str:
    return "".join(sep.join(repr(float(c[i])) for c in cols) + "\n" for i in range(cols[0].size))


# -- master curves: every layout loads to the same curve -------------------------------------
F = W / (2 * np.pi)
MASTER_LAYOUTS = {
    "canonical": "omega [rad/s],E_storage [Pa],E_loss [Pa]\n" + rows(W, ER, EI),
    "commented header, white space, Hz, MPa":
        "# DMA master curve, tension, 0.1 % strain\n# f [Hz]  E' [MPa]  E'' [MPa]\n"
        + rows(F, ER / 1e6, EI / 1e6, sep="  "),
    "tab, parentheses, kPa": "freq (Hz)\tE' (kPa)\tE'' (kPa)\n"
                             + rows(F, ER / 1e3, EI / 1e3, sep="\t"),
    "semicolon, GPa, tan delta": "frequency [rad/s];E_storage [GPa];tan delta [1]\n"
                                 + rows(W, ER / 1e9, EI / ER, sep=";"),
    "commented comma header, aliases": "# source: synthetic\n"
                                       "# omega [rad/s], Eprime [MPa], Edoubleprime [MPa]\n"
                                       + rows(W, ER / 1e6, EI / 1e6, sep=", "),
    "white space, multi-word alias without unit": "f [Hz] E' [Pa] tan d\n"
                                                  + rows(F, ER, EI / ER, sep=" "),
}


@pytest.mark.parametrize("layout", list(MASTER_LAYOUTS))
def test_master_curve_layouts_load_to_the_same_curve(tmp_path: Path, layout: str) -> None:
    """Unit conversions (x 1e3, 1e6, 1e9, 2 pi) and tan delta x E' round at 1e-16: 1e-13."""
    (tmp_path / "mc.txt").write_text(MASTER_LAYOUTS[layout])
    c = load_compound(compound_file(tmp_path, tabulated("mc.txt")))
    for got, want in ((c.modulus.omega, W), (c.modulus.E_storage, ER), (c.modulus.E_loss, EI)):
        np.testing.assert_allclose(got, want, rtol=1e-13, err_msg=layout)
    assert c.modulus.measured_band == pytest.approx((W[0], W[-1]), rel=1e-13)


def test_missing_column_names_what_is_expected_and_found(tmp_path: Path) -> None:
    (tmp_path / "mc.txt").write_text("# f [Hz]  E' [MPa]\n" + rows(F, ER / 1e6, sep=" "))
    p = compound_file(tmp_path, tabulated("mc.txt"))
    with pytest.raises(InputError, match="missing column 'E_loss'") as err:
        load_compound(p)
    names_all(err, str(tmp_path / "mc.txt"), "E_loss (also E''", "tan_delta (also tan delta",
              "[Pa, kPa, MPa, GPa]", "omega (also f, freq, frequency", "[rad/s, Hz]",
              "commented header line 1, white-space-delimited", "['f [Hz]', \"E' [MPa]\"]")


def test_file_not_found_names_the_absolute_path_tried(tmp_path: Path) -> None:
    sub = tmp_path / "compounds"
    sub.mkdir()
    p = compound_file(sub, tabulated("../data/mc.txt"))
    with pytest.raises(InputError, match="file not found") as err:
        load_compound(p)
    names_all(err, str(p), "modulus.file", "../data/mc.txt",
              f"tried {(tmp_path / 'data' / 'mc.txt').resolve()}",
              f"relative to the folder of {p}")


@pytest.mark.parametrize("text,needle", [
    (rows(W, ER, EI), "no header line"),
    ("# f [Hz] E' [MPa]\n" + rows(F, ER / 1e6, EI / 1e6), "has 2 column(s)"),
    ("f [1/s],E' [MPa],E'' [MPa]\n" + rows(F, ER / 1e6, EI / 1e6), "ambiguous"),
    ("f [Hz],E' [MPa],E'' [MPa],E_loss [MPa]\n" + rows(F, ER / 1e6, EI / 1e6, EI / 1e6),
     "2 columns mean 'E_loss'"),
    ("f [Hz],E' [MPa],E'' [MPa],tan delta\n" + rows(F, ER / 1e6, EI / 1e6, EI / ER),
     "both a loss modulus and a tan delta"),
])
def test_bad_master_curve_tables_are_named(tmp_path: Path, text: str, needle: str) -> None:
    (tmp_path / "mc.txt").write_text(text)
    with pytest.raises(InputError) as err:
        load_compound(compound_file(tmp_path, tabulated("mc.txt")))
    names_all(err, needle, str(tmp_path / "mc.txt"))


# -- shift tables and the reference temperature --------------------------------------------------
TS = np.arange(-30.0, 81.0, 10.0)  # C


def wlf_at(T_C: np.ndarray, T_r_C: float, C1: float = 15.0, C2: float = 150.0) -> np.ndarray:
    """log10 a_T of review eq. (5) with reference T_r (own code, not lookup.shift)."""
    d = T_C - T_r_C
    return -C1 * d / (C2 + d)


def shift_table(tmp_path: Path, text: str, T_ref: str | None = None) -> str:
    (tmp_path / "aT.txt").write_text(text)
    line = "" if T_ref is None else f'T_ref = "{T_ref}"\n'
    return f'[shift]\nmodel = "tabulated"\nfile = "aT.txt"\n{line}\n'


SHIFT_LAYOUTS = {
    "log10, degC": "T [degC],log10_aT [1]\n" + rows(TS, wlf_at(TS, 20.0)),
    "plain factor, kelvin, commented white space": "# T [K]   aT\n"
                                                   + rows(TS + 273.15, 10 ** wlf_at(TS, 20.0),
                                                          sep="   "),
    "hot to cold, tab, parentheses": "Temperature (C)\ta_T\n"
                                     + rows(TS[::-1], 10 ** wlf_at(TS[::-1], 20.0), sep="\t"),
}


@pytest.mark.parametrize("layout", list(SHIFT_LAYOUTS))
def test_shift_table_layouts_agree(tmp_path: Path, layout: str) -> None:
    """Same a_T(T) from each layout (log10 of a plain factor and kelvin conversion: 1e-12)."""
    c = load_compound(compound_file(tmp_path, shift=shift_table(tmp_path, SHIFT_LAYOUTS[layout])))
    T = np.linspace(250.0, 350.0, 11)
    np.testing.assert_allclose(c.log10_aT(TS + 273.15), wlf_at(TS, 20.0), atol=1e-12,
                               err_msg=f"{layout}: the table's rows")
    (tmp_path / "ref").mkdir()
    ref = load_compound(compound_file(tmp_path / "ref", shift=shift_table(
        tmp_path / "ref", SHIFT_LAYOUTS["log10, degC"])))
    np.testing.assert_allclose(c.log10_aT(T), ref.log10_aT(T), atol=1e-12, err_msg=layout)
    assert c.shift.T_ref == pytest.approx(T20, abs=1e-9), "T_ref of the table: where aT = 1"


def test_wrong_reference_temperature_is_refused(tmp_path: Path) -> None:
    """The issue's case: the data's shift table has aT = 1 at 40 C, the TOML says 20 C."""
    table = "# T [degC]  aT\n" + rows(TS, 10 ** wlf_at(TS, 40.0), sep="  ")
    p = compound_file(tmp_path, shift=shift_table(tmp_path, table))
    with pytest.raises(InputError, match="is not where the shift factor is 1") as err:
        load_compound(p)
    names_all(err, str(p), "modulus.T_ref", "T_ref = 20 C", "40 C", str(tmp_path / "aT.txt"))
    ok = compound_file(tmp_path, tabulated_summer_T_ref("40 degC"),
                       shift_table(tmp_path, table), name="ok.toml")
    assert load_compound(ok).T_ref == pytest.approx(313.15)
    # a stated [shift] T_ref is checked against the table too
    bad = compound_file(tmp_path, tabulated_summer_T_ref("40 degC"),
                        shift_table(tmp_path, table, T_ref="30 degC"), name="bad.toml")
    with pytest.raises(InputError, match="shift factor is 1") as err:
        load_compound(bad)
    names_all(err, "shift.T_ref", "30 C", "40 C")


def tabulated_summer_T_ref(T_ref: str) -> str:
    """Summer's [modulus] table with another T_ref."""
    mod = "[modulus]" + SUMMER.split("[modulus]")[1].split("[shift]")[0]
    return mod.replace('T_ref = "20 degC"', f'T_ref = "{T_ref}"')


@pytest.mark.parametrize("T_one,accepted", [(20.3, True), (19.6, True), (20.7, False),
                                            (19.2, False)])
def test_reference_temperature_tolerance(tmp_path: Path, T_one: float, accepted: bool) -> None:
    """a_T = 1 within 0.5 K of the stated T_ref (lookup.shift.T_REF_TOLERANCE), interpolated
    linearly between table rows 10 K apart (T_one is not a row). Linear interpolation of the
    curved WLF law misplaces the crossing by up to (|f''| h^2 / 8) / |f'| = 0.17 K (f = log10
    a_T, |f''| = 2 C1 C2 / C2^3 = 1.3e-3 / K^2, |f'| = C1 / C2 = 0.1 / K, h = 10 K): 0.2 K;
    the cases lie 0.2 K or more from the tolerance's edge."""
    table = "T [degC],log10_aT [1]\n" + rows(TS, wlf_at(TS, T_one))
    p = compound_file(tmp_path, shift=shift_table(tmp_path, table))
    if accepted:
        assert load_compound(p).shift.unit_temperature() == pytest.approx(T_one + 273.15,
                                                                           abs=0.2)
    else:
        with pytest.raises(InputError, match=r"tolerance 0\.5 K"):
            load_compound(p)


def test_wlf_at_another_reference_is_refused_with_the_same_law_at_T_ref(tmp_path: Path) -> None:
    """WLF constants at T_r = 0 C with a master curve at 20 C: refused; the message gives
    the same law written at 20 C (C1' = C1 C2/(C2 + dT), C2' = C2 + dT, Ferry ch. 11), and
    those constants give the same shift relative to the master curve (algebra: 1e-12)."""
    wlf0 = '[shift]\nmodel = "wlf"\nC1 = 17.44\nC2 = 51.6\nT_ref = "0 degC"\n\n'
    p = compound_file(tmp_path, shift=wlf0)
    with pytest.raises(InputError, match="WLF law at the master curve's T_ref") as err:
        load_compound(p)
    C1 = 17.44 * 51.6 / (51.6 + 20.0)
    names_all(err, "modulus.T_ref", "0 C", "20 C", f"C1 = {C1:.6g}", "C2 = 71.6 K")
    moved = compound_file(tmp_path, shift=f'[shift]\nmodel = "wlf"\nC1 = {C1!r}\nC2 = 71.6\n'
                                           'T_ref = "20 degC"\n\n', name="moved.toml")
    c = load_compound(moved)
    T = np.linspace(263.15, 353.15, 10)
    own = WLF(17.44, 51.6, 273.15)
    np.testing.assert_allclose(c.log10_aT(T), own.log10_aT(T) - own.log10_aT(np.array(T20)),
                               atol=1e-12)


# -- strain sweeps -------------------------------------------------------------------------------
EPS = np.geomspace(1e-4, 0.25, 28)  # strain amplitudes [1]
SWEEP_T = {0.0: KrausSoftening(0.01, 0.6, 0.25, 1.5), 40.0: KrausSoftening(0.02, 0.5, 0.45, 1.2)}
SMALL = {0.0: (12e6, 1.8e6), 40.0: (6e6, 0.6e6)}  # small-strain E', E'' [Pa] per T


def sweep(T_C: float) -> tuple[np.ndarray, np.ndarray]:
    """Measured E', E'' of one sweep [Pa]."""
    law = SWEEP_T[T_C]
    f = np.array([law.factors(e) for e in EPS])
    return SMALL[T_C][0] * f[:, 0], SMALL[T_C][1] * f[:, 1]


def expected_ratios(T_C: float) -> tuple[np.ndarray, np.ndarray]:
    Ep, Epp = sweep(T_C)
    return Ep / Ep[0], Epp / Epp[0]


def sweep_table(layout: str) -> str:
    blocks = []
    for T_C in SWEEP_T:
        Ep, Epp = sweep(T_C)
        R, I_ = expected_ratios(T_C)
        T = np.full(EPS.size, T_C)
        if layout == "moduli":
            blocks.append(rows(T, np.ones(EPS.size), 100 * EPS, Ep / 1e6, Epp / 1e6))
        elif layout == "kelvin, tan delta":
            blocks.append(rows(T + 273.15, EPS, Ep, Epp / Ep, sep="  "))
        else:
            blocks.append(rows(T, 100 * EPS[::-1], R[::-1], I_[::-1], sep="\t"))
    head = {"moduli": "T [degC],f [Hz],strain [%],E' [MPa],E'' [MPa]\n",
            "kelvin, tan delta": "# 1 Hz, tension\n"
                                 "# T [K]  strain [1]  E_storage [Pa]  tan delta\n",
            "ratios": "T (C)\tstrain (%)\teta_R\teta_I\n"}[layout]
    return head + "".join(blocks)


def sweep_softening(tmp_path: Path, table: str, strain: str = "0.1", name: str = "s.toml"
                    ) -> Path:
    (tmp_path / f"{name}.csv").write_text(table)
    soft = (f'[softening]\nmodel = "strain_sweep"\nfile = "{name}.csv"\nstrain = {strain}\n\n')
    return compound_file(tmp_path, softening=soft, name=name)


@pytest.mark.parametrize("layout", ["moduli", "kelvin, tan delta", "ratios"])
def test_strain_sweep_layouts_load_to_the_same_softening(tmp_path: Path, layout: str) -> None:
    """Each layout gives the measured ratios to the smallest strain at every strain and
    temperature of the sweeps (1e-12: unit conversions and ratios round at 1e-16)."""
    c = load_compound(sweep_softening(tmp_path, sweep_table(layout)))
    s = c.softening
    assert isinstance(s, StrainSweepSoftening) and s.varies_with_T
    np.testing.assert_allclose(s.T, [273.15, 313.15], atol=1e-12)
    for k, T_C in enumerate(SWEEP_T):
        R, I_ = expected_ratios(T_C)
        np.testing.assert_allclose(s.strain[k], EPS, rtol=1e-12)
        np.testing.assert_allclose(s.eta_R[k], R, rtol=1e-12, err_msg=layout)
        np.testing.assert_allclose(s.eta_I[k], I_, rtol=1e-12, err_msg=layout)
    assert c.strain == 0.1


def test_strain_sweep_strain_unit_is_required(tmp_path: Path) -> None:
    table = sweep_table("moduli").replace("strain [%]", "strain")
    with pytest.raises(InputError, match="strain without a unit is ambiguous") as err:
        load_compound(sweep_softening(tmp_path, table))
    names_all(err, "field 'strain'", "'%'", "'1'")


def test_sweep_at_one_temperature_is_the_tabulated_softening(tmp_path: Path) -> None:
    """A sweep without temperature (or at one) reproduces today's tabulated softening: the
    same factors and the same friction, both branches (the same table: bit for bit)."""
    Ep, Epp = sweep(0.0)
    R, I_ = expected_ratios(0.0)
    (tmp_path / "eta.csv").write_text("strain [1],eta_R [1],eta_I [1]\n" + rows(EPS, R, I_))
    tab = compound_file(tmp_path, softening='[softening]\nmodel = "tabulated"\nfile = "eta.csv"'
                                             '\nstrain = 0.1\n\n', name="tab.toml")
    one = sweep_softening(tmp_path, "# strain [%]  E' [MPa]  E'' [MPa]\n"
                          + rows(100 * EPS, Ep / 1e6, Epp / 1e6, sep="  "), '"10 %"',
                          "one.toml")
    at0 = sweep_softening(tmp_path, "T [degC],strain [1],eta_R,eta_I\n"
                          + rows(np.zeros(EPS.size), EPS, R, I_), "0.1", "at0.toml")
    a, b, c = load_compound(tab), load_compound(one), load_compound(at0)
    assert isinstance(a.softening, TabulatedSoftening) and not b.softening_varies_with_T
    for other in (b, c):
        assert not other.softening_varies_with_T
        for eps in (1e-5, 3e-4, 0.01, 0.1, 0.3):
            np.testing.assert_allclose(other.softening.factors(eps), a.softening.factors(eps),
                                       rtol=1e-12)
    s = make_surface()
    v, p = np.array([1e-3, 0.1, 3.0]), 3e5
    ca, ha = PerssonFriction(a, s).cold_and_hot(v, T20, p)
    for other in (b, c):
        cb, hb = PerssonFriction(other, s).cold_and_hot(v, T20, p)
        np.testing.assert_allclose(cb.mu, ca.mu, rtol=1e-12)
        np.testing.assert_allclose(hb.mu, ha.mu, rtol=1e-12)


def test_softening_between_sweep_temperatures(tmp_path: Path) -> None:
    """Linear in T between the sweeps, held at the nearest sweep outside them (exact: 1e-12)."""
    c = load_compound(sweep_softening(tmp_path, sweep_table("moduli")))
    f0 = np.interp(np.log10(0.1), np.log10(EPS), expected_ratios(0.0)[0])
    f40 = np.interp(np.log10(0.1), np.log10(EPS), expected_ratios(40.0)[0])
    T = np.array([253.15, 273.15, 283.15, 293.15, 313.15, 353.15])
    R, _ = c.softening_at(T)
    np.testing.assert_allclose(R, [f0, f0, 0.75 * f0 + 0.25 * f40, 0.5 * (f0 + f40), f40, f40],
                               rtol=1e-12)
    with pytest.raises(InputError, match="give T"):
        c.softening_factors()


def test_engine_uses_the_softening_at_each_temperature(tmp_path: Path) -> None:
    """Cold branch at T: the same friction as the compound with that temperature's factors
    fixed (another code path: factors in the table, not per scale; 1e-12). Time-temperature
    superposition still holds without T dependence (1e-9, as tests/test_persson_engine.py)
    and no longer with it. Hot branch with two identical sweeps = the T-independent law
    (its fixed point is solved to 1e-3 K: 1e-5), and hot = cold at 1e-6 m/s (no heating)."""
    c = load_compound(sweep_softening(tmp_path, sweep_table("moduli")))
    c = type(c)(**{**c.__dict__, "adhesion": NoAdhesion()})
    surf = make_surface()
    m = PerssonFriction(c, surf)
    v = np.logspace(-4, 0, 5)
    for T in (263.15, 293.15, 303.15):
        R, I_ = c.softening_factors(T)
        fixed = type(c)(**{**c.__dict__, "softening": TabulatedSoftening(
            np.array([1e-6, 1.0]), np.full(2, R), np.full(2, I_))})
        np.testing.assert_allclose(m.cold(v, T, 3e5).mu,
                                   PerssonFriction(fixed, surf).cold(v, T, 3e5).mu, rtol=1e-12)
    aT = 10.0 ** c.log10_aT(np.array(313.15))
    assert not np.allclose(m.cold(v, 313.15, 3e5).mu, m.cold(v * aT, T20, 3e5).mu, rtol=1e-3), \
        "softening that depends on T breaks time-temperature superposition (as it should)"
    one = type(c)(**{**c.__dict__, "softening": TabulatedSoftening(
        EPS, *expected_ratios(0.0))})
    mo = PerssonFriction(one, surf)
    np.testing.assert_allclose(mo.cold(v, 313.15, 3e5).mu, mo.cold(v * aT, T20, 3e5).mu,
                               rtol=1e-9)
    same = StrainSweepSoftening(np.array([273.15, 313.15]), (EPS, EPS),
                                (expected_ratios(0.0)[0],) * 2, (expected_ratios(0.0)[1],) * 2)
    ms = PerssonFriction(type(c)(**{**c.__dict__, "softening": same}), surf)
    assert ms.soft_T and not mo.soft_T
    np.testing.assert_allclose(ms.hot(v, T20, 3e5).mu, mo.hot(v, T20, 3e5).mu, rtol=1e-5)
    np.testing.assert_allclose(m.hot(1e-6, T20, 3e5).mu, m.cold(1e-6, T20, 3e5).mu,
                               rtol=1e-6)


# -- extrapolation: what a result took from outside the data ----------------------------------
SURF = make_surface(H=0.8, q0=1e3, q_r=1e3, h_rms=1e-5, cutoff=CutoffRule("fixed", q1=1e6))
V = np.array([1e-3, 0.1, 10.0])  # needs log10 omega from -2.1 to 3 (v = 1e-3) .. 1.9 to 7


def master(lo: float, hi: float, outside: str = "maxwell") -> TabulatedMasterCurve:
    w = np.logspace(lo, hi, round((hi - lo) * 8) + 1)
    return TabulatedMasterCurve(w, *REF.storage_loss(w), outside=outside, source="mc.csv")


def engine(lo: float, hi: float, outside: str = "maxwell", **settings) -> PerssonFriction:
    return PerssonFriction(make_compound(master(lo, hi, outside)), SURF,
                           EngineSettings(**settings))


def test_share_is_zero_when_the_data_cover_the_needed_range() -> None:
    m = engine(-6, 10)
    c, h = m.cold_and_hot(V, T20, 3e5)
    for r in (c, h):
        assert np.all(r.outside == 0) and np.all(r.outside_visc == 0)
        assert np.all(r.outside_area == 0)
    parts = m._evaluate(V, np.full(3, T20), np.full(3, 3e5), None, outside=True)
    lw_min = np.log10(V * SURF.psd.q0 * m.cos_phi.min())
    np.testing.assert_allclose(parts["log10_omega_min"], lw_min, rtol=1e-12)
    analytic = PerssonFriction(make_compound(REF), SURF)
    assert analytic.band is None and np.all(analytic.cold(V, T20, 3e5).outside == 0)


@pytest.mark.filterwarnings("ignore::tirefric.errors.ExtrapolationWarning")
def test_share_is_positive_when_the_data_are_cut() -> None:
    """Cut at 1e-1 and 1e4 rad/s: every speed needs the continuation; the share rises where
    more of the needed band lies beyond the data, and is 1 where none is inside."""
    c, h = engine(-1, 4).cold_and_hot(V, T20, 3e5)
    for r in (c, h):
        assert np.all(r.outside > 0) and np.all(r.outside <= 1)
        assert np.all((r.outside_visc > 0) & (r.outside_area > 0))
    far = engine(9, 12).cold(V, T20, 3e5)  # data entirely above what the points need
    np.testing.assert_allclose([far.outside, far.outside_visc, far.outside_area], 1.0,
                               rtol=1e-12)


@pytest.mark.filterwarnings("ignore::tirefric.errors.ExtrapolationWarning")
def test_share_is_the_fraction_of_the_integrand_outside() -> None:
    """At full contact (P = 1, S = 1: tiny roughness, high pressure) eq. (17) is linear in
    E_I, mu_visc = (1/2) int dq q^3 C int dphi cos(phi) E_I(q v cos phi)/((1-nu^2) sigma0),
    and G(q1) of eq. (19) is int dq q^3 C int dphi |E|^2 (...). The shares are then the
    integrals over the nodes outside the band over the whole integrals, computed here by
    midpoint rules on a fine (ln q, phi) grid (2000 x 2000: a step in the integrand costs at
    most one cell, 5e-4). The engine's Gauss nodes see the band's edges as steps too; with
    128 angular nodes (the node next to an edge weighs < 1/128 of the angular integral, and
    the edge moves across the nodes as q changes) and 96 q-nodes per decade: 1e-2."""
    surf = make_surface(H=0.8, q0=1e3, q_r=1e3, h_rms=1e-8, cutoff=CutoffRule("fixed", q1=1e5))
    lo, hi = 0.5, 2.5  # the data cover the middle of what the point needs (-1.1 .. 3)
    curve = master(lo, hi)
    m = PerssonFriction(make_compound(curve), surf, EngineSettings(n_phi=128, q_per_decade=96))
    v, sigma0 = 0.01, 1e8
    r = m.cold(v, T20, sigma0)
    assert r.area == pytest.approx(1.0, abs=1e-6), "full contact"
    lq = np.linspace(np.log(1e3), np.log(1e5), 2001)
    q = np.exp(0.5 * (lq[1:] + lq[:-1]))
    phi = (np.arange(2000) + 0.5) * (0.5 * np.pi / 2000)
    lw = np.log10(q[:, None] * v * np.cos(phi)[None, :])
    E_R, E_I = curve.continued(10.0**lw)
    F_q = (q**4 * surf.psd.C(q))[:, None]  # q^3 C per d(ln q)
    out = (lw < lo) | (lw > hi)
    w_visc = F_q * np.cos(phi)[None, :] * E_I
    w_area = F_q * (E_R**2 + E_I**2)
    assert float(r.outside_visc) == pytest.approx(w_visc[out].sum() / w_visc.sum(), rel=1e-2)
    assert float(r.outside_area) == pytest.approx(w_area[out].sum() / w_area.sum(), rel=1e-2)
    assert 0.1 < float(r.outside_visc) < 0.9, "a case with a share that is neither 0 nor 1"


def test_outside_error_refuses_only_what_needs_the_continuation() -> None:
    """outside = "error": a curve covering the needed range is accepted (both branches); on a
    curve from 1e-2 to 1e8 rad/s the points at 0.1 and 10 m/s are inside it and accepted,
    the point at 1e-3 m/s needs down to 10^-2.1 rad/s and is refused with what it needs."""
    engine(-6, 10, "error").cold_and_hot(V, T20, 3e5)
    m = engine(-2, 8, "error")
    m.cold_and_hot(V[1:], T20, 3e5)
    for call in (m.cold, m.hot):
        with pytest.raises(InputError, match="policy is 'error'") as err:
            call(V, T20, 3e5)
        names_all(err, "1 of 3 point(s)", "v = 0.001 m/s", "T = 20 C", "mc.csv",
                  "modulus.outside", "0.01..1e+08 rad/s")


def test_large_share_warns_small_share_does_not() -> None:
    m = engine(-1, 4)
    with pytest.warns(ExtrapolationWarning, match="from outside the measured master curve"):
        r = m.cold(V, T20, 3e5)
    assert r.outside.max() > OUTSIDE_WARNING_SHARE
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert engine(-6, 10).cold(V, T20, 3e5).outside.max() == 0
        m.cold_and_hot(V, T20, 3e5, warn=False)


def test_cli_reports_the_share(tmp_path: Path, capsys) -> None:
    """`tirefric mu --json`: a share per point and branch; the text output has the shares as
    columns and a '# warning:' line above the threshold."""
    w = np.logspace(-1, 4, 41)
    (tmp_path / "mc.txt").write_text("# omega [rad/s]  E' [Pa]  E'' [Pa]\n"
                                     + rows(w, *REF.storage_loss(w), sep="  "))
    comp = compound_file(tmp_path, tabulated("mc.txt"))
    args = ["mu", "--compound", str(comp), "--surface", "asphalt", "--v", "1e-4,1",
            "--T", "20", "--p", "3e5"]
    assert main([*args, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    m = PerssonFriction(load_compound(comp), __import__("lookup.surface").surface.load_surface(
        "asphalt"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c, h = m.cold_and_hot(np.array([1e-4, 1.0]), T20, 3e5)
    np.testing.assert_allclose([p["outside_cold"] for p in out["points"]], c.outside,
                               rtol=1e-12)
    np.testing.assert_allclose([p["outside_hot"] for p in out["points"]], h.outside,
                               rtol=1e-12)
    assert out["measured_band_rad_s"] == pytest.approx([0.1, 1e4])
    assert out["warnings"] and "outside the measured master curve" in out["warnings"][0]
    assert main(args) == 0
    text = capsys.readouterr().out
    header = next(line for line in text.splitlines() if not line.startswith("#"))
    assert "outside_cold" in header and "outside_hot" in header and "# warning:" in text
    assert main(["mu", "--compound", "summer", "--surface", "asphalt", "--v", "1", "--T", "20",
                 "--p", "3e5", "--json", "--branch", "cold"]) == 0
    summer = json.loads(capsys.readouterr().out)
    assert summer["points"][0]["outside_cold"] == 0.0 and summer["measured_band_rad_s"] is None


def test_grid_stores_the_share_per_node(tmp_path: Path, capsys) -> None:
    """A grid of a tabulated compound carries outside_cold and outside_hot per node (the
    engine's values, rounded to float32 as every variable) and their summary in its metadata;
    `tirefric grid info` shows it."""
    from lookup.grid import load_grid
    from lookup.grid.build import build_grid
    from lookup.grid.spec import load_spec

    m = engine(-1, 4)
    spec = load_spec("default").with_axes(v=[1e-3, 0.1, 10.0], T=[T20, 313.15], p=[1e5, 1e6])
    grid, _ = build_grid(spec, tmp_path / "g.nc", workers=1, model=m, progress=False)
    c, h = m.cold_and_hot(V[:, None, None], spec.T[None, :, None], spec.p[None, None, :],
                          warn=False)
    np.testing.assert_allclose(grid["outside_cold"], c.outside, rtol=1e-6)
    np.testing.assert_allclose(grid["outside_hot"], h.outside, rtol=1e-6)
    loaded = load_grid(tmp_path / "g.nc")
    assert loaded.hash == grid.hash and "outside_hot" in loaded.variables
    ob = loaded.meta["outside_band"]
    assert ob["max_cold"] == pytest.approx(float(grid["outside_cold"].max()))
    assert ob["measured_band_rad_s"] == pytest.approx([0.1, 1e4])
    assert main(["grid", "info", str(tmp_path / "g.nc")]) == 0
    assert "largest share of a node's integrand from outside it" in capsys.readouterr().out
    # an analytic compound's grid has no such variables (the shipped grids are unchanged)
    plain, _ = build_grid(spec, tmp_path / "p.nc", workers=1,
                          model=PerssonFriction(make_compound(REF), SURF), progress=False)
    assert "outside_cold" not in plain.variables
    assert plain.meta["outside_band"]["measured_band_rad_s"] is None
    assert math.isfinite(plain.meta["outside_band"]["max_cold"])
