"""``tirefric grid build|info|query|plot`` through the real entry point (in-process main)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lookup.cli import MU_KEYS
from lookup.grid import FrictionGrid, load_grid, save_grid
from lookup.grid.reader import VARIABLES
from tirefric.cli import main

SPEC = """
name = "cli-test"
compound = "summer"
surface = "asphalt"
[axes.v]
min = "1e-4 m/s"
max = "10 m/s"
n = 4
[axes.T]
min = "0 degC"
max = "60 degC"
n = 2
[axes.p]
min = "0.1 MPa"
max = "1 MPa"
n = 2
"""


@pytest.fixture
def linear_grid(tmp_path):
    """A grid whose values are known in closed form: mu_cold = 0.5 + 0.1 log10 v."""
    lv = np.linspace(-6, 1.6, 5)
    T = np.array([253.15, 393.15])
    lp = np.array([4.7, 6.3])
    LV = np.broadcast_to(lv[:, None, None], (5, 2, 2))
    variables = {n: 0.5 + 0.1 * LV + k for k, n in enumerate(VARIABLES)}
    g = FrictionGrid(lv, T, lp, variables, {"s0_m": 2e-4, "D_m": 1e-3,
                                             "compound_name": "x", "surface_name": "y"})
    return g, save_grid(g, tmp_path / "lin.nc")


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_query_json_keys_and_values(capsys, linear_grid):
    _, path = linear_grid
    code, out, err = run(capsys, "grid", "query", str(path), "--v", "1e-3,0.1,1000",
                         "--T", "20", "--p", "3e5", "--json")
    assert code == 0
    data = json.loads(out)
    assert [list(p) for p in data["points"]] == [list(MU_KEYS)] * 3, \
        "same keys as `tirefric mu`"
    mu = [p["mu_cold"] for p in data["points"]]
    np.testing.assert_allclose(mu, [0.2, 0.4, 0.5 + 0.16], rtol=1e-12,
                               err_msg="interpolated (and clamped at v_max = 40 m/s)")
    assert data["clamped"] == {"log10_v": {"below": 0, "above": 1}}
    assert "clamped" in err, "clamping is reported on stderr"


def test_query_pchip_along_v(capsys, linear_grid):
    """--v-interp pchip: data linear in log10 v stay exact (PCHIP reproduces lines)."""
    _, path = linear_grid
    code, out, _ = run(capsys, "grid", "query", str(path), "--v", "1e-3,0.1", "--T", "20",
                       "--p", "3e5", "--v-interp", "pchip", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["v_interp"] == "pchip"
    np.testing.assert_allclose([q["mu_cold"] for q in data["points"]], [0.2, 0.4], rtol=1e-12)


def test_query_text(capsys, linear_grid):
    _, path = linear_grid
    code, out, _ = run(capsys, "grid", "query", str(path), "--v", "0.01", "--T", "20",
                       "--p", "3e5")
    assert code == 0 and "mu_cold" in out and "0.3" in out


def test_info(capsys, linear_grid):
    g, path = linear_grid
    code, out, _ = run(capsys, "grid", "info", str(path), "--json")
    assert code == 0
    info = json.loads(out)
    assert info["hash"] == g.hash and info["shape"] == [5, 2, 2]
    assert info["axes"]["T"]["units"] == "K" and info["variables"]["dT_flash"]["units"] == "K"
    code, out, _ = run(capsys, "grid", "info", str(path))
    assert code == 0 and g.hash in out


def test_plot(capsys, linear_grid, tmp_path):
    _, path = linear_grid
    png = tmp_path / "g.png"
    code, _, _ = run(capsys, "grid", "plot", str(path), "-o", str(png))
    assert code == 0 and png.stat().st_size > 10_000


def test_errors_exit_2(capsys, linear_grid, tmp_path):
    _, path = linear_grid
    bad = tmp_path / "bad.nc"
    bad.write_bytes(path.read_bytes()[:1000])
    code, _, err = run(capsys, "grid", "info", str(bad))
    assert code == 2 and "corrupt or truncated" in err
    code, _, err = run(capsys, "grid", "query", str(tmp_path / "none.nc"), "--v", "1",
                       "--T", "20", "--p", "1e5")
    assert code == 2 and "not a shipped grid name" in err
    code, _, err = run(capsys, "grid", "query", str(path), "--v", "1", "--T", "20",
                       "--p", "-5")
    assert code == 2 and "--p" in err


def test_build_and_resume_cli(capsys, tmp_path):
    pytest.importorskip("lookup.friction")
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC)
    out = tmp_path / "g.nc"
    code, stdout, _ = run(capsys, "grid", "build", str(spec), "-o", str(out), "--workers", "1",
                          "--quiet", "--json")
    assert code == 0
    report = json.loads(stdout)
    assert report["n_computed"] == 4 and report["points_per_s_per_core"] > 0
    assert load_grid(out).hash == report["hash"]
