"""``tirefric label``: the EU tyre label's classes (Regulation (EU) 2020/740, Annex I, C1)
at their edges, and the command on the shipped tire."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tire_brush.label import JSON_KEYS, label_classes
from tire_brush.rolling_resistance import eu_label_class
from tire_brush.wet_grip import label_class

# (value, class) at and around every edge: G is classed to two decimals (A >= 1.55,
# B 1.40-1.54, C 1.25-1.39, D 1.10-1.24, E <= 1.09), the RRC to one (A <= 6.5, B 6.6-7.7,
# C 7.8-9.0, D 9.1-10.5, E >= 10.6 N/kN); a value rounds half up to the class's digits
G_EDGES = [(1.55, "A"), (1.545, "A"), (1.5449, "B"), (1.54, "B"), (1.40, "B"), (1.395, "B"),
           (1.3949, "C"), (1.39, "C"), (1.25, "C"), (1.2449, "D"), (1.24, "D"), (1.10, "D"),
           (1.0949, "E"), (1.09, "E"), (0.5, "E"), (2.0, "A")]
RRC_EDGES = [(6.5, "A"), (6.549, "A"), (6.55, "B"), (6.6, "B"), (7.7, "B"), (7.749, "B"),
             (7.75, "C"), (7.8, "C"), (9.0, "C"), (9.049, "C"), (9.05, "D"), (9.1, "D"),
             (10.5, "D"), (10.549, "D"), (10.55, "E"), (10.6, "E"), (0.0, "A"), (25.0, "E")]


@pytest.mark.parametrize("G,cls", G_EDGES)
def test_wet_grip_class_edges(G, cls):
    assert label_class(G) == cls


@pytest.mark.parametrize("rrc,cls", RRC_EDGES)
def test_fuel_efficiency_class_edges(rrc, cls):
    assert eu_label_class(rrc) == cls


def test_label_json_on_the_shipped_tire(tmp_path):
    """The command on the shipped passenger tire: the documented keys, classes that follow
    from the printed numbers, the noise not modelled, the label drawn when asked."""
    svg = tmp_path / "label.svg"
    out = subprocess.run([sys.executable, "-m", "tirefric.cli", "label", "--tire", "passenger",
                          "--json", "--svg", str(svg)], capture_output=True, text=True,
                         check=True)
    doc = json.loads(out.stdout)
    assert tuple(doc) == JSON_KEYS
    w, r = doc["wet_grip"], doc["rolling_resistance"]
    assert w["class"] == label_class(w["G"]) and r["class"] == eu_label_class(r["rrc_N_per_kN"])
    assert w["G"] == pytest.approx(1.25 * w["bfc_candidate"] / w["bfc_reference"], rel=1e-12)
    assert 0.5 < w["G"] < 2.0 and 0.0 < r["rrc_N_per_kN"] < 40.0
    assert (r["load_N"], r["inflation_Pa"]) == pytest.approx((0.8 * 6031.0, 210e3))
    assert doc["noise"] == {"class": None, "level_dB": None, "modelled": False}
    assert doc["tire"] == "passenger" and doc["tyre_class"] == "C1" and doc["grid"] == "r117_wet"
    if doc["label_svg"] is None:  # drawing is optional: the package is not installed
        assert any("tyre-energy-label" in n for n in doc["notes"])
    else:
        text = svg.read_text()
        assert text.startswith("<") and "205/55 R16 91" in text
        kw = label_classes(doc)
        assert kw["noise_level"] == "" and kw["roll_noise"] == "--"
