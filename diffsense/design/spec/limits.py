"""The work a spec may ask for, estimated and refused past stated ceilings when it is read,
before anything is traced or compiled.

Counts of the spec's own entries:

========================================  =====================================================
requirements                              at most :data:`MAX_REQUIREMENTS`
options of one catalog                    at most :data:`MAX_CATALOG_OPTIONS`
catalog combinations (product)            at most :data:`MAX_COMBINATIONS`
parameters of one ``over`` box            at most :data:`MAX_OVER_PARAMETERS`
search-grid points of one ``over`` box    at most :data:`MAX_GRID_POINTS` (``over_points``\\ :sup:`d`)
``[uncertain] samples``                   64 … :data:`MAX_SAMPLES`
``[uncertain] check_samples``             100,000 … :data:`MAX_CHECK_SAMPLES`
``[trade] points``                        2 … :data:`MAX_TRADE_POINTS`
``[trade] objectives``                    2 … :data:`MAX_TRADE_OBJECTIVES`
========================================  =====================================================

and the **chain evaluations** one call of a program makes (:func:`work`), each at most
:data:`MAX_CHAIN_EVALUATIONS`:

* the solver's lane program: lanes × (cases + interval slots + design samples), with lanes =
  catalog combinations × starts, an interval requirement's slots its ``over_worst`` points and
  one point found earlier, and the design sample ``samples`` once per case with a requirement
  met with a probability;
* the dense re-check of the interval requirements: Σ over them of the dense grid,
  (⌈10,001^(1/d)⌉ + 1)^d points for a box of d parameters;

and for a trade, the ε-constraint solves: combinations × (objectives + grid points of the
front), at most :data:`MAX_TRADE_SOLVES`. Each refusal names the key that asks for the work and
the figure. The ceilings keep the largest program's arrays to a few hundred megabytes for the
heaviest chain shipped (memory grows about linearly with the evaluations of one call).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from diffsense.errors import SpecError
from diffsense.optimize.semi_infinite import default_counts, dense_size

MAX_REQUIREMENTS = 256
MAX_CATALOG_OPTIONS = 256
MAX_COMBINATIONS = 1024
MAX_OVER_PARAMETERS = 3
MAX_GRID_POINTS = 1 << 17
MAX_SAMPLES = 1 << 16
MAX_CHECK_SAMPLES = 10_000_000
MAX_TRADE_POINTS = 200
MAX_TRADE_OBJECTIVES = 4
MAX_TRADE_SOLVES = 4096
MAX_CHAIN_EVALUATIONS = 1_000_000
#: the starts per catalog combination of ``diffsense optimize`` unless ``--starts`` says otherwise
DEFAULT_STARTS = 8
#: points of the dense re-check of one interval requirement (before rounding up to a grid;
#: :mod:`diffsense.design.intervals` re-checks with this many)
DENSE_POINTS = 10_001


class Work(NamedTuple):
    """Chain evaluations of one call of a program, and the spec key that asks for most of them."""

    evaluations: int
    key: str
    what: str


def grid_points(r) -> int:
    """Search-grid points of the ``over`` box of requirement ``r`` (0 without ``over``)."""
    d = len(r.over)
    if not d:
        return 0
    return math.prod(default_counts(d)) if r.over_points is None else r.over_points ** d


def combinations(spec) -> int:
    """Catalog combinations of ``spec``: the product of its catalogs' option counts."""
    return math.prod(len(c.option_names) for c in spec.choices.values())


def work(spec, starts: int = DEFAULT_STARTS):
    """``(lane program, dense re-check)`` as :class:`Work`: the chain evaluations of one call."""
    interval = [(i, r) for i, r in enumerate(spec.requirements) if r.over]
    chance_cases = {r.case for r in spec.requirements if r.probability is not None}
    samples = spec.uncertain.samples if spec.uncertain is not None and chance_cases else 0
    slots = sum(r.over_worst + 1 for _, r in interval)
    per_lane = len(spec.scenes) + slots + samples * len(chance_cases)
    lanes = combinations(spec) * starts
    if samples * len(chance_cases) >= slots + len(spec.scenes):
        key = "uncertain.samples"
    elif slots > len(spec.scenes):
        key = f"requirements[{max(interval, key=lambda ir: ir[1].over_worst)[0]}].over_worst"
    else:
        key = "variables"
    lane = Work(lanes * per_lane, key, f"the solver ({lanes} lanes x {per_lane} evaluations)")
    dense = sum(dense_size(len(r.over), DENSE_POINTS) for _, r in interval)
    check = Work(dense, "requirements", f"the dense re-check of {len(interval)} interval requirements")
    return lane, check


