"""Independent Monte Carlo check of the probability that each requirement is met under the
declared uncertainty (:mod:`diffsense.design.spec.uncertain`).

After a solve — or at any design — every point requirement (``at_least`` / ``at_most``, no
``over``) whose case has uncertain inputs is evaluated at a fresh sample of ``check_samples``
(default 100,000) pseudo-random draws of those inputs: NumPy's PCG64 generator seeded by
(seed, 1), a different generator and seed from the design sample (scrambled Sobol points,
:func:`diffsense.design.chance.design_sample`), so the check is independent of the sample the
optimiser met the requirement on. With k of n draws meeting the requirement, the estimate is
k/n and its interval the Wilson score interval at the ``confidence`` level (Wilson 1927,
JASA 22: 209; Brown, Cai & DasGupta 2001, Statist. Sci. 16: 101)::

    centre = (p̂ + z²/2n)/(1 + z²/n),   half = z/(1 + z²/n)·√(p̂(1 − p̂)/n + z²/4n²),

z = Φ⁻¹((1 + confidence)/2). A requirement that asks for a probability p is ``consistent`` when
p lies in the interval, ``above`` when the whole interval lies above p and ``below`` when it
lies below (the check refutes the design sample's answer).
"""

from __future__ import annotations

import math
from statistics import NormalDist
from typing import Dict, List, NamedTuple, Optional

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.chance import sampled_outputs
from diffsense.design.model import DesignModel

#: draws evaluated per compiled call
CHUNK = 8192


class ProbabilityCheck(NamedTuple):
    """The Monte Carlo check of one requirement at one design."""

    asked: Optional[float]  # the requirement's probability (None: a deterministic requirement)
    estimate: float  # fraction of the draws meeting it
    lower: float  # Wilson interval
    upper: float
    met: int  # draws meeting it
    samples: int
    confidence: float
    seed: int
    status: Optional[str]  # vs asked: "above", "consistent", "below"

    def as_dict(self) -> dict:
        return {"asked": self.asked, "estimate": self.estimate, "interval": [self.lower, self.upper],
                "met_draws": self.met, "samples": self.samples, "confidence": self.confidence,
                "seed": self.seed, "status": self.status}


def wilson_interval(k: int, n: int, confidence: float = 0.95):
    """The Wilson score interval (lower, upper) of a binomial proportion with k successes in n
    trials (module docstring).

    k = 95 of n = 100 at 95 % (z = 1.959964), against the formula evaluated independently here:

    >>> lo, hi = wilson_interval(95, 100, 0.95)
    >>> z = 1.959963984540054; p = 0.95; n = 100
    >>> c = (p + z * z / (2 * n)) / (1 + z * z / n)
    >>> h = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    >>> abs(lo - (c - h)) < 1e-15 and abs(hi - (c + h)) < 1e-15, round(lo, 4), round(hi, 4)
    (True, 0.8883, 0.9785)
    """
    z = NormalDist().inv_cdf(0.5 * (1.0 + confidence))
    p = k / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2.0 * n)) / denom
    half = z / denom * math.sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


def checked_requirements(model: DesignModel) -> List[int]:
    """Indices of the requirements the check covers: point inequalities of a case with
    uncertain inputs."""
    unc = model.spec.uncertain
    if unc is None:
        return []
    return [j for j, r in enumerate(model.requirements)
            if r.sense != "equals" and not r.over and set(unc.parameters) & set(model.spec.parameters[r.case])]


def check_sample(uncertainty, samples: Optional[int] = None, seed: Optional[int] = None) -> np.ndarray:
    """The check's uniform draws (n, d): PCG64 seeded by (seed, 1) (module docstring)."""
    n = uncertainty.check_samples if samples is None else int(samples)
    seed = uncertainty.seed if seed is None else int(seed)
    return np.random.default_rng([seed, 1]).random((n, len(uncertainty.distributions)))


def _program(model: DesignModel, indices):
    reqs = [model.requirements[j] for j in indices]
    cases = sorted({r.case for r in reqs})

    def run(values, u):
        params = model.parameters(values)
        out = {c: sampled_outputs(model.spec, c, params[c], {r.output for r in reqs if r.case == c}, u)
               for c in cases}
        return jnp.stack([out[r.case][r.output] for r in reqs])

    return jax.jit(run)


def check_probabilities(model: DesignModel, x, combo, *, samples: Optional[int] = None, seed: Optional[int] = None,
                        confidence: Optional[float] = None) -> Dict[int, ProbabilityCheck]:
    """Per checked requirement (:func:`checked_requirements`), its probability of being met at
    design ``x`` and catalog row ``combo`` with its Wilson interval (module docstring).
    ``samples``, ``seed``, ``confidence``: default the spec's ``[uncertain]`` settings."""
    indices = checked_requirements(model)
    if not indices:
        return {}
    unc = model.spec.uncertain
    seed = unc.seed if seed is None else int(seed)
    confidence = unc.confidence if confidence is None else float(confidence)
    u = check_sample(unc, samples, seed)
    n = u.shape[0]
    fn = _program(model, indices)
    values = np.asarray(model.layout.values, dtype=float).copy()
    values[model.layout.variable_slots] = np.asarray(x, dtype=float)
    values[model.layout.catalog_slots] = np.asarray(combo, dtype=float)[:-1]
    met = np.zeros(len(indices), dtype=np.int64)
    for start in range(0, n, CHUNK):
        rows = np.arange(start, min(start + CHUNK, n))
        padded = np.concatenate([rows, np.full(CHUNK - rows.size, rows[-1])])
        v = np.asarray(fn(values, u[padded]))[:, : rows.size]
        for k, j in enumerate(indices):
            r = model.requirements[j]
            ok = v[k] >= r.limit if r.sense == "at_least" else v[k] <= r.limit
            met[k] += int(np.count_nonzero(ok & np.isfinite(v[k])))
    out = {}
    for k, j in enumerate(indices):
        lo, hi = wilson_interval(int(met[k]), n, confidence)
        asked = model.requirements[j].probability
        status = None if asked is None else "below" if hi < asked else "above" if lo > asked else "consistent"
        out[j] = ProbabilityCheck(asked, float(met[k] / n), lo, hi, int(met[k]), n, confidence, seed, status)
    return out


def attach_probabilities(model: DesignModel, record: dict, x, combo_index: int) -> None:
    """Add to each requirement row of a design record (``record["requirements"]``) its
    ``probability`` check (:meth:`ProbabilityCheck.as_dict`) when the check covers it; no-op
    for a spec without ``[uncertain]``."""
    checks = check_probabilities(model, x, model.combo_table[combo_index])
    for j, chk in checks.items():
        record["requirements"][j]["probability"] = chk.as_dict()
    if checks:
        record["uncertain"] = [{"parameter": d.parameter, "unit": d.unit, "distribution": d.kind,
                                "nominal": d.nominal, "spec": d.text} for d in model.spec.uncertain.distributions]
