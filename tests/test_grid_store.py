"""NetCDF-4 grid files (:mod:`lookup.grid.store`): round trips through h5netcdf and xarray,
and refusal of corrupt, truncated or incomplete files."""

from __future__ import annotations

import json
import shutil

import h5py
import numpy as np
import pytest

from lookup.grid import load_grid, save_grid
from lookup.grid.reader import AXES, AXIS_UNITS, VARIABLE_UNITS, VARIABLES, FrictionGrid
from lookup.grid.store import grid_summary, resolve_grid_path
from tirefric.errors import GridError, InputError

RNG_SEED = 7


def make_grid() -> FrictionGrid:
    rng = np.random.default_rng(RNG_SEED)
    lv = np.linspace(-6.0, 1.6, 9)
    T = np.linspace(253.15, 393.15, 4)
    lp = np.linspace(4.7, 6.3, 3)
    shape = (lv.size, T.size, lp.size)
    variables = {n: rng.uniform(0.1, 2.0, shape) for n in VARIABLES}
    meta = {"s0_m": 2e-4, "D_m": 1e-3, "q1_per_m": 1.2e6, "q1_rule": "rms slope = 1",
            "compound": {"name": "summer", "modulus": {"E0_Pa": 6e6}},
            "surface": {"name": "asphalt", "H": 0.8}, "engine_settings": {"n_q": 64},
            "package_version": "0.1.0", "created": "2024-01-01T00:00:00+00:00"}
    return FrictionGrid(lv, T, lp, variables, meta)


@pytest.fixture
def grid_file(tmp_path):
    g = make_grid()
    return g, save_grid(g, tmp_path / "g.nc")


def test_netcdf_round_trip(grid_file):
    g, path = grid_file
    h = load_grid(path)
    assert h.hash == g.hash, "content hash survives the NetCDF round trip"
    for n in AXES:
        np.testing.assert_array_equal(h.axes[n], g.axes[n], err_msg=f"axis {n}")
    for n in VARIABLES:
        np.testing.assert_array_equal(h[n], g[n], err_msg=f"variable {n}")
    assert h.meta["compound"] == g.meta["compound"], "full compound parameters kept"
    assert h.meta["q1_rule"] == "rms slope = 1" and h.s0_m == g.s0_m and h.D_m == g.D_m


def test_readable_by_xarray_with_units(grid_file):
    xr = pytest.importorskip("xarray")
    g, path = grid_file
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        for n in AXES:
            assert ds[n].attrs["units"] == AXIS_UNITS[n], f"units of axis {n}"
        for n in VARIABLES:
            assert ds[n].attrs["units"] == VARIABLE_UNITS[n], f"units of {n}"
            assert ds[n].dims == AXES, f"dimension order of {n}"
            np.testing.assert_array_equal(ds[n].values, g[n], err_msg=f"xarray reads {n}")
        assert ds.attrs["hash"] == g.hash
        assert json.loads(ds.attrs["compound_json"])["modulus"]["E0_Pa"] == 6e6
        assert ds.attrs["D_m"] == 1e-3
        # selection by coordinate as a user would do it
        sel = ds["mu_hot"].sel(T=g.T[1], log10_p=g.log10_p[2])
        np.testing.assert_array_equal(sel.values, g["mu_hot"][:, 1, 2])


def test_readable_by_plain_hdf5(grid_file):
    g, path = grid_file
    with h5py.File(path, "r") as f:
        np.testing.assert_array_equal(f["dT_flash"][...], g["dT_flash"],
                                      err_msg="plain h5py (as MATLAB h5read) reads the data")


def test_summary(grid_file):
    g, path = grid_file
    s = grid_summary(load_grid(path))
    assert s["shape"] == [9, 4, 3] and s["hash"] == g.hash
    assert s["axes"]["T"]["T_min_C"] == pytest.approx(-20.0)
    json.dumps(s)


def test_truncated_file_refused(grid_file, tmp_path):
    _, path = grid_file
    data = path.read_bytes()
    for frac in (0.1, 0.5, 0.9):
        bad = tmp_path / f"trunc{frac}.nc"
        bad.write_bytes(data[: int(len(data) * frac)])
        with pytest.raises(GridError, match="corrupt or truncated") as exc:
            load_grid(bad)
        assert str(bad) in str(exc.value), "the message names the file"


def _data_offset(path, name):
    with h5py.File(path, "r") as f:
        ds = f[name]
        return ds.id.get_chunk_info(0).byte_offset


def test_flipped_bytes_in_data_refused(grid_file, tmp_path):
    _, path = grid_file
    off = _data_offset(path, "mu_hot")
    b = bytearray(path.read_bytes())
    for k in range(off + 10, off + 14):
        b[k] ^= 0xFF
    bad = tmp_path / "flipped.nc"
    bad.write_bytes(bytes(b))
    with pytest.raises(GridError, match="corrupt"):
        load_grid(bad)