def check_counts(file, spec) -> None:
    """Raise :class:`SpecError` for a count of the spec's entries past its ceiling."""
    if len(spec.requirements) > MAX_REQUIREMENTS:
        raise SpecError(file, "requirements", f"{len(spec.requirements)} requirements; at most {MAX_REQUIREMENTS} "
                        "are allowed (combine requirements on one output into its tightest limit)")
    for name, c in spec.choices.items():
        if len(c.option_names) > MAX_CATALOG_OPTIONS:
            where = f"variables.{name}.choices" if len(c.settings[0]) == 1 and name in c.settings[0] else \
                f"choices.{name}.options"
            raise SpecError(file, where, f"{len(c.option_names)} options; at most {MAX_CATALOG_OPTIONS} per catalog "
                            "(a continuous variable between bounds covers a dense range)")
    combos = combinations(spec)
    if combos > MAX_COMBINATIONS:
        sizes = " x ".join(str(len(c.option_names)) for c in spec.choices.values())
        raise SpecError(file, "variables", f"the catalogs make {combos:,} combinations ({sizes}); at most "
                        f"{MAX_COMBINATIONS:,} are allowed (make a catalog a continuous variable, or drop options)")
    for i, r in enumerate(spec.requirements):
        if len(r.over) > MAX_OVER_PARAMETERS:
            raise SpecError(file, f"requirements[{i}].over", f"a box of {len(r.over)} parameters; at most "
                            f"{MAX_OVER_PARAMETERS} are allowed (split the requirement, or fix the parameters "
                            "that matter least at their worst values)")
        points = grid_points(r)
        if points > MAX_GRID_POINTS:
            key = f"requirements[{i}].over_points" if r.over_points else f"requirements[{i}].over"
            raise SpecError(file, key, f"the search grid has {points:,} points; at most {MAX_GRID_POINTS:,} are "
                            "allowed (fewer over_points: the search polishes between grid points)")


def check_work(file, spec, starts: int = DEFAULT_STARTS, starts_key: str = "") -> None:
    """Raise :class:`SpecError` when one program call would make more than
    :data:`MAX_CHAIN_EVALUATIONS` chain evaluations (``starts_key``: the key to name instead of
    the spec's, e.g. the ``--starts`` option of a spec already checked at the default starts)."""
    for w in work(spec, starts):
        if w.evaluations > MAX_CHAIN_EVALUATIONS:
            key = starts_key or w.key
            raise SpecError(file, key, f"{w.what} would make {w.evaluations:,} chain evaluations per step; "
                            f"at most {MAX_CHAIN_EVALUATIONS:,} are allowed")


def trade_solves(spec, points: int) -> int:
    """ε-constraint solves of a trade of ``points`` points: per combination, one anchor per
    objective and the front's grid (``points`` for two objectives, ⌈points^(1/(K−1))⌉^(K−1) for K)."""
    k = len(spec.trade.objectives)
    per_axis = points if k == 2 else math.ceil(points ** (1.0 / (k - 1)) - 1e-9)
    return combinations(spec) * (k + per_axis ** (k - 1))


def check_trade_work(file, spec, points: int, key: str = "trade.points") -> None:
    """Raise :class:`SpecError` when the trade would run more than :data:`MAX_TRADE_SOLVES` solves."""
    solves = trade_solves(spec, points)
    if solves > MAX_TRADE_SOLVES:
        raise SpecError(file, key, f"the front of {points} points over {combinations(spec)} catalog combinations "
                        f"needs {solves:,} solves; at most {MAX_TRADE_SOLVES:,} are allowed")


def require_variables(spec) -> None:
    """Raise :class:`SpecError` for a spec with nothing to optimise (no variable, no catalog):
    ``diffsense evaluate`` checks such a fixed design, ``optimize``, ``report`` and ``trade`` refuse it."""
    if not spec.variables and not spec.choices:
        raise SpecError(spec.path, "variables", "nothing to optimise: the spec has no [variables.<name>] and no "
                        "catalog; add one, or check the fixed design with 'diffsense evaluate'")
