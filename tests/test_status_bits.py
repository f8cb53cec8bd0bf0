"""The native wrapper's status-bit literals agree with the table of the pythonfmu flavour.

fmu_src/runtime/native/fmu_wrapper.c carries the input guard's bits (GUARD_BIT, GUARD_NAME) and
the model's (MODEL_BIT, MODEL_NAME, MODEL_FLAG) as C literals, duplicated from
fmu_src/runtime/interface.py (STATUS_BITS, MODEL_FLAGS) until a refactor generates them; this
test keeps the two in step.
"""

from __future__ import annotations

import re
from pathlib import Path

from fmu_src.runtime.interface import MODEL_FLAGS, STATUS_BITS

WRAPPER = Path(__file__).parents[1] / "fmu_src" / "runtime" / "native" / "fmu_wrapper.c"
CORE_H = Path(__file__).parents[1] / "tire_brush" / "csrc" / "tirecore.h"


def _array(text: str, name: str) -> list[str]:
    """The initialiser of the C array ``name`` in ``text``, split at commas."""
    m = re.search(rf"{name}\[[A-Z_]+\]\s*=\s*\{{(.*?)\}};", text, re.S)
    assert m, name
    return [x.strip().strip('"') for x in m.group(1).split(",") if x.strip()]


def test_guard_bits_match_status_bits() -> None:
    c = WRAPPER.read_text()
    names, bits = _array(c, "GUARD_NAME"), [int(b) for b in _array(c, "GUARD_BIT")]
    assert len(names) == len(bits)
    for name, bit in zip(names, bits, strict=True):
        assert STATUS_BITS[name.partition(":")[0]] == bit, name


def test_model_bits_match_status_bits_and_core_flags() -> None:
    c, h = WRAPPER.read_text(), CORE_H.read_text()
    flags = {f: int(re.search(rf"#define {f} (\d+)", h).group(1))
             for f in _array(c, "MODEL_FLAG")}
    names, bits = _array(c, "MODEL_NAME"), [int(b) for b in _array(c, "MODEL_BIT")]
    for flag, name, bit in zip(flags.values(), names, bits, strict=True):
        assert MODEL_FLAGS[flag] == name and STATUS_BITS[name] == bit, name
    assert len(names) == len(MODEL_FLAGS)
    # every bit is a distinct power of two
    values = sorted(STATUS_BITS.values())
    assert values == [1 << k for k in range(len(values))]
