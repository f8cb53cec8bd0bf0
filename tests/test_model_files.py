"""Shipped model files load and reproduce the review's qualitative facts; bad files are refused
with errors naming the file, the field and the value."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lookup.compound import load_compound
from lookup.friction import PerssonFriction
from lookup.surface import load_surface
from tirefric.cli import main
from tirefric.errors import InputError
from tirefric.paths import models_dir

SUMMER = (models_dir() / "compounds" / "summer.toml").read_text()
ASPHALT = (models_dir() / "surfaces" / "asphalt.toml").read_text()


def test_shipped_names_resolve() -> None:
    for n in ("summer", "winter", "racing"):
        assert load_compound(n).name == n
    for n in ("asphalt", "concrete"):
        assert load_surface(n).name == n


def test_concrete_q1_and_asphalt_slopes() -> None:
    """Concrete: rule xi(q1) = 1 gives q1 ~ 1e6 1/m (review sec. 5.1); asphalt: the measured
    slopes quoted in docs/review-notes.md (xi ~0.8 at 1e4 1/m, ~1.8 at 1e5 1/m)."""
    c = load_surface("concrete")
    assert 5e5 < c.q1 < 2e6
    a = load_surface("asphalt")
    assert np.sqrt(a.psd.xi_squared(1e4)) == pytest.approx(0.8, abs=0.01)
    assert np.sqrt(a.psd.xi_squared(1e5)) == pytest.approx(1.8, abs=0.1)
    assert a.psd.describe()["h_rms_m"] == pytest.approx(7e-4, rel=1e-9)


def _peak_speed(compound: str, surface: str, T_C: float) -> float:
    m = PerssonFriction(load_compound(compound), load_surface(surface))
    v = np.logspace(-8, 1.6, 97)
    return float(v[np.argmax(m.cold(v, T_C + 273.15, 3e5).mu)])


def test_review_sec52_friction_maxima() -> None:
    """Review sec. 5.2: summer tread maximum near 1 cm/s at room temperature and at m/s near
    50 C; racing compound maximum near 1 um/s at room temperature; winter above summer.
    'Near' = within half a decade."""
    assert abs(np.log10(_peak_speed("summer", "concrete", 20.0)) - (-2)) < 0.5
    assert 0.5 <= _peak_speed("summer", "concrete", 50.0) <= 10.0
    assert abs(np.log10(_peak_speed("racing", "concrete", 20.0)) - (-6)) < 0.5
    assert _peak_speed("winter", "concrete", 20.0) > 10 * _peak_speed("summer", "concrete", 20.0)


def test_racing_glass_transition() -> None:
    """T_g by the review's definition (tan delta maximum at 0.01 1/s) near -12 C."""
    c = load_compound("racing")
    T = np.arange(-60.0, 40.0, 0.1) + 273.15
    ER, EI = c.modulus.storage_loss(0.01 * 10.0 ** c.log10_aT(T))
    assert T[np.argmax(EI / ER)] - 273.15 == pytest.approx(-12.0, abs=3.0)


# -- bad input ---
BAD_COMPOUNDS = [
    ('E_inf = "10 MPa"', 'E_inf = "-10 MPa"', "modulus.E_inf", "must be > 0"),
    ('E_inf = "10 MPa"', 'E_inf = "10 MPascal"', "modulus.E_inf", "unknown unit"),
    ('E_inf = "10 MPa"', "E_inf = nan", "modulus.E_inf", "finite"),
    ('E_inf = "10 MPa"', "", "modulus.E_inf", "missing"),
    ("C1 = 15.0", "C1 = 15.0\nC3 = 1.0", "shift.C3", "unknown field"),
    ('sigma_f0 = "4 MPa"', 'sigma_f0 = "four"', "adhesion.sigma_f0", "number"),
]


