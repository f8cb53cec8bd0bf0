"""The TOML writer (tirefric.toml_writer) writes what tomllib reads back unchanged: every
shipped model file, and the strings, numbers and keys that need escaping."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

from tirefric.errors import InputError
from tirefric.paths import models_dir
from tirefric.toml_writer import dumps

SHIPPED = sorted(models_dir().rglob("*.toml"))


@pytest.mark.parametrize("path", SHIPPED, ids=[p.name for p in SHIPPED])
def test_shipped_files_round_trip(path) -> None:
    data = tomllib.loads(path.read_text())
    assert tomllib.loads(dumps(data)) == data


def test_awkward_values_round_trip() -> None:
    data = {
        "plain": "x", "quotes": 'say "hi"', "backslash": r"C:\data\mu.csv",
        "multi": "line one\nline two with \"quotes\"\n", "ends_in_quote": 'a\nb"',
        "triple": 'a\n"""b', "control": "tab\there\x01", "unicode": "20 °C, Ø 1 mm",
        "float": 0.1 + 0.2, "tiny": 5e-324, "big": 1.7976931348623157e308, "neg": -0.0,
        "int": -3, "bool": False, "list": [1.5, "a", [2, 3]],
        "key with space": 1, "dotted.key": 2, "ü": 3,
        "table": {"sub": {"x": 1.0}, "y": "z"},
        "arr": [{"a": 1}, {"a": 2, "b": {"c": "d"}}],
    }
    back = tomllib.loads(dumps(data, header="a header\nsecond line"))
    assert back == data
    assert math.copysign(1.0, back["neg"]) == -1.0


def test_special_floats_and_numpy_scalars() -> None:
    back = tomllib.loads(dumps({"nan": float("nan"), "inf": float("inf"),
                                "minf": -float("inf"), "np": np.float64(0.22),
                                "npi": np.int64(7), "arr": [np.float64(1.5)]}))
    assert math.isnan(back["nan"]) and back["inf"] == math.inf and back["minf"] == -math.inf
    assert back["np"] == 0.22 and type(back["np"]) is float
    assert back["npi"] == 7 and back["arr"] == [1.5]


def test_unwritable_values_are_refused() -> None:
    with pytest.raises(InputError, match="cannot write a object"):
        dumps({"x": object()})
