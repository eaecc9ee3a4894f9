"""The ``over`` key of a requirement: the requirement holds at every point of an interval of a
parameter, or of a box of several::

    [[requirements]]
    output = "sea_skimmer.detection_margin_db"
    at_least = "0 dB"
    over.range_m = ["50 m", "12 km"]                 # every range in the interval
    over.target_height_m = { from = "3 m", to = "30 m", log = false }   # and every height: a box
    over_points = 129                                # optional: search-grid points per parameter

Each parameter of ``over`` is a fixed parameter of the requirement's case (not a design
variable nor a catalog setting): its fixed value is replaced by every value of the interval.
Bounds are in any unit of the parameter, ``from < to``, both inside the model's domain. ``log``
(optional) grids the interval in log p; by default log spacing is used where the interval
spans a factor of ten or more. The solver meets the requirement at the worst points of the box
(:mod:`diffsense.optimize.semi_infinite`), and every answer is re-checked on a dense grid.
"""

from __future__ import annotations

from typing import Mapping, Optional, Tuple

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.common import closest, key_text, parameter_value, reject_unknown, whole_number
from diffsense.design.spec.types import Interval
from diffsense.errors import SpecError

#: the keys of an interval written as a table
INTERVAL_KEYS = {"from", "to", "log"}
#: requirement keys this module reads
OVER_KEYS = {"over", "over_points", "over_worst"}


def read_over(file, key: str, r: Mapping, case: str, cases: Cases, design_names) -> Tuple[Tuple[Interval, ...], Optional[int], int]:
    """``(intervals, grid points per parameter or None, worst points kept)`` of requirement ``r``
    (``key`` its dotted name); ``((), None, 3)`` when it has no ``over``."""
    over = r.get("over")
    if over is None:
        for extra in ("over_points", "over_worst"):
            if extra in r:
                raise SpecError(file, f"{key}.{extra}", "only meaningful with an 'over' table")
        return (), None, 3
    if not isinstance(over, dict) or not over:
        raise SpecError(file, f"{key}.over", "must be a table of parameter = [from, to], e.g. over.range_m = [\"50 m\", \"12 km\"]")
    if r.get("equals") is not None:
        raise SpecError(file, f"{key}.equals", "an equality cannot hold over an interval; use at_least or at_most")
    table = cases.parameters[case]
    intervals = []
    for name, value in over.items():
        k = f"{key}.over.{key_text(name)}"
        if name not in table:
            raise SpecError(file, k, f"unknown parameter of case '{case}'{closest(name, table)}")
        if name in design_names:
            raise SpecError(file, k, f"'{name}' is a design variable or catalog setting; 'over' takes a fixed parameter")
        if table[name].integer:
            raise SpecError(file, k, f"'{name}' counts something (a whole number); 'over' takes a continuous "
                            "parameter (write one requirement per count, in a case each)")
        intervals.append(_interval(file, k, table[name], value))
    points = _count(file, f"{key}.over_points", r.get("over_points"), 3, 4097)
    worst = _count(file, f"{key}.over_worst", r.get("over_worst"), 1, 16)
    return tuple(intervals), points, 3 if worst is None else worst


def _interval(file, key: str, prm, value) -> Interval:
    log = None
    if isinstance(value, dict):
        reject_unknown(file, key + ".", value, INTERVAL_KEYS)
        if "from" not in value or "to" not in value:
            raise SpecError(file, key, "an interval table needs 'from' and 'to'")
        log = value.get("log")
        if log is not None and not isinstance(log, bool):
            raise SpecError(file, f"{key}.log", "must be true or false")
        ends = [value["from"], value["to"]]
    elif isinstance(value, list) and len(value) == 2:
        ends = value
    else:
        raise SpecError(file, key, "must be [from, to] or { from = ..., to = ... }")
    lo = parameter_value(file, f"{key}[0]", prm, ends[0])
    hi = parameter_value(file, f"{key}[1]", prm, ends[1])
    if not lo < hi:
        raise SpecError(file, key, f"needs from < to; got {lo:g} and {hi:g} {prm.unit}")
    if log and lo <= 0:
        raise SpecError(file, f"{key}.log", "log spacing needs a positive lower end")
    return Interval(prm.name, prm.unit, lo, hi, log)


def _count(file, key: str, value, lo: int, hi: int) -> Optional[int]:
    if value is None:
        return None
    return whole_number(file, key, value, lo, hi)
