"""Every benchmark still runs: ``python benchmarks/<name>.py --quick`` from the repository root
exits with status 0 and prints its table.

The scripts are found by globbing ``benchmarks/*.py`` (helper modules, whose names start with an
underscore, are left out), so a new benchmark is covered without touching this file. A script
that reports missing optional packages (the ``bench`` extras) is skipped with its message.
"""

import subprocess
import sys

import pytest

from benchmarks._support import MISSING_EXTRAS_EXIT, MISSING_EXTRAS_MESSAGE
from helpers.paths import REPO

SCRIPTS = sorted(p for p in (REPO / "benchmarks").glob("*.py") if not p.name.startswith("_"))


def test_benchmarks_are_found():
    assert len(SCRIPTS) >= 5, SCRIPTS


@pytest.mark.slow
@pytest.mark.parametrize("script", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_benchmark_runs_with_quick(script):
    out = subprocess.run([sys.executable, str(script.relative_to(REPO)), "--quick"], cwd=REPO,
                         capture_output=True, text=True, timeout=600)
    if out.returncode == MISSING_EXTRAS_EXIT and MISSING_EXTRAS_MESSAGE in out.stderr:
        pytest.skip(out.stderr.strip())
    assert out.returncode == 0, f"exit {out.returncode}\n{out.stdout[-2000:]}\n{out.stderr[-4000:]}"
    lines = [line for line in out.stdout.splitlines() if line.strip()]
    rows = [line for line in lines if any(ch.isdigit() for ch in line)]
    assert len(lines) >= 2 and rows, f"no table printed:\n{out.stdout}"
