"""The ``[trade]`` section: several objectives traded against each other (a Pareto front)::

    [trade]
    objectives = ["peak_power_w", "antenna_diameter_m"]   # two or more; each a parameter, an
                                                          # output, "cost", a weighted-sum table
                                                          # { a = 1.0, cost = 0.1 }, or
                                                          # { maximize = "..." } / { minimize = ... }
    points = 30                                           # points on the front (default 30)
    [trade.variables.range_m]                             # optional: a fixed parameter freed
    lower = "100 m"                                       # for the trade, same keys as
    upper = "1 km"                                        # [variables.<name>]

``diffsense optimize`` ignores the section; ``diffsense trade`` traces the front
(:mod:`diffsense.design.trade`). Every objective is checked like ``[objective]``
(:mod:`.objective`), against the spec's parameters and outputs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Mapping, Optional, Tuple

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.common import is_number, optional_table, reject_unknown
from diffsense.design.spec.objective import read_objective
from diffsense.design.spec.types import Objective, Variable
from diffsense.design.spec.variables import read_variables
from diffsense.errors import SpecError

TRADE_KEYS = {"objectives", "points", "variables", "doc"}
#: default number of points on a front
DEFAULT_POINTS = 30


@dataclass(frozen=True)
class Trade:
    """A validated ``[trade]`` section: the objectives (each an :class:`Objective`: its terms,
    +1 minimise / −1 maximise, a text), the number of points and the parameters it frees."""

    objectives: Tuple[Objective, ...]
    points: int
    variables: Dict[str, Variable]


def _objective(file, key: str, item, cases: Cases) -> Objective:
    """One objective of the list, read as ``[objective]`` reads its ``minimize``/``maximize``."""
    if isinstance(item, dict) and len(item) == 1 and next(iter(item)) in ("minimize", "maximize"):
        table = dict(item)
    elif isinstance(item, (str, dict)):
        table = {"minimize": item}
    else:
        raise SpecError(file, key, "must be a name, a table of name = weight, or { maximize = ... }")
    try:
        return read_objective(file, {"objective": table}, cases)
    except SpecError as exc:
        raise SpecError(file, key, exc.problem) from None


def read_trade(file, raw: Mapping, cases: Cases, chosen) -> Optional[Trade]:
    """The ``[trade]`` section, or None when absent; ``chosen``: parameters already set by the
    designer (a freed parameter must not be one of them).

    >>> from diffsense.design.spec import parse_spec
    >>> spec = parse_spec({"sensor": "sonar", "parts": ["sea_noise"], "options": {"absorption": "book"},
    ...     "fixed": {"range_m": "500 m", "freq_hz": "117 kHz"},
    ...     "variables": {"electrical_power_w": {"lower": "10 W", "upper": "5 kW"}},
    ...     "requirements": [{"output": "snr_margin_db", "at_least": "0 dB"}],
    ...     "objective": {"minimize": "electrical_power_w"},
    ...     "trade": {"objectives": ["electrical_power_w", {"maximize": "range_m"}], "points": 12,
    ...               "variables": {"range_m": {"lower": "100 m", "upper": "2 km"}}}})
    >>> [o.text for o in spec.trade.objectives], spec.trade.points, sorted(spec.trade.variables)
    (['minimize electrical_power_w', 'maximize range_m'], 12, ['range_m'])
    """
    if "trade" not in raw:
        return None
    table = optional_table(file, raw, "trade")
    reject_unknown(file, "trade.", table, TRADE_KEYS)
    items = table.get("objectives")
    if not isinstance(items, list) or len(items) < 2:
        raise SpecError(file, "trade.objectives", "must be a list of at least two objectives")
    objectives = tuple(_objective(file, f"trade.objectives[{i}]", it, cases) for i, it in enumerate(items))
    points = table.get("points", DEFAULT_POINTS)
    if not is_number(points) or int(points) != points or points < 2:
        raise SpecError(file, "trade.points", f"must be an integer of at least 2; got {points!r}")
    try:
        variables, catalogs = read_variables(file, {"variables": optional_table(file, table, "variables")}, cases)
    except SpecError as exc:
        raise SpecError(file, f"trade.{exc.key}", exc.problem) from None
    if catalogs:
        raise SpecError(file, f"trade.variables.{next(iter(catalogs))}", "a trade frees parameters between "
                        "bounds; catalogs belong in [variables] or [choices]")
    for name in variables:
        if name in chosen:
            raise SpecError(file, f"trade.variables.{name}", "already a design variable or catalog parameter")
    return Trade(objectives, int(points), variables)
