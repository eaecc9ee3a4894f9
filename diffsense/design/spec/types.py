"""What a validated requirement spec holds: :class:`Spec` and its entries (:class:`Variable`,
:class:`Choice`, :class:`Requirement`, :class:`Objective`).

Every value is already converted to the unit of its chain parameter or output (SI, or dB where
the chain's table says so); see :mod:`diffsense.design.spec` for the TOML format.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Tuple

from diffsense.scene import Scene
from diffsense.sensors.chain import Output, Param

#: the senses of a requirement: the output must be at least / at most / equal to the limit
SENSES = ("at_least", "at_most", "equals")
#: each sense as a relation symbol (reports, the explorer) and in ASCII (the terminal)
SENSE_SYMBOLS = {"at_least": "≥", "at_most": "≤", "equals": "="}
SENSE_ASCII = {"at_least": ">=", "at_most": "<=", "equals": "="}
#: the stoplight of a requirement with a goal: the goal met, only the threshold met, neither
GOAL_STATUSES = ("PASS", "WARN", "FAIL")


def goal_status(sense: str, value: float, limit: float, goal: float, met: bool) -> str:
    """"PASS" when ``value`` meets the goal, "WARN" when it meets only the threshold (``met``, the
    row's verdict on ``limit``), "FAIL" otherwise (Radar Designer's threshold and objective).

    >>> goal_status("at_least", 2.5, 0.0, 3.0, True), goal_status("at_most", 0.8, 1.0, 0.5, True)
    ('WARN', 'WARN')
    >>> goal_status("at_least", 3.0, 0.0, 3.0, True), goal_status("at_least", -0.1, 0.0, 3.0, False)
    ('PASS', 'FAIL')
    """
    if not met:
        return "FAIL"
    reached = value >= goal if sense == "at_least" else value <= goal
    return "PASS" if reached else "WARN"
#: the name of the one evaluation case of a spec without a ``[cases]`` table
DEFAULT_CASE = "main"


@dataclass(frozen=True)
class Variable:
    """A continuous or integer design variable (values in the parameter's unit)."""

    name: str
    unit: str
    lower: float
    upper: float
    initial: float
    log_scale: bool
    integer: bool


@dataclass(frozen=True)
class Choice:
    """A catalog choice: each option sets one or more parameters (and may carry a cost)."""

    name: str
    option_names: Tuple[str, ...]
    settings: Tuple[Dict[str, float], ...]  # per option: parameter -> value
    costs: Tuple[float, ...]


@dataclass(frozen=True)
class Interval:
    """A requirement holds for every value of ``parameter`` from ``lower`` to ``upper`` (its
    unit); ``log``: grid in log p (None: by span)."""

    parameter: str
    unit: str
    lower: float
    upper: float
    log: Optional[bool] = None


@dataclass(frozen=True)
class Requirement:
    """``output`` of ``case`` must be at least / at most / equal to ``limit`` (output unit);
    with ``over`` at every point of that box of parameters (:mod:`.intervals`)."""

    name: str
    case: str
    output: str
    sense: str
    limit: float
    unit: str
    over: Tuple[Interval, ...] = ()
    over_points: Optional[int] = None  # search-grid points per parameter (None: default)
    over_worst: int = 3  # worst points kept as constraints
    probability: Optional[float] = None  # chance constraint: met with this probability (:mod:`.uncertain`)
    goal: Optional[float] = None  # the objective value beyond the threshold ``limit`` (output unit; :func:`goal_status`)


@dataclass(frozen=True)
class Objective:
    """Weighted sum of terms (parameter, output or "cost"); ``sign`` +1 minimise, −1 maximise."""

    terms: Tuple[Tuple[str, float], ...]
    sign: float
    text: str
    #: after meeting the thresholds, buy the requirements' goals in order of cost (:mod:`diffsense.design.goals`)
    reach_goals: bool = False


@dataclass
class Spec:
    """A validated requirement specification."""

    path: Path
    name: str
    title: str
    description: str
    sensor: str
    scenes: Dict[str, Scene]  # case -> scene
    fixed: Dict[str, Dict[str, float]]  # case -> parameter -> value
    variables: Dict[str, Variable]
    choices: Dict[str, Choice]
    requirements: List[Requirement]
    objective: Objective
    parameters: Dict[str, Dict[str, Param]] = field(default_factory=dict)  # case -> table
    outputs: Dict[str, Dict[str, Output]] = field(default_factory=dict)  # case -> table
    uncertain: Optional["Uncertainty"] = None  # the [uncertain] section (:mod:`.uncertain`)
    trade: Optional[object] = None  # diffsense.design.spec.trade.Trade, from [trade]
    #: case -> names of the parameters its own ``[cases.<name>]`` table sets (the rest of a
    #: case's fixed values come from ``[fixed]`` or the chain's defaults, shared by the cases)
    case_overrides: Dict[str, frozenset] = field(default_factory=dict)
    #: ``options.fidelity`` ("exact" or "fast", :mod:`diffsense.design.spec.fidelity`) and the
    #: options the fast fidelity set (option -> value; empty for "exact")
    fidelity: str = "exact"
    fidelity_switched: Dict[str, str] = field(default_factory=dict)

    @property
    def cases(self) -> List[str]:
        return list(self.scenes)

    def unit_of(self, case: str, name: str) -> str:
        if name in self.parameters[case]:
            return self.parameters[case][name].unit
        if name in self.outputs[case]:
            return self.outputs[case][name].unit
        return "1"
