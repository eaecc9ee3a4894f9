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

import math
from dataclasses import dataclass
from typing import Dict, Mapping, Optional, Tuple

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.common import optional_table, reject_unknown, whole_number
from diffsense.design.spec.limits import MAX_TRADE_OBJECTIVES, MAX_TRADE_POINTS
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
    if not isinstance(items, list) or not 2 <= len(items) <= MAX_TRADE_OBJECTIVES:
        raise SpecError(file, "trade.objectives", f"must be a list of 2 to {MAX_TRADE_OBJECTIVES} objectives")
    objectives = tuple(_objective(file, f"trade.objectives[{i}]", it, cases) for i, it in enumerate(items))
    _distinct(file, objectives)
    points = whole_number(file, "trade.points", table.get("points", DEFAULT_POINTS), 2, MAX_TRADE_POINTS)
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
    return Trade(objectives, points, variables)


def _direction(objective: Objective) -> Dict[str, float]:
    """The objective as minimised: term -> signed weight, scaled to unit length."""
    terms: Dict[str, float] = {}
    for name, weight in objective.terms:
        terms[name] = terms.get(name, 0.0) + objective.sign * weight
    norm = math.sqrt(sum(w * w for w in terms.values())) or 1.0
    return {n: w / norm for n, w in terms.items()}


def _distinct(file, objectives) -> None:
    """Raise when two objectives are the same up to a positive factor (one objective twice) or a
    negative one (exact opposites: every design would be on the front)."""
    seen = []
    for i, o in enumerate(objectives):
        d = _direction(o)
        for j, e in seen:
            if set(d) == set(e):
                dot = sum(d[n] * e[n] for n in d)
                if dot > 1.0 - 1e-12:
                    raise SpecError(file, f"trade.objectives[{i}]", f"the same objective as trade.objectives[{j}] "
                                    "(up to a factor); a trade needs objectives that conflict")
                if dot < -1.0 + 1e-12:
                    raise SpecError(file, f"trade.objectives[{i}]", f"the exact opposite of trade.objectives[{j}]: "
                                    "every design would be on the front")
        seen.append((i, d))


def check_trade(file, spec) -> None:
    """The ``[trade]`` section against the rest of ``spec``: a freed parameter is not uncertain
    and not swept by an ``over`` requirement (it would be two things at once), ``cost`` needs a
    catalog with costs, and an objective of fixed parameters only is constant."""
    trade = spec.trade
    if trade is None:
        return
    uncertain = set(spec.uncertain.parameters) if spec.uncertain is not None else set()
    for name in trade.variables:
        key = f"trade.variables.{name}"
        if name in uncertain:
            raise SpecError(file, key, f"'{name}' is uncertain ([uncertain]); a trade cannot also free it")
        for i, r in enumerate(spec.requirements):
            if any(iv.parameter == name for iv in r.over):
                raise SpecError(file, key, f"requirements[{i}] holds over an interval of '{name}' "
                                f"({r.over[0].lower:g} to {r.over[0].upper:g} {r.over[0].unit}); a trade cannot also "
                                "free it: trade another parameter, or remove 'over'")
    free = set(spec.variables) | set(trade.variables) | {p for c in spec.choices.values() for p in c.settings[0]}
    has_costs = any(any(c != 0 for c in ch.costs) for ch in spec.choices.values())
    outputs = set().union(*(spec.outputs[c] for c in spec.scenes))
    for i, o in enumerate(trade.objectives):
        key = f"trade.objectives[{i}]"
        names = [n for n, _ in o.terms]
        if "cost" in names and not has_costs:
            raise SpecError(file, key, "'cost' is the summed cost of the catalog options chosen, and no catalog of "
                            "this spec has a cost: it is 0 for every design")
        params = {n.split(".", 1)[-1] for n in names if n != "cost"}
        if not (params & outputs) and not (params & free) and not ("cost" in names and has_costs):
            raise SpecError(file, key, f"constant: {', '.join(sorted(params))} is fixed (not a design variable, "
                            "catalog or [trade.variables] parameter), so every design has the same value")
