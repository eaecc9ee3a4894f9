"""Paths of the repository that tests read: the root, the shipped designs and test data."""

from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DESIGNS = REPO / "designs"
DATA = REPO / "tests" / "data"
