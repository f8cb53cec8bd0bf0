"""The friction engine on a scientist's own data files.

Every bad input of the issue is refused with an error naming the file (or option), the field
and the value; the new options (units on the command line, explicit frequency units, plain
a_T factors, a q0 for tabulated spectra, line-scan spectra in TOML, cold-only studies, engine
settings from the CLI, the kappa-rescaled contact area) change what they claim and nothing
else.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import T20, make_compound, make_surface
from scipy.special import erf

from lookup.adhesion import NoAdhesion
from lookup.compound import load_compound
from lookup.friction import EngineSettings, PerssonFriction
from lookup.grid.spec import load_spec
from lookup.modulus import SingleRelaxation
from lookup.reference import contact_area_elastic
from lookup.roughness import CutoffRule
from lookup.surface import load_surface
from lookup.topography import psd_2d_from_1d
from tirefric.cli import main
from tirefric.config import read_csv_table
from tirefric.errors import InputError
from tirefric.paths import models_dir

#: The shipped summer compound's text, its strain-softening table named by its absolute path so
#: that a copy written elsewhere loads.
SUMMER = (models_dir() / "compounds" / "summer.toml").read_text().replace(
    'file = "data/', f'file = "{(models_dir() / "compounds").as_posix()}/data/')
ASPHALT = (models_dir() / "surfaces" / "asphalt.toml").read_text()
MASTER = "omega [rad/s],E_storage [MPa],E_loss [MPa]\n0.1,5,0.5\n10,8,2\n1000,50,30\n"


def tabulated_compound(tmp_path: Path, csv_text: str | bytes, name: str = "mc.csv") -> Path:
    csv = tmp_path / name
    if isinstance(csv_text, bytes):
        csv.write_bytes(csv_text)
    else:
        csv.write_text(csv_text)
    toml = SUMMER.split("[modulus]")[0] + (
        f'[modulus]\nT_ref = "20 degC"\nmodel = "tabulated"\nfile = "{name}"\n'
    ) + "[shift]" + SUMMER.split("[shift]")[1]
    p = tmp_path / "tab.toml"
    p.write_text(toml)
    return p


def names_all(err: pytest.ExceptionInfo, *parts: str) -> None:
    text = str(err.value)
    for part in parts:
        assert part in text, f"error should name {part!r}: {text}"


# -- CSV files ---------------------------------------------------------------------------------
def test_non_utf8_comment_lines_are_read(tmp_path: Path) -> None:
    """Comment lines in Latin-1 (e.g. 'Messung bei 20 \xb0C, M\xfcller') do not matter."""
    text = "# Messung bei 20 \u00b0C, M\u00fcller\n".encode("latin-1") + MASTER.encode()
    c = load_compound(tabulated_compound(tmp_path, text))
    ER, _ = c.modulus.storage_loss(np.array([10.0]))
    assert ER[0] == pytest.approx(8e6)


def test_non_utf8_data_line_names_file_and_line(tmp_path: Path) -> None:
    text = MASTER.replace("[MPa],E_loss", "[MPa],E_loss").encode() + "1e4,60,\u00b5\n".encode(
        "latin-1")
    p = tabulated_compound(tmp_path, text)
    with pytest.raises(InputError, match="not UTF-8") as err:
        load_compound(p)
    names_all(err, str(tmp_path / "mc.csv"), "line 5", "0xb5")


@pytest.mark.parametrize("delim", ["\t", ";"])
def test_tab_and_semicolon_delimited_tables(tmp_path: Path, delim: str) -> None:
    """The delimiter is detected from the header: same numbers as the comma version."""
    ref = load_compound(tabulated_compound(tmp_path, MASTER)).modulus
    other = load_compound(tabulated_compound(tmp_path, MASTER.replace(",", delim), "t.csv"))
    np.testing.assert_array_equal(other.modulus.E_storage, ref.E_storage)
    np.testing.assert_array_equal(other.modulus.E_loss, ref.E_loss)


def test_mixed_delimiters_name_the_delimiter(tmp_path: Path) -> None:
    """Header with commas, data rows with tabs: the error says which delimiter was used."""
    p = tmp_path / "m.csv"
    p.write_text("q [1/m],C [m^4]\n100\t1e-9\n1000\t1e-12\n")
    with pytest.raises(InputError, match="comma-delimited") as err:
        read_csv_table(p, {"q": "wavenumber", "C": "psd"})
    names_all(err, str(p), "field 'q'", "100\\t1e-9")


def test_unit_with_a_delimiter_inside_names_it(tmp_path: Path) -> None:
    """'[Hz]\\tE_storage [Pa]' as one unit (the issue's message) now explains itself."""
    p = tmp_path / "m.csv"
    p.write_text("omega [Hz]\tE_storage [Pa],E_loss [Pa]\n1\t2,3\n")
    with pytest.raises(InputError, match="tab: is that the delimiter") as err:
        read_csv_table(p, {"omega": "angular_frequency"})
    names_all(err, str(p), "field 'omega'")


# -- master-curve frequency unit -----------------------------------------------------------------
def test_frequency_unit_one_per_second_is_refused(tmp_path: Path) -> None:
    p = tabulated_compound(tmp_path, MASTER.replace("[rad/s]", "[1/s]"))
    with pytest.raises(InputError, match="ambiguous") as err:
        load_compound(p)
    names_all(err, str(tmp_path / "mc.csv"), "field 'omega'", "'1/s'", "rad/s", "Hz")


@pytest.mark.parametrize("unit,factor", [("rad/s", 1.0), ("Hz", 2 * np.pi)])
def test_frequency_unit_is_applied_and_reported(tmp_path: Path, unit: str, factor: float) -> None:
    c = load_compound(tabulated_compound(tmp_path, MASTER.replace("[rad/s]", f"[{unit}]")))
    np.testing.assert_allclose(c.modulus.omega, factor * np.array([0.1, 10.0, 1000.0]))
    how = c.describe()["modulus"]["frequency_column"]
    assert ("used as is" in how) == (unit == "rad/s") and unit in how


def test_cli_reports_the_frequency_unit_used(tmp_path: Path, capsys) -> None:
    comp = tabulated_compound(tmp_path, MASTER.replace("[rad/s]", "[Hz]"))
    assert main(["mu", "--compound", str(comp), "--surface", "asphalt", "--v", "0.01",
                 "--T", "20", "--p", "3e5", "--branch", "cold"]) == 0
    assert "cyclic frequency f [Hz], converted to omega = 2 pi f" in capsys.readouterr().out


# -- modulus and shift -----------------------------------------------------------------------------
def test_single_relaxation_elastic_limit_loads_and_gives_eq10(tmp_path: Path) -> None:
    """E0 == E1: E real (no loss); the engine then gives mu_visc = 0 and eq. (10)."""
    toml = SUMMER.split("[modulus]")[0] + (
        '[modulus]\nT_ref = "20 degC"\nmodel = "single_relaxation"\nE0 = "8 MPa"\n'
        'E1 = "8 MPa"\ntau = 1e-3\n') + "[shift]" + SUMMER.split("[shift]")[1]
    p = tmp_path / "el.toml"
    p.write_text(toml.replace('model = "eq21"', 'model = "none"'))
    p.write_text(p.read_text().split("[adhesion]")[0] + "[thermal]"
                 + p.read_text().split("[thermal]")[1])
    c = load_compound(p)
    assert isinstance(c.modulus, SingleRelaxation) and c.modulus.E0 == c.modulus.E1
    c = make_compound(c.modulus, NoAdhesion(), nu=0.5)
    surf = make_surface(H=0.8, q0=1e3, q_r=1e3, h_rms=1e-5, cutoff=CutoffRule("fixed", q1=1e6))
    m = PerssonFriction(c, surf, EngineSettings(q_per_decade=200))
    xi = np.sqrt(2 * np.pi * np.sum(m.w_lnq * m.F))
    r = m.cold(1.0, T20, np.array([1e5, 1e6]))
    np.testing.assert_allclose(r.area, contact_area_elastic(np.array([1e5, 1e6]), xi,
                                                            8e6 / 0.75), rtol=1e-9)
    assert np.all(r.mu_visc < 1e-300), "no loss, no viscoelastic friction (E_I floored at 1e-300)"
    bad = tmp_path / "bad.toml"
    bad.write_text(toml.replace('E1 = "8 MPa"', 'E1 = "7 MPa"'))
    with pytest.raises(InputError, match="elastic limit") as err:
        load_compound(bad)
    names_all(err, str(bad), "modulus.E1", "7 MPa")


def shift_compound(tmp_path: Path, table: str) -> Path:
    (tmp_path / "aT.csv").write_text(table)
    shift = SUMMER[SUMMER.index("[shift]"):SUMMER.index("[softening]")]
    toml = SUMMER.replace(shift, '[shift]\nmodel = "tabulated"\nfile = "aT.csv"\n'
                          'T_ref = "20 degC"\n\n')
    p = tmp_path / "shift.toml"
    p.write_text(toml)
    return p


def test_shift_as_plain_factor_equals_log10(tmp_path: Path) -> None:
    T = [-20, 0, 20, 40, 60]
    la = [3.2, 1.5, 0.0, -1.1, -2.0]
    logt = "T [degC],log10_aT [1]\n" + "".join(f"{t},{a}\n" for t, a in zip(T, la, strict=True))
    plain = "T [degC],aT [1]\n" + "".join(f"{t},{10**a!r}\n" for t, a in zip(T, la, strict=True))
    a = load_compound(shift_compound(tmp_path, logt))
    b = load_compound(shift_compound(tmp_path, plain))
    Tq = np.linspace(250, 340, 7)
    np.testing.assert_allclose(b.log10_aT(Tq), a.log10_aT(Tq), atol=1e-12)


@pytest.mark.parametrize("table,field,needle", [
    ("T [degC],aT [1],log10_aT [1]\n0,10,1\n20,1,0\n", "log10_aT", "exactly one"),
    ("T [degC],aT [1]\n0,10\n20,-1\n", "aT", "> 0"),
])
def test_bad_shift_table_is_named(tmp_path: Path, table, field, needle) -> None:
    with pytest.raises(InputError, match=needle) as err:
        load_compound(shift_compound(tmp_path, table))
    names_all(err, str(tmp_path / "aT.csv"), f"field '{field}'")


# -- surfaces ------------------------------------------------------------------------------------
def tabulated_surface(tmp_path: Path, model: str, table: str, extra: str = "") -> Path:
    (tmp_path / "psd.csv").write_text(table)
    psd = f'[psd]\nmodel = "{model}"\nfile = "psd.csv"\n{extra}'
    text = ASPHALT.split("[psd]")[0] + psd + "\n[cutoff]" + ASPHALT.split("[cutoff]")[1]
    text = text.replace('rule = "rms_slope"  # q1 where the cumulative rms slope reaches xi1 '
                        '(review sec. 5.1)\nxi1 = 1.0', 'rule = "fixed"\nq1 = 1e5')
    p = tmp_path / f"{model}.toml"
    p.write_text(text)
    return p


Q = np.geomspace(10.0, 1e6, 41)
PSD_TABLE = "q [1/m],C [m^4]\n" + "".join(f"{float(q)!r},{float(1e-10 * (q / 10) ** -3.6)!r}\n"
                                          for q in Q)


def test_tabulated_psd_q0_trims_the_spectrum(tmp_path: Path) -> None:
    full = load_surface(tabulated_surface(tmp_path, "tabulated", PSD_TABLE))
    cut = load_surface(tabulated_surface(tmp_path, "tabulated", PSD_TABLE, "q0 = 200.0\n"))
    assert cut.psd.q0 == 200.0 and full.psd.q0 == 10.0
    q = np.geomspace(200.0, 1e5, 50)
    np.testing.assert_allclose(cut.psd.C(q), full.psd.C(q), rtol=1e-12)
    assert cut.psd.C(np.array([150.0]))[0] == 0.0
    bad = tabulated_surface(tmp_path, "tabulated", PSD_TABLE, "q0 = 5.0\n")
    with pytest.raises(InputError, match="inside the spectrum") as err:
        load_surface(bad)
    names_all(err, str(bad), "psd.q0", "5.0")


def test_line_scan_spectrum_in_toml(tmp_path: Path) -> None:
    """A 1D spectrum C1D [m^3] is turned into the review's 2D C(q) (inverse Abel transform)."""
    C1 = 1e-7 * (Q / 10) ** -2.6
    table = "q [1/m],C1D [m^3]\n" + "".join(f"{float(q)!r},{float(c)!r}\n"
                                             for q, c in zip(Q, C1, strict=True))
    s = load_surface(tabulated_surface(tmp_path, "tabulated_1d", table, "q0 = 100.0\n"))
    q = np.geomspace(100.0, 1e5, 30)
    np.testing.assert_allclose(s.psd.C(q), psd_2d_from_1d(Q, C1, q), rtol=1e-9)
    # self-affine 1D slope -(1 + 2H) gives the 2D slope -2(1 + H): H = 0.8 here
    slope = np.polyfit(np.log(q[5:-5]), np.log(s.psd.C(q[5:-5])), 1)[0]
    assert slope == pytest.approx(-3.6, abs=0.02)
    bad = tabulated_surface(tmp_path, "tabulated_1d", table.replace("[m^3]", "[m^4]"))
    with pytest.raises(InputError, match="unknown unit 'm\\^4'") as err:
        load_surface(bad)
    names_all(err, str(tmp_path / "psd.csv"), "field 'C1D'")


# -- cold-only studies and the command line ----------------------------------------------
def cold_only_files(tmp_path: Path) -> tuple[Path, Path]:
    c = tmp_path / "cold_compound.toml"
    c.write_text(SUMMER.split("[thermal]")[0])
    s = tmp_path / "cold_surface.toml"
    s.write_text(ASPHALT.split("[macroasperity]")[0])
    return c, s


def test_cold_only_study_needs_no_thermal_data(tmp_path: Path, capsys) -> None:
    c, s = cold_only_files(tmp_path)
    ref = PerssonFriction(load_compound("summer"), load_surface("asphalt")).cold(
        [1e-3, 1.0], T20, 3e5)
    rc = main(["mu", "--compound", str(c), "--surface", str(s), "--v", "1e-3,1", "--T", "20",
               "--p", "0.3 MPa", "--branch", "cold", "--json"])
    assert rc == 0
    pts = json.loads(capsys.readouterr().out)["points"]
    np.testing.assert_allclose([x["mu_cold"] for x in pts], ref.mu, rtol=1e-12)
    m = PerssonFriction(load_compound(c), load_surface(s))
    with pytest.raises(InputError) as err:
        m.hot(1.0, T20, 3e5)
    names_all(err, str(s), "macroasperity.D")
    m = PerssonFriction(load_compound(c), load_surface("asphalt"))
    with pytest.raises(InputError) as err:
        m.cold_and_hot(1.0, T20, 3e5)
    names_all(err, str(c), "field 'thermal'")


def run_mu(*extra: str) -> subprocess.CompletedProcess:
    argv = ["mu", "--compound", "summer", "--surface", "asphalt", "--v", "0.01", *extra]
    return subprocess.run([sys.executable, "-m", "tirefric.cli", *argv], capture_output=True,
                          text=True)


def test_cli_units_on_pressure_and_temperature(capsys) -> None:
    def mu(*extra):
        assert main(["mu", "--compound", "summer", "--surface", "asphalt", "--v", "0.01",
                     "--branch", "cold", "--json", *extra]) == 0
        return json.loads(capsys.readouterr().out)["points"][0]["mu_cold"]

    ref = mu("--T", "20", "--p", "3e5")
    assert mu("--T", "20", "--p", "0.3 MPa") == ref
    assert mu("--T", "293.15 K", "--p", "300 kPa") == pytest.approx(ref, rel=1e-12)


@pytest.mark.parametrize("args,opt,value,needle", [
    (["--T", "293.15", "--p", "3e5"], "--T", "293.15", "for kelvin write '293.15 K'"),
    (["--T", "20", "--p", "3 bar"], "--p", "3 bar", "unknown unit 'bar'"),
    (["--T", "20", "--p", "3e5", "--gamma", "1.5"], "--gamma", "1.5", "invalid engine"),
    (["--T", "20", "--p", "3e5", "--area-kappa", "9"], "--area-kappa", "9", "invalid engine"),
])
def test_cli_bad_values_are_named(args, opt, value, needle) -> None:
    r = run_mu(*args)
    assert r.returncode == 2 and needle in r.stderr and opt in r.stderr
    assert value in r.stderr and "Traceback" not in r.stderr


def test_cli_engine_settings_reach_the_engine(capsys) -> None:
    def cold(*extra):
        assert main(["mu", "--compound", "summer", "--surface", "asphalt", "--v", "0.01",
                     "--T", "20", "--p", "3e5", "--branch", "cold", "--json", *extra]) == 0
        return json.loads(capsys.readouterr().out)

    base = cold()
    fine = cold("--q-per-decade", "96", "--gamma", "0.4")
    assert fine["settings"]["q_per_decade"] == 96 and fine["settings"]["gamma"] == 0.4
    m = PerssonFriction(load_compound("summer"), load_surface("asphalt"),
                        EngineSettings(q_per_decade=96, gamma=0.4))
    assert fine["points"][0]["mu_cold"] == pytest.approx(m.cold(0.01, T20, 3e5).mu, rel=1e-12)
    assert fine["points"][0]["mu_visc_cold"] != base["points"][0]["mu_visc_cold"]


def test_grid_spec_engine_value_is_named(tmp_path: Path) -> None:
    text = (models_dir() / "grids" / "default.toml").read_text()
    text = text.replace('compound = "summer"', 'compound = "summer"').replace(
        "[engine]", "[engine]\ngamma = 1.5", 1) if "[engine]" in text else (
        text + "\n[engine]\ngamma = 1.5\n")
    p = tmp_path / "spec.toml"
    p.write_text(text)
    with pytest.raises(InputError, match="invalid engine setting") as err:
        load_spec(p)
    names_all(err, str(p), "engine.gamma", "1.5")


# -- contact area: kappa-rescaled P(q) --------------------------------------------------
def test_rescaled_kappa_contact_area_elastic_limit() -> None:
    """Elastic limit: A/A0 = erf((sqrt(pi) kappa/2) sigma0/(xi E*)); small-contact slope kappa
    (review eq. 11) instead of (8/pi)^(1/2); the default stays eq. (10)."""
    comp = make_compound(SingleRelaxation(8e6, 8e6, 1e-3), NoAdhesion(), nu=0.5)
    surf = make_surface(H=0.8, q0=1e3, q_r=1e3, h_rms=1e-5, cutoff=CutoffRule("fixed", q1=1e6))
    E_star = 8e6 / 0.75
    sig = np.array([1e2, 1e4, 1e5, 1e6])
    for kappa in (2.0, 2.4):
        m = PerssonFriction(comp, surf, EngineSettings(q_per_decade=100,
                                                       contact_area="rescaled_kappa",
                                                       area_kappa=kappa))
        xi = np.sqrt(2 * np.pi * np.sum(m.w_lnq * m.F))
        area = m.cold(1.0, T20, sig).area
        np.testing.assert_allclose(area, erf(np.sqrt(np.pi) * kappa / 2 * sig / (xi * E_star)),
                                   rtol=1e-9)
        small = area[0] / (sig[0] / (xi * E_star))
        assert small == pytest.approx(kappa, rel=1e-4)
    d = PerssonFriction(comp, surf, EngineSettings(q_per_decade=100))
    assert d.cold(1.0, T20, 1e2).area / (1e2 / (xi * E_star)) == pytest.approx(
        np.sqrt(8 / np.pi), rel=1e-4)


def test_rescaled_kappa_viscoelastic_friction_is_consistent() -> None:
    """With the rescaled law, eq. (17) integrates S(P(cG)) P(cG) dG = d[Phi(cG)/c]: checked
    against a direct trapezoidal quadrature of that integrand."""
    from lookup.contact import Phi, area_rescale, contact_fraction

    c = area_rescale(2.0)
    G = np.array([1e-3, 0.1, 1.0, 30.0, 1e4])
    g = np.geomspace(1e-12, 1e4, 400001)
    P = contact_fraction(c * g)
    f = (0.5 + 0.5 * P * P) * P
    cum = np.concatenate([[1e-12], 1e-12 + np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(g))])
    np.testing.assert_allclose(Phi(c * G, 0.5) / c, np.interp(G, g, cum), rtol=1e-5)
