"""The mutation check (``python tests/mutations.py``) as a slow test: every planted physics
error of :data:`mutations.MUTATIONS` must make the fast suite fail."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from mutations import MUTATIONS, check_patches

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_patch_list_applies() -> None:
    assert check_patches(MUTATIONS) == [], "each old text must occur exactly once"


@pytest.mark.slow
def test_every_mutation_is_caught() -> None:
    r = subprocess.run([sys.executable, str(ROOT / "tests" / "mutations.py")], cwd=ROOT,
                       capture_output=True, text=True, timeout=3600)
    assert r.returncode == 0, f"a mutation survived:\n{r.stdout}\n{r.stderr[-2000:]}"
    assert f"{len(MUTATIONS)}/{len(MUTATIONS)} caught" in r.stdout