def test_flipped_bytes_anywhere_never_loads_silently(grid_file, tmp_path):
    """Flip a byte at many places: the file either loads with the original content (the byte
    was padding) or is refused; it never loads with different numbers."""
    g, path = grid_file
    data = path.read_bytes()
    rng = np.random.default_rng(RNG_SEED)
    bad = tmp_path / "flip.nc"
    refused = 0
    for pos in rng.choice(len(data), size=60, replace=False):
        b = bytearray(data)
        b[pos] ^= 0x5A
        bad.write_bytes(bytes(b))
        try:
            h = load_grid(bad)
        except GridError:
            refused += 1
            continue
        assert h.hash == g.hash, f"byte {pos} changed the content without being detected"
        for n in VARIABLES:
            np.testing.assert_array_equal(h[n], g[n])
    assert refused > 0, "some flips must hit data or metadata"


def test_values_changed_in_place_refused_by_hash(grid_file, tmp_path):
    _, path = grid_file
    bad = tmp_path / "edited.nc"
    shutil.copy(path, bad)
    with h5py.File(bad, "r+") as f:
        f["mu_cold"][0, 0, 0] = 5.0  # rewritten with valid checksums: only the hash knows
    with pytest.raises(GridError, match="hash mismatch"):
        load_grid(bad)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda f: f.__delitem__("mu_hot"), "variable 'mu_hot' is missing"),
        (lambda f: f["dT_flash"].attrs.__delitem__("units"), "'dT_flash' has units None"),
        (lambda f: f["T"].attrs.__setitem__("units", "degC"), "axis 'T' has units 'degC'"),
        (lambda f: f.attrs.__delitem__("meta_json"), "'meta_json' is missing"),
        (lambda f: f.attrs.__setitem__("tirefric_format", "other"), "not a tirefric grid"),
    ],
)
def test_incomplete_file_refused(grid_file, tmp_path, edit, message):
    _, path = grid_file
    bad = tmp_path / "edited.nc"
    shutil.copy(path, bad)
    with h5py.File(bad, "r+") as f:
        edit(f)
    with pytest.raises(GridError, match=message):
        load_grid(bad)


def test_nan_and_nonmonotonic_refused(grid_file, tmp_path):
    _, path = grid_file
    bad = tmp_path / "nan.nc"
    shutil.copy(path, bad)
    with h5py.File(bad, "r+") as f:
        f["area_hot"][1, 1, 1] = np.nan
    with pytest.raises(GridError, match="'area_hot' has 1 non-finite"):
        load_grid(bad)
    bad2 = tmp_path / "mono.nc"
    shutil.copy(path, bad2)
    with h5py.File(bad2, "r+") as f:
        f["log10_p"][2] = f["log10_p"][0]
    with pytest.raises(GridError, match="'log10_p' must be strictly ascending"):
        load_grid(bad2)


def test_not_hdf5_and_missing(tmp_path):
    p = tmp_path / "text.nc"
    p.write_text("hello")
    with pytest.raises(GridError, match="corrupt or truncated"):
        load_grid(p)
    with pytest.raises(InputError, match="not a shipped grid name"):
        load_grid(tmp_path / "does-not-exist.nc")


def test_npz_through_load_grid(tmp_path):
    g = make_grid()
    path = g.save_npz(tmp_path / "g.npz")
    assert load_grid(path).hash == g.hash, "load_grid accepts the FMU's npz archives too"


def test_incomplete_grid_not_written(tmp_path):
    g = FrictionGrid.from_arrays([1e-3, 1.0], [280.0, 300.0], [1e5, 2e5],
                                 {n: np.ones((2, 2, 2)) for n in ("mu_cold", "mu_hot",
                                                                  "dT_flash")},
                                 s0_m=1e-4, D_m=1e-3)
    with pytest.raises(GridError, match="needs every variable"):
        save_grid(g, tmp_path / "x.nc")
    assert not list(tmp_path.iterdir()), "nothing (not even a temporary file) is left behind"


def test_default_name_resolves():
    try:
        path = resolve_grid_path("default")
    except InputError:
        pytest.skip("the default grid has not been built yet")
    assert path.name in ("default.nc", "default.npz")


def test_float32_exact_content_stored_as_float32(tmp_path):
    from lookup.grid.reader import round_to_float32

    g = make_grid()
    g32 = FrictionGrid(g.log10_v, g.T, g.log10_p,
                       {n: round_to_float32(a) for n, a in g.variables.items()},
                       {k: v for k, v in g.meta.items() if k != "hash"})
    path = save_grid(g32, tmp_path / "g32.nc")
    with h5py.File(path, "r") as f:
        assert f["mu_cold"].dtype == np.float32, "float32-exact values are stored as float32"
        assert f["log10_v"].dtype == np.float64, "axes stay float64"
    h = load_grid(path)
    assert h.hash == g32.hash, "hash identical after float32 storage"
    assert h["mu_cold"].dtype == np.float64, "read back as float64"
    npz = g32.save_npz(tmp_path / "g32.npz")
    assert FrictionGrid.load_npz(npz).hash == g32.hash
