"""The errors diffsense raises on bad input, in one public module.

* :class:`DomainError` — an argument of a model lies outside its documented domain (raised at
  the API edge for concrete values; see :mod:`diffsense.numerics.checks`).
* :class:`UnitError` — a quantity string that the units registry cannot read or convert.
* :class:`SpecError` — an invalid requirement spec, naming the file, the key and the problem.

All three derive from :class:`ValueError`, so ``except ValueError`` catches any of them.
"""

from __future__ import annotations


class DomainError(ValueError):
    """An argument lies outside the documented domain of a model."""


class UnitError(ValueError):
    """A quantity could not be read or converted to the required unit."""


class SpecError(ValueError):
    """An invalid requirement spec: ``file``, ``key`` (dotted path) and what is wrong."""

    def __init__(self, file, key: str, problem: str):
        self.file = str(file)
        self.key = key
        self.problem = problem
        where = f"key '{key}': " if key else ""
        super().__init__(f"{self.file}: {where}{problem}")
