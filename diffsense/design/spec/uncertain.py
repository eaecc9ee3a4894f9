"""The ``[uncertain]`` section and the ``probability`` key of a requirement: inputs known only
by a distribution, and requirements met with a stated probability over them::

    [uncertain]
    rcs_m2 = { lognormal = "1 m^2", sigma_db = 3 }             # median, spread of 10 log10 σ in dB
    rain_rate_mm_h = { uniform = ["0 mm/h", "25 mm/h"] }        # ends of the interval
    noise_figure_db = { normal = "5 dB", sigma = "0.5 dB" }     # mean and standard deviation
    samples = 4096            # optional: design sample size (scrambled Sobol points, 64 to 65536)
    seed = 0                  # optional: seed of the design sample
    check_samples = 100000    # optional: size of the independent Monte Carlo check (100000 to 10^7)
    confidence = 0.99         # optional: confidence level of the check's interval

    [[requirements]]
    output = "clear.detection_margin_db"
    at_least = "0 dB"
    probability = 0.95        # met with probability 0.95 over the uncertain inputs

Every uncertain parameter is a fixed parameter of at least one case (not a design variable or
catalog setting) and is not written in ``[fixed]`` or a case table: its *nominal* value — the
median of its distribution (the median for ``lognormal``, the mean for ``normal``, the middle
for ``uniform``) — is its fixed value in every case that has it, and is what every deterministic
evaluation (requirements without ``probability``, the objective, budgets) uses. Quantities are
in any unit of the parameter; ``sigma`` is a spread in the parameter's unit and ``sigma_db`` the
standard deviation of 10·log10 of the value, in dB. Normal and lognormal distributions are
truncated at ±6 standard deviations (a probability of 2e-9 removed), and that whole support must
lie inside the model's domain; the ends of a uniform interval may sit on an open end of the
domain (its draws stay strictly inside).

A requirement with ``probability`` p (0 < p < 1) is a chance constraint over the distributions
of its case's uncertain parameters (see :mod:`diffsense.design.chance`); it takes ``at_least``
or ``at_most`` (not ``equals``, whose probability is 0) and no ``over``, and both p·samples and
(1 − p)·samples must be at least :data:`MIN_TAIL_SAMPLES`, so that the design sample resolves the
quantile.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Optional, Tuple

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.common import closest, echo, is_number, quantity, reject_unknown, whole_number
from diffsense.design.spec.limits import MAX_CHECK_SAMPLES, MAX_SAMPLES
from diffsense.design.units import split_quantity, to_unit
from diffsense.errors import DomainError, SpecError, UnitError
from diffsense.numerics.checks import check_range
from diffsense.numerics.db import DB_PER_NEPER

#: distribution kinds and the keys each takes besides its own
KINDS = {"normal": {"sigma"}, "lognormal": {"sigma_db"}, "uniform": set()}
#: settings of the section that are not parameters, with their defaults
SETTINGS = {"samples": 4096, "seed": 0, "check_samples": 100_000, "confidence": 0.99}
#: the smallest independent check allowed
MIN_CHECK_SAMPLES = 100_000
#: design-sample points required on each side of a requirement's quantile
MIN_TAIL_SAMPLES = 20
#: normal and lognormal distributions are truncated at this many standard deviations
TRUNCATE_SIGMAS = 6.0


@dataclass(frozen=True)
class Distribution:
    """The distribution of one uncertain parameter (values in the parameter's unit).

    ``nominal``: the median; ``spread``: the standard deviation (``normal``, parameter unit),
    the standard deviation of ln of the value (``lognormal``, nepers: sigma_db / (10/ln 10)),
    or the width of the interval (``uniform``); ``text``: as written, for reports."""

    parameter: str
    unit: str
    kind: str
    nominal: float
    spread: float
    text: str

    def support(self) -> Tuple[float, float]:
        """The smallest and largest value drawn (±6 standard deviations, or the interval)."""
        if self.kind == "normal":
            return self.nominal - TRUNCATE_SIGMAS * self.spread, self.nominal + TRUNCATE_SIGMAS * self.spread
        if self.kind == "lognormal":  # exp saturates to 0 and inf rather than overflow
            reach = min(TRUNCATE_SIGMAS * self.spread, 1000.0)
            return self.nominal * math.exp(-reach), self.nominal * math.exp(reach) if reach < 709.0 else math.inf
        return self.nominal - 0.5 * self.spread, self.nominal + 0.5 * self.spread


@dataclass(frozen=True)
class Uncertainty:
    """The ``[uncertain]`` section: the distributions and the sampling settings."""

    distributions: Tuple[Distribution, ...]
    samples: int = SETTINGS["samples"]
    seed: int = SETTINGS["seed"]
    check_samples: int = SETTINGS["check_samples"]
    confidence: float = SETTINGS["confidence"]

    @property
    def parameters(self) -> Tuple[str, ...]:
        return tuple(d.parameter for d in self.distributions)


def read_uncertain(file, raw: Mapping, cases: Cases, chosen) -> Optional[Uncertainty]:
    """The ``[uncertain]`` section (None when absent); ``chosen``: the design parameters."""
    table = raw.get("uncertain")
    if table is None:
        return None
    if not isinstance(table, dict) or not table:
        raise SpecError(file, "uncertain", "must be a table of parameter = { normal | lognormal | uniform = ... }")
    settings = dict(SETTINGS)
    dists = []
    for name, value in table.items():
        key = f"uncertain.{name}"
        if name in SETTINGS:
            settings[name] = _setting(file, key, name, value)
            continue
        if name not in cases.all_parameters:
            raise SpecError(file, key, f"unknown parameter {echo(name, 60)}{closest(name, cases.all_parameters)}; "
                            f"[uncertain] takes fixed parameters and the settings {sorted(SETTINGS)}")
        if name in chosen:
            raise SpecError(file, key, f"'{name}' is a design variable or catalog setting; it cannot be uncertain")
        prm = cases.param_of(file, name, key)
        if prm.integer:
            raise SpecError(file, key, f"'{name}' counts something (a whole number); a distribution needs a "
                            "continuous parameter")
        for where, values in [("fixed", raw.get("fixed") or {})] + \
                [(f"cases.{c}", o) for c, o in cases.overrides.items()]:
            if isinstance(values, dict) and name in values:
                raise SpecError(file, f"{where}.{name}", f"'{name}' is uncertain: remove it here (its nominal "
                                "value, the median of its distribution, is used where a fixed value is needed)")
        dists.append(_distribution(file, key, prm, value))
    if not dists:
        raise SpecError(file, "uncertain", "names no uncertain parameter")
    return Uncertainty(tuple(dists), **settings)


def _setting(file, key: str, name: str, value):
    if name == "confidence":
        if not is_number(value) or not 0.5 <= value < 1.0:
            raise SpecError(file, key, f"must be a number from 0.5 to below 1, e.g. 0.95; got {echo(value)}")
        return float(value)
    lo, hi = {"samples": (64, MAX_SAMPLES), "seed": (0, 2**31 - 1),
              "check_samples": (MIN_CHECK_SAMPLES, MAX_CHECK_SAMPLES)}[name]
    return whole_number(file, key, value, lo, hi)


def _distribution(file, key: str, prm, value) -> Distribution:
    if not isinstance(value, dict):
        raise SpecError(file, key, "must be a table such as { normal = \"5 dB\", sigma = \"0.5 dB\" }, "
                        "{ lognormal = \"1 m^2\", sigma_db = 3 } or { uniform = [\"0 mm/h\", \"25 mm/h\"] }")
    kinds = [k for k in KINDS if k in value]
    if len(kinds) != 1:
        raise SpecError(file, key, f"needs exactly one of {sorted(KINDS)}")
    kind = kinds[0]
    reject_unknown(file, key + ".", value, {kind} | KINDS[kind])
    for extra in KINDS[kind]:
        if extra not in value:
            raise SpecError(file, f"{key}.{extra}", f"missing (a {kind} distribution needs '{extra}')")
    text = ", ".join(f"{k} = {v!r}" for k, v in value.items())
    if kind == "uniform":
        ends = value["uniform"]
        if not isinstance(ends, list) or len(ends) != 2:
            raise SpecError(file, f"{key}.uniform", "must be [lower, upper]")
        lo, hi = (quantity(file, f"{key}.uniform[{i}]", e, prm.unit) for i, e in enumerate(ends))
        if not lo < hi:
            raise SpecError(file, f"{key}.uniform", f"needs lower < upper; got {lo:g} and {hi:g} {prm.unit}")
        dist = Distribution(prm.name, prm.unit, kind, 0.5 * (lo + hi), hi - lo, text)
        _inside(file, key, prm, dist, closed=True)
        return dist
    centre = quantity(file, f"{key}.{kind}", value[kind], prm.unit)
    if kind == "normal":
        spread = _spread(file, f"{key}.sigma", value["sigma"], prm.unit)
    else:
        if centre <= 0:
            raise SpecError(file, f"{key}.lognormal", f"the median of a lognormal must be positive; got {centre:g}")
        spread = quantity(file, f"{key}.sigma_db", value["sigma_db"], "dB") / DB_PER_NEPER
    if not spread > 0:
        raise SpecError(file, f"{key}.{'sigma' if kind == 'normal' else 'sigma_db'}", "must be positive")
    dist = Distribution(prm.name, prm.unit, kind, centre, spread, text)
    _inside(file, key, prm, dist, closed=False)
    return dist


def _spread(file, key: str, value, unit: str) -> float:
    """A spread (a difference of two values) in ``unit``: a number, or "<number> <unit>"
    converted as the difference from zero of that unit (so "0.5 degC" is 0.5 K)."""
    if isinstance(value, str):
        try:
            number, u = split_quantity(value)
            return to_unit(f"{number} {u}", unit) - to_unit(f"0 {u}", unit)
        except UnitError as exc:
            raise SpecError(file, key, f"{exc} (expected a spread in '{unit}')") from None
    return quantity(file, key, value, unit)


def _inside(file, key: str, prm, dist: Distribution, closed: bool) -> None:
    """Raise unless every value ``dist`` draws lies in the domain of ``prm`` (``closed``: the
    ends of the support may sit on an open end of the domain)."""
    lo, hi = dist.support()
    try:
        for v in (lo, hi):
            check_range(prm.name, float(v), prm.lo, prm.hi, lo_open=prm.lo_open and not closed,
                        hi_open=prm.hi_open and not closed)
    except DomainError as exc:
        what = "its interval" if dist.kind == "uniform" else f"its ±{TRUNCATE_SIGMAS:g} sigma support"
        raise SpecError(file, key, f"{what} [{lo:g}, {hi:g}] {prm.unit} reaches outside the model's domain: "
                        f"{exc}") from None


def read_probability(file, key: str, r: Mapping) -> Optional[float]:
    """The ``probability`` of requirement ``r`` (None when absent): a number in (0, 1), with
    ``at_least`` or ``at_most`` and without ``over``."""
    p = r.get("probability")
    if p is None:
        return None
    if not is_number(p) or not 0.0 < p < 1.0:
        raise SpecError(file, f"{key}.probability", f"must be a number between 0 and 1 (exclusive); got {echo(p)}")
    if "equals" in r:
        raise SpecError(file, f"{key}.probability", "an equality holds with probability 0; use at_least or at_most")
    if "over" in r:
        raise SpecError(file, f"{key}.probability", "'probability' and 'over' cannot be combined")
    return float(p)


def check_probabilities(file, requirements, uncertainty: Optional[Uncertainty], cases: Cases) -> None:
    """Raise unless every requirement with a probability has uncertain inputs in its case and
    a quantile the design sample resolves."""
    for i, r in enumerate(requirements):
        if r.probability is None:
            continue
        key = f"requirements[{i}].probability"
        if uncertainty is None:
            raise SpecError(file, key, "needs an [uncertain] table naming the uncertain inputs")
        if not set(uncertainty.parameters) & set(cases.parameters[r.case]):
            raise SpecError(file, key, f"case '{r.case}' has none of the uncertain parameters "
                            f"{list(uncertainty.parameters)}")
        tail = min(r.probability, 1.0 - r.probability) * uncertainty.samples
        if tail < MIN_TAIL_SAMPLES:
            need = math.ceil(MIN_TAIL_SAMPLES / min(r.probability, 1.0 - r.probability))
            raise SpecError(file, key, f"probability {r.probability:g} is not resolved by {uncertainty.samples} "
                            f"samples; set [uncertain] samples = {need} or more")


def nominal_values(fixed, uncertainty: Optional[Uncertainty], cases: Cases):
    """``fixed`` (case -> parameter -> value) with every uncertain parameter at its nominal
    value (the median) in the cases that have it."""
    if uncertainty is not None:
        for case, table in cases.parameters.items():
            fixed[case].update({d.parameter: d.nominal for d in uncertainty.distributions if d.parameter in table})
    return fixed