@pytest.mark.parametrize("old,new,field,msg", BAD_COMPOUNDS)
def test_bad_compound_field_is_named(tmp_path: Path, old, new, field, msg) -> None:
    p = tmp_path / "bad.toml"
    p.write_text(SUMMER.replace(old, new, 1))
    with pytest.raises(InputError, match=msg) as err:
        load_compound(p)
    text = str(err.value)
    assert str(p) in text and field in text, f"error names file and field: {text}"


def test_non_monotonic_master_curve_table(tmp_path: Path) -> None:
    csv = tmp_path / "mc.csv"
    csv.write_text("# provenance: test\nomega [rad/s],E_storage [MPa],E_loss [MPa]\n"
                   "1,5,1\n10,6,2\n5,7,3\n")
    toml = SUMMER.split("[modulus]")[0] + (
        '[modulus]\nT_ref = "20 degC"\nmodel = "tabulated"\nfile = "mc.csv"\n'
    ) + "[shift]" + SUMMER.split("[shift]")[1]
    p = tmp_path / "tab.toml"
    p.write_text(toml)
    with pytest.raises(InputError, match="strictly increasing") as err:
        load_compound(p)
    assert "omega" in str(err.value) and "5.0" in str(err.value)


def test_tabulated_master_curve_loads_with_units(tmp_path: Path) -> None:
    csv = tmp_path / "mc.csv"
    csv.write_text("omega [Hz],E_storage [MPa],E_loss [MPa]\n0.1,5,0.5\n10,8,2\n1000,50,30\n")
    toml = SUMMER.split("[modulus]")[0] + (
        '[modulus]\nT_ref = "20 degC"\nmodel = "tabulated"\nfile = "mc.csv"\n'
    ) + "[shift]" + SUMMER.split("[shift]")[1]
    p = tmp_path / "tab.toml"
    p.write_text(toml)
    c = load_compound(p)
    ER, _ = c.modulus.storage_loss(np.array([2 * np.pi * 10]))
    assert ER[0] == pytest.approx(8e6), "Hz -> rad/s and MPa -> Pa converted"
    bad = tmp_path / "mc.csv"
    bad.write_text("omega [Hz],E_storage [psi],E_loss [MPa]\n0.1,5,0.5\n10,8,2\n")
    with pytest.raises(InputError, match="unknown unit 'psi'"):
        load_compound(p)


def test_q1_below_q0_refused(tmp_path: Path) -> None:
    p = tmp_path / "s.toml"
    p.write_text(ASPHALT.replace('rule = "rms_slope"  # q1 where the cumulative rms slope '
                                 'reaches xi1 (review sec. 5.1)\nxi1 = 1.0',
                                 'rule = "fixed"\nq1 = 50.0'))
    with pytest.raises(InputError, match="q1 must exceed q0") as err:
        load_surface(p)
    assert str(p) in str(err.value) and "50.0" in str(err.value)


def test_missing_surface_table(tmp_path: Path) -> None:
    """[macroasperity] is optional for a cold-only study; the hot branch names it."""
    p = tmp_path / "s.toml"
    p.write_text(ASPHALT.replace("[macroasperity]\nD = \"1 mm\"", ""))
    m = PerssonFriction(load_compound("summer"), load_surface(p))
    assert np.isfinite(m.cold(1e-2, 293.15, 3e5).mu)
    with pytest.raises(InputError, match="macroasperity") as err:
        m.hot(1e-2, 293.15, 3e5)
    assert str(p) in str(err.value) and "macroasperity.D" in str(err.value)


