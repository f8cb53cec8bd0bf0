"""Every command in the README is run here, in order, in a scratch folder holding
copies of models/ and examples/ (the way a user runs them from a checkout).

Blocks: ``csv``/``toml`` blocks whose first line is ``# file: NAME`` are written to that file;
``bash`` blocks run with ``bash -e``; ``python`` blocks run with the interpreter; a block
preceded by ``<!-- readme-test: slow -->`` is marked slow. The set-up block and the test
command are not re-run here: the test checks that ``.ci/run`` runs exactly them.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

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


RUNNABLE = [(lang, body, mark) for i, (lang, body, mark) in enumerate(_blocks())
            if lang in ("bash", "python") and i not in (0, 2)]


def _id(block: tuple[str, str, str]) -> str:
    return block[1].strip().splitlines()[0][:60]


@pytest.mark.parametrize(
    "lang,body,mark",
    [pytest.param(*b, marks=pytest.mark.slow) if b[2] == "slow" else b for b in RUNNABLE],
    ids=[_id(b) for b in RUNNABLE])
def test_readme_block_runs(workdir: Path, lang: str, body: str, mark: str) -> None:
    env = dict(os.environ, MPLBACKEND="Agg")
    if lang == "bash":
        cmd = ["bash", "-e", "-o", "pipefail", "-c", body]
    else:
        cmd = [sys.executable, "-c", body]
    r = subprocess.run(cmd, cwd=workdir, env=env, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, f"README block failed:\n{body}\nstdout:\n{r.stdout[-3000:]}\n" \
                              f"stderr:\n{r.stderr[-3000:]}"
