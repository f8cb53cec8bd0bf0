"""Every command in the README is run here, in order, in a scratch folder holding
copies of models/ and examples/ (the way a user runs them from a checkout).

Blocks: ``csv``/``toml`` blocks whose first line is ``# file: NAME`` are written to that file;
``bash`` blocks run with ``bash -e``; ``python`` blocks run with the interpreter; a block
preceded by ``<!-- readme-test: slow -->`` is marked slow, one preceded by
``<!-- readme-test: skip (reason) -->`` is not run. A ``text`` block preceded by
``<!-- readme-test: prints rtol=R atol=A -->`` is what the block before it prints: each of its
lines must appear in the run's output, in order, with the same words and every number within
``|got - want| <= A + R |want|`` (the README states the reason for the tolerances). The set-up
block and the test command are not re-run here: the test checks that ``.ci/run`` runs exactly
them.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
BLOCK = re.compile(r"(?:<!-- readme-test: (?P<mark>[^>]*?) -->\s*\n)?```(?P<lang>\w+)\n"
                   r"(?P<body>.*?)```", re.S)


def _blocks() -> list[tuple[str, str, str]]:
    return [(m["lang"], m["body"], m["mark"] or "") for m in BLOCK.finditer(README)]


SETUP, TESTS = _blocks()[0][1].strip(), _blocks()[2][1].strip()


def test_ci_runs_the_readme_setup_and_test_command() -> None:
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert 'pip install ".[test]"' in SETUP and "python3 -m venv" in SETUP
    assert any("python3 -m venv" in line for line in ci), "CI makes a fresh venv"
    assert any(re.search(r'pip install (--quiet )?"\.\[test\]"', line) for line in ci)
    assert TESTS == "pytest"
    assert TESTS in [line.strip() for line in ci], "CI runs exactly the README's test command"
    assert "export TIREFRIC_EXPECT_COPY=installed" in ci, "CI checks it tests the installed copy"
    dev = README[README.index("## Development"):]
    assert 'pip install -e ".[test]"' in dev, "development uses an editable install"


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("readme")
    shutil.copytree(ROOT / "models", d / "models")
    shutil.copytree(ROOT / "examples", d / "examples")
    for lang, body, _ in _blocks():
        first = body.splitlines()[0] if body else ""
        if lang in ("csv", "toml") and first.startswith("# file: "):
            (d / first.removeprefix("# file: ").strip()).write_text(body)
    return d


def _expected(i: int) -> tuple[str, float, float] | None:
    """The ``prints`` block after block ``i``: (text, rtol, atol), or None."""
    blocks = _blocks()
    if i + 1 >= len(blocks) or blocks[i + 1][0] != "text":
        return None
    mark = blocks[i + 1][2]
    if not mark.startswith("prints"):
        return None
    tol = dict(kv.split("=") for kv in mark.split()[1:])
    return blocks[i + 1][1], float(tol["rtol"]), float(tol["atol"])


RUNNABLE = [(lang, body, mark, _expected(i)) for i, (lang, body, mark) in enumerate(_blocks())
            if lang in ("bash", "python") and i not in (0, 2) and not mark.startswith("skip")]

NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def check_printed(out: str, expected: str, rtol: float, atol: float) -> None:
    """Every expected line appears in ``out`` in order: same words, numbers within tolerance."""
    lines = out.splitlines()
    k = 0
    for want in filter(str.strip, expected.splitlines()):
        skeleton = NUMBER.sub("#", want).split()
        while k < len(lines) and NUMBER.sub("#", lines[k]).split() != skeleton:
            k += 1
        assert k < len(lines), f"README output line not printed (in order): {want!r}\n{out}"
        got = np.array([float(x) for x in NUMBER.findall(lines[k])])
        exp = np.array([float(x) for x in NUMBER.findall(want)])
        np.testing.assert_allclose(got, exp, rtol=rtol, atol=atol,
                                   err_msg=f"README prints {want!r}, the run {lines[k]!r}")
        k += 1


def test_check_printed_fails_on_a_wrong_number() -> None:
    check_printed("a 1.0 b\nmu 2.000 x\n", "mu 2.001 x", 1e-3, 0.0)
    with pytest.raises(AssertionError):
        check_printed("mu 2.000 x\n", "mu 2.01 x", 1e-3, 0.0)
    with pytest.raises(AssertionError):
        check_printed("mu 2.000 x\n", "nu 2.000 x", 1e-3, 0.0)


def _id(block: tuple) -> str:
    return block[1].strip().splitlines()[0][:60]


@pytest.mark.parametrize(
    "lang,body,mark,expected",
    [pytest.param(*b, marks=pytest.mark.slow) if b[2] == "slow" else b for b in RUNNABLE],
    ids=[_id(b) for b in RUNNABLE])
def test_readme_block_runs(workdir: Path, lang: str, body: str, mark: str,
                           expected: tuple[str, float, float] | None) -> None:
    # the commands (``tirefric``, ``python``) of the interpreter running the tests come first,
    # or a bash block could run another installation's tirefric than the one under test
    path = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    env = dict(os.environ, MPLBACKEND="Agg", PATH=path)
    if lang == "bash":
        cmd = ["bash", "-e", "-o", "pipefail", "-c", body]
    else:
        cmd = [sys.executable, "-c", body]
    r = subprocess.run(cmd, cwd=workdir, env=env, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, f"README block failed:\n{body}\nstdout:\n{r.stdout[-3000:]}\n" \
                              f"stderr:\n{r.stderr[-3000:]}"
    if expected is not None:
        check_printed(r.stdout, *expected)
