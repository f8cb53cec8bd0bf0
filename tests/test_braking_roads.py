"""``tirefric abs roads``: the four-wheel car on roads that change (tire_brush.braking.roads),
on the force map and through the FMU, on the synthetic grid of :mod:`fmu_support`."""

from __future__ import annotations

import csv
import json
from dataclasses import replace

import numpy as np
import pytest
from fmu_support import build_test_fmu, synthetic_grid

from tire_brush.braking.roads import load_roads_spec, run_roads, write_roads
from tirefric.errors import InputErrors

SPEC = """
provenance = "test"
[study]
name = "roads_test"
v0 = "8 m/s"
v_stop = "2 m/s"
temperature = "20 degC"
controllers = {controllers}
fmu = {fmu}
[car]
mass = "1600 kg"
wheelbase = "2.7 m"
cg_to_front = "1.2 m"
cg_height = "0.55 m"
track = "1.55 m"
wheel_inertia = "1.2 kg m^2"
radius = "0.31 m"
brake_balance = 0.65
brake_torque_max_Nm = 9000.0
brake_torque_rate_max_Nm_per_s = 40000.0
[friction]
tire = "passenger"
grid = "{grid}"
[map]
n_kappa = 21
n_v = 4
n_loads = 3
[[roads]]
name = "uniform"
[[roads]]
name = "split_mu"
right = 0.3
[[roads]]
name = "patch"
left = {{ from_m = 2.0, to_m = 6.0, factor = 0.5 }}
"""


@pytest.fixture(scope="module")
def grid_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("roads_grid") / "synthetic.npz"
    synthetic_grid().save_npz(path)
    return path


def _spec(tmp_path, grid, controllers='["locked"]', fmu="false"):
    path = tmp_path / "roads.toml"
    path.write_text(SPEC.format(grid=grid, controllers=controllers, fmu=fmu))
    return path


def test_roads_on_the_map_split_mu_and_a_patch(tmp_path, grid_file):
    """Locked wheels on the map: the uniform road has no yaw moment (symmetric car), the
    split-mu road pulls towards the high (left) side (M_z > 0) and stops longer, the low patch
    under the left wheels gives a yaw moment of the other sign while the car is on it; the
    files list every run."""
    spec = load_roads_spec(_spec(tmp_path, grid_file))
    doc, runs = run_roads(spec)
    rows = {r["road"]: r for r in doc["results"]}
    assert rows["uniform"]["yaw_moment_peak_Nm"] < 1e-6 * spec.car.mass * spec.car.g
    assert rows["split_mu"]["yaw_moment_mean_Nm"] > 0.0
    assert rows["split_mu"]["stopping_distance"] > rows["uniform"]["stopping_distance"]
    patch = runs[("patch", "locked", "map")]
    on = (patch.x > 2.5) & (patch.x < 5.5)
    assert np.all(patch.yaw_moment[on] < 0.0)
    assert rows["patch"]["stopping_distance"] > rows["uniform"]["stopping_distance"]
    out = write_roads(doc, runs, tmp_path / "out", plots=False)
    with open(out / "results.csv") as fh:
        assert len(list(csv.reader(fh))) == 1 + 3
    assert json.loads((out / "results.json").read_text())["results"][1]["road"] == "split_mu"
    assert (out / "trajectories" / "patch_locked_map.csv").is_file()


@pytest.mark.slow
def test_roads_through_the_fmu_agree_with_the_map(tmp_path, grid_file):
    """Locked wheels on the uniform and the split-mu road, through four FMU instances
    (transient brush) and on the steady map. On this synthetic grid the transient locked
    tire stops 4.6-4.8 % shorter than the steady map from 8 m/s (its velocity weakening
    makes the sliding tread stick-slip, docs/tire-core.md), the same on both roads: what the
    split-mu road costs against the uniform one agrees within 2 % (measured 0.3 %), and the
    mean yaw moments within 15 % (measured 6 %; as on the default grid,
    test_braking_two_track_fmu). Slow (~37 s): the fast suite keeps the two-track FMU's own
    checks (tests/test_braking_two_track_fmu.py) and the roads runner on the map."""
    from fmu_src.host.cosim import CosimSettings, FmuBrakingSimulator

    fmu = build_test_fmu(tmp_path)

    def factory(tire, grid, work_dir, options):
        return FmuBrakingSimulator(str(fmu), CosimSettings(step=options["step"]))

    spec = load_roads_spec(_spec(tmp_path, grid_file, fmu="true"))
    spec = replace(spec, roads=spec.roads[:2])
    _, runs = run_roads(spec, simulator_factory=factory, work_dir=tmp_path)
    d = {(road, model): runs[(road, "locked", model)].stopping_distance
         for road in ("uniform", "split_mu") for model in ("map", "fmu")}
    cost_map = d[("split_mu", "map")] / d[("uniform", "map")]
    cost_fmu = d[("split_mu", "fmu")] / d[("uniform", "fmu")]
    assert cost_map > 1.3
    assert cost_fmu == pytest.approx(cost_map, rel=0.02)
    m, f = (runs[("split_mu", "locked", k)].summary() for k in ("map", "fmu"))
    assert f["yaw_moment_mean_Nm"] == pytest.approx(m["yaw_moment_mean_Nm"], rel=0.15)
    with pytest.raises(Exception, match="FMU simulator"):
        run_roads(spec)


def test_bad_roads_spec_names_file_field_value(tmp_path, grid_file):
    path = _spec(tmp_path, grid_file, controllers='["abs", "pumping"]')
    text = path.read_text().replace("right = 0.3", "right = -0.3").replace(
        "to_m = 6.0", "to_m = 1.0").replace('track = "1.55 m"', 'trak = "1.55 m"')
    path.write_text(text)
    with pytest.raises(InputErrors) as exc:
        load_roads_spec(path)
    msg = str(exc.value)
    for part in ("roads.toml", "study.controllers", "pumping", "roads[1].right", "-0.3",
                 "roads[2].left.to_m", "car.trak"):
        assert part in msg, part