# -- CLI ---
def test_cli_mu_json(capsys) -> None:
    rc = main(["mu", "--compound", "summer", "--surface", "asphalt", "--v", "1e-5,1",
               "--T", "20", "--p", "3e5", "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    keys = {"v", "mu_cold", "mu_hot", "mu_visc_cold", "mu_cont_cold", "area_cold", "area_hot",
            "dT_flash", "outside_cold", "outside_hot"}
    assert len(out["points"]) == 2 and set(out["points"][0]) == keys
    p0 = out["points"][0]
    assert p0["mu_hot"] == pytest.approx(p0["mu_cold"], rel=1e-3), "hot = cold at 1e-5 m/s"


@pytest.mark.parametrize("args,needle", [
    (["--v", "nan"], "--v"), (["--v", "-1"], "--v"), (["--p", "-5"], "--p"),
    (["--compound", "nonexistent"], "nonexistent"),
])
def test_cli_mu_bad_input_exits_nonzero(args, needle) -> None:
    base = {"--compound": "summer", "--surface": "asphalt", "--v": "1", "--T": "20",
            "--p": "3e5"}
    for k, v in zip(args[::2], args[1::2], strict=True):
        base[k] = v
    argv = ["mu"] + [x for kv in base.items() for x in kv]
    r = subprocess.run([sys.executable, "-m", "tirefric.cli", *argv], capture_output=True,
                       text=True)
    assert r.returncode == 2 and needle in r.stderr and "Traceback" not in r.stderr


# -- measured topography and the Schallamach law through the loaders ---------------------------
def _topography_surface(tmp_path: Path, kind: str, data: str) -> Path:
    src = models_dir() / "surfaces" / "data" / data
    (tmp_path / data).write_text(src.read_text())
    psd = f'[psd]\nmodel = "{kind}"\nfile = "{data}"\n'
    text = ASPHALT.split("[psd]")[0] + psd + "\n[cutoff]" + ASPHALT.split("[cutoff]")[1]
    text = text.replace('rule = "rms_slope"  # q1 where the cumulative rms slope reaches xi1 '
                        '(review sec. 5.1)\nxi1 = 1.0', 'rule = "fixed"\nq1 = 2e4')
    p = tmp_path / f"{kind}.toml"
    p.write_text(text)
    return p


@pytest.mark.parametrize("kind,data", [("height_map", "synthetic_self_affine_map.csv"),
                                       ("line_scan", "synthetic_self_affine_scan.csv")])
def test_measured_topography_surface(tmp_path: Path, kind, data) -> None:
    """A surface from a height map or line scan carries exactly the spectrum that
    lookup.topography computes from the file (2D, or the isotropic transform of the 1D one)."""
    from lookup.topography import psd_2d_from_1d, read_height_map, read_line_scan

    s = load_surface(_topography_surface(tmp_path, kind, data))
    path = models_dir() / "surfaces" / "data" / data
    if kind == "height_map":
        q, C = read_height_map(path).psd()
    else:
        q, C1 = read_line_scan(path).psd()
        C = psd_2d_from_1d(q, C1)
    keep = C > 0
    np.testing.assert_allclose(s.psd.C(q[keep]), C[keep], rtol=1e-9)
    assert s.q1 == 2e4
    m = PerssonFriction(load_compound("summer"), s)
    assert np.isfinite(m.cold([1e-3, 1.0], 293.15, 3e5).mu).all()


def test_schallamach_compound_loads(tmp_path: Path) -> None:
    text = SUMMER
    for line in ('sigma_f0 = "4 MPa"\n', "c = 0.17\n", 'shift = "bulk"\n'):
        text = text.replace(line, "", 1)
    text = text.replace('model = "eq21"', 'model = "schallamach"\nsigma_star = "9 MPa"\n'
                        'delta_E = "0.0758 eV"\ntau0_shift = "bulk"')
    p = tmp_path / "sch.toml"
    p.write_text(text)
    c = load_compound(p)
    assert c.adhesion.describe()["model"] == "schallamach_appendix_A"
    from lookup.schallamach import normalized_shear_stress

    v = np.logspace(-6, 2, 161)
    dE_kT = 0.0758 * 1.602176634e-19 / (1.380649e-23 * 293.15)
    np.testing.assert_allclose(c.adhesion.sigma_f(v, 293.15),
                               9e6 * normalized_shear_stress(v / 0.01, dE_kT), rtol=1e-9,
                               err_msg="loader builds review eq. (A21) with the file's values")
