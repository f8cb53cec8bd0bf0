"""``tirefric tire curve``: JSON keys, agreement with the library, plot, input errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

from tire_brush.friction import ConstantFriction
from tire_brush.params import load_tire
from tire_brush.steady import SteadyBrush
from tirefric.cli import main

BASE = ["tire", "curve", "--tire", "passenger", "--Fz", "4000", "--vx", "20", "--T", "20"]


def test_curve_json_matches_library(capsys) -> None:
    rc = main([*BASE, "--grid", "constant:1.0,0.8", "--kappa=-0.2:0:5", "--json"])
    assert rc == 0
    data = json.loads(capsys.readouterr().out)
    pts = data["points"]
    assert len(pts) == 5
    for key in ("kappa", "alpha", "Fx", "Fy", "Mz", "mu_eff", "sliding_fraction"):
        assert all(key in p for p in pts), key
    model = SteadyBrush(load_tire("passenger"), ConstantFriction(1.0, 0.8))
    out = model.solve(np.linspace(-0.2, 0, 5), 0.0, 20.0, 4000.0, 293.15)
    np.testing.assert_allclose([p["Fx"] for p in pts], out.Fx, rtol=1e-12)
    assert pts[-1]["Fx"] == 0.0 and pts[0]["Fx"] < -3000.0


def test_curve_alpha_sweep_table_and_plot(tmp_path, capsys) -> None:
    png = tmp_path / "curve.png"
    rc = main([*BASE, "--grid", "constant:1.0", "--alpha-deg", "0:8:5", "--plot", str(png)])
    assert rc == 0
    assert png.stat().st_size > 10_000
    text = capsys.readouterr().out
    assert "Fy" in text and "passenger" in text


@pytest.mark.parametrize("args,match", [
    (["--grid", "constant:1.0", "--kappa", "0:1"], "A:B:N"),
    (["--grid", "constant:1.0", "--kappa=-1:0:3"], "kappa"),
    (["--grid", "constant:1.0", "--alpha-deg", "0:95:3"], "alpha"),
    (["--grid", "constant:x", "--kappa", "0:0.1:3"], "grid"),
    (["--grid", "no-such-grid.nc", "--kappa", "0:0.1:3"], "no-such-grid"),
])
def test_curve_input_errors(args, match, capsys) -> None:
    assert main([*BASE, *args]) == 2
    assert match in capsys.readouterr().err


def test_curve_realtime_fidelity(tmp_path, monkeypatch, capsys) -> None:
    """``--fidelity realtime``: the real-time tire settled at each slip (its table cached under
    $TIREFRIC_CACHE; coarse axes here) agrees with the steady march within 2 % of Fz on a
    constant friction (full sliding is exact in both: mu Fz)."""
    from tire_brush import realtime_build

    small = {"gamma": [0.0, 0.1], "T": [273.15, 313.15], "Fz": [2000.0, 4500.0, 7000.0],
             "log10_v": np.log10([1.0, 10.0, 40.0]).tolist(),
             "theta": np.radians([-90.0, -45.0, 0.0, 45.0, 90.0]).tolist(),
             "rho": [0.0, 0.1, 0.2, 0.33, 0.5, 0.75, 1.0]}
    monkeypatch.setattr(realtime_build, "default_axes", lambda T: {
        k: np.asarray(v, float) for k, v in small.items()})
    monkeypatch.setenv("TIREFRIC_CACHE", str(tmp_path))
    args = [*BASE, "--grid", "constant:1.0", "--kappa=-0.3:-0.1:3", "--json"]
    out = {}
    for fid in ("full", "realtime"):
        assert main([*args, "--fidelity", fid]) == 0
        out[fid] = json.loads(capsys.readouterr().out)
    assert out["realtime"]["fidelity"] == "realtime"
    for a, b in zip(out["full"]["points"], out["realtime"]["points"], strict=True):
        assert abs(a["Fx"] - b["Fx"]) < 0.02 * 4000.0
    assert list(tmp_path.glob("patch-*.bin")), "the table is cached"
