"""The ``[objective]`` section: what the optimizer minimises or maximises::

    [objective]
    minimize = "antenna_diameter_m"                    # a parameter, an output or "cost"
    # or a weighted sum: minimize = { antenna_diameter_m = 1.0, cost = 0.1 }
    # or maximize = "<name>"; with several cases "<case>.<name>" (default: the first case)
    reach_goals = true      # optional: then buy the requirements' goals, cheapest first

"cost" is the summed cost of the chosen catalog options. With ``reach_goals = true`` the optimiser
first meets every threshold, then raises requirements to their goals (``goal = "..."``) one at a
time, each time the one that costs the least objective, while the design stays feasible
(:mod:`diffsense.design.goals`); at most :data:`MAX_GOALS` goals (the re-solves grow as their square).
"""

from __future__ import annotations

from typing import List, Mapping, Tuple

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.common import closest, echo, key_text, reject_unknown, split_case, weight_number
from diffsense.design.spec.types import Objective
from diffsense.errors import SpecError
from diffsense.scene import describe_command

OBJECTIVE_KEYS = {"minimize", "maximize", "doc", "reach_goals"}
#: goals ``reach_goals`` may buy: the optimiser re-solves at most MAX_GOALS (MAX_GOALS + 1) / 2 times
MAX_GOALS = 6


def read_objective(file, raw: Mapping, cases: Cases) -> Objective:
    """The objective: its terms (name, weight), sign (+1 minimise, −1 maximise) and a text.

    >>> from diffsense.design.spec import parse_spec
    >>> spec = parse_spec({"sensor": "sonar", "parts": ["sea_noise"], "options": {"absorption": "book"},
    ...     "fixed": {"range_m": "500 m", "freq_hz": "117 kHz"},
    ...     "variables": {"electrical_power_w": {"lower": "10 W", "upper": "5 kW"}},
    ...     "requirements": [{"output": "snr_margin_db", "at_least": "0 dB"}],
    ...     "objective": {"maximize": {"snr_margin_db": 1.0, "electrical_power_w": -0.5}}})
    >>> spec.objective.sign, spec.objective.text
    (-1.0, 'maximize snr_margin_db + -0.5·electrical_power_w')
    """
    oraw = raw.get("objective")
    if not isinstance(oraw, dict):
        raise SpecError(file, "objective", "missing: give [objective] minimize = ... or maximize = ...")
    reject_unknown(file, "objective.", oraw, OBJECTIVE_KEYS)
    senses = [s for s in ("minimize", "maximize") if s in oraw]
    if len(senses) != 1:
        raise SpecError(file, "objective", "needs exactly one of 'minimize' or 'maximize'")
    sense = senses[0]
    terms = _terms(file, sense, oraw[sense])
    first = next(iter(cases.scenes))
    for tname, _ in terms:
        if tname == "cost":
            continue
        case, base = split_case(file, f"objective.{sense}", tname, cases.scenes, default=first)
        known = set(cases.parameters[case]) | set(cases.outputs[case])
        if base not in known:
            raise SpecError(file, f"objective.{sense}", f"unknown parameter or output {echo(tname, 60)}"
                            f"{closest(base, known)}; run '{describe_command(cases.scenes[case])}' for them all")
    reach = oraw.get("reach_goals", False)
    if not isinstance(reach, bool):
        raise SpecError(file, "objective.reach_goals", f"must be true or false; got {echo(reach)}")
    return Objective(tuple(terms), 1.0 if sense == "minimize" else -1.0,
                     f"{sense} " + " + ".join(f"{w:g}·{n}" if w != 1 else n for n, w in terms), reach)


def check_goals(file, objective: Objective, requirements) -> None:
    """``reach_goals = true`` needs between 1 and :data:`MAX_GOALS` requirements with a goal."""
    if not objective.reach_goals:
        return
    goals = [r.name for r in requirements if r.goal is not None]
    if not goals:
        raise SpecError(file, "objective.reach_goals", "no requirement has a goal: add goal = \"...\" beside a "
                        "requirement's at_least / at_most, or remove reach_goals")
    if len(goals) > MAX_GOALS:
        raise SpecError(file, "objective.reach_goals", f"{len(goals)} requirements have goals; at most {MAX_GOALS} "
                        f"can be bought in order of cost (the re-solves grow as the square of their number)")


def _terms(file, sense: str, obj) -> List[Tuple[str, float]]:
    if isinstance(obj, str):
        return [(obj, 1.0)]
    if isinstance(obj, dict) and obj:
        terms = []
        for k, w in obj.items():
            terms.append((k, weight_number(file, f"objective.{sense}.{key_text(k)}", w)))
        return terms
    raise SpecError(file, f"objective.{sense}", f"must be a name or a table of name = weight; got {echo(obj)}")
