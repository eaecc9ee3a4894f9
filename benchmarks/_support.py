"""Set-up shared by the benchmark scripts: the repository root on ``sys.path`` (so that
``tests.reference`` and the checkout's ``diffsense`` import when a script is run as
``python benchmarks/<name>.py`` from anywhere), the ``--quick`` flag, the check for the optional
``bench`` extras, and a median timer.

Modules whose name starts with an underscore are helpers, not benchmarks: the test that runs every
benchmark with ``--quick`` (``tests/test_benchmarks_quick.py``) leaves them out.
"""

from __future__ import annotations

import importlib.util
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

#: exit status of a benchmark whose optional packages are not installed
MISSING_EXTRAS_EXIT = 3
#: the first words of the message printed then (the quick-run test looks for them)
MISSING_EXTRAS_MESSAGE = "missing optional packages"
QUICK_HELP = "tiny sizes (few rounds, small batches): checks in well under a minute that the benchmark runs"


def require(script: str, *modules: str) -> None:
    """Exit with :data:`MISSING_EXTRAS_EXIT` and a message naming the install command unless every
    module in ``modules`` can be imported."""
    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if missing:
        print(f"{script}: {MISSING_EXTRAS_MESSAGE} {missing}; install the benchmark extras with "
              "pip install -e '.[bench]'", file=sys.stderr)
        sys.exit(MISSING_EXTRAS_EXIT)


def median_time(fn, repeats: int) -> float:
    """Median wall time in seconds of ``repeats`` calls of ``fn``."""
    ts = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return float(np.median(ts))
