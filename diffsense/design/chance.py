"""Chance constraints: requirements met with a stated probability over uncertain inputs.

A requirement with ``probability`` p (:mod:`diffsense.design.spec.uncertain`) on output v of
its case, with s = −1 for ``at_least`` and +1 for ``at_most`` and limit b, asks

    P_ξ[ s·(v(x, ξ) − b) ≤ 0 ] ≥ p,

ξ the case's uncertain inputs. Equivalently a quantile of v meets the limit: the α-quantile
q_α(x) of v(x, ξ) with α = 1 − p (``at_least``: q_α ≥ b) or α = p (``at_most``: q_α ≤ b). The
optimiser receives the one smooth row s·(q̃_α(x) − b)/scale ≤ 0 where q̃_α is a
**sample-average approximation with a smoothed quantile**:

* a fixed design sample ξ_1 … ξ_N (scrambled Sobol points, seeded, N = ``samples``, default
  4096) mapped to the distributions by their inverse CDFs: common random numbers, so q̃ is a
  deterministic function of x and every iteration of the solve sees the same sample;
* q̃ solves the kernel-smoothed empirical CDF equation

      (1/N) Σ_i Φ((q̃ − v_i)/h) = α,      h = c·√(var v + h₀²),  c = 0.02

  (Φ the standard normal CDF; h₀ = 1e-9 times the requirement's scale keeps h positive when v
  does not vary). q̃ is C^∞ in every v_i: its derivative is dq̃ = Σ_i w_i dv_i + (Σ_i w_i z_i) dh
  with z_i = (q̃ − v_i)/h and weights w_i = φ(z_i)/Σ_k φ(z_k) (the implicit function theorem),
  a smooth average of the gradients of the samples near the quantile, written as a custom JVP
  that JAX differentiates again (the report's post-optimal Hessian).

Why a smoothed quantile and not the alternatives: the empirical indicator average
(1/N) Σ 1[met] is piecewise constant (no gradient); a smoothed indicator in the probability
form p − P̃ ≤ 0 has a vanishing gradient wherever the whole sample meets or misses the limit,
and its residual is a probability where the other rows are in the output's unit. The quantile
form keeps the row in the output's unit (dB for a margin), so the multiplier and the
post-optimal sensitivities read as for a deterministic requirement, and its gradient never
vanishes. CVaR (Rockafellar & Uryasev 2000), the convex conservative surrogate, would meet the
requirement with a probability above p by an amount that depends on the tail's shape; here the
asked probability itself is targeted, which the independent check
(:mod:`diffsense.design.monte_carlo`) can then confirm. The smoothing bias of the probability
is (h²/2)·f′(q) (kernel CDF estimator, Azzalini 1981, Biometrika 68: 326): for a normal v,
0.085·c² = 3.4e-5 at p = 0.95, below the check's resolution (±1.4e-3 at 1e5 samples).
Scrambled Sobol points (Owen 1995) make the quantile's sampling error far smaller than
pseudo-random points of the same number for the few smooth inputs a spec declares.

Each probabilistic requirement is an individual chance constraint; the joint probability of
meeting several is not constrained.
"""

from __future__ import annotations

from typing import Dict, Optional

import jax
import jax.numpy as jnp
import numpy as np
from jax.scipy.special import ndtr, ndtri

from diffsense.design.spec.uncertain import TRUNCATE_SIGMAS, Distribution, Uncertainty
from diffsense.optimize.multistart import sobol_points
from diffsense.scene import compute

#: bandwidth of the smoothed quantile as a fraction of the sample's standard deviation
BANDWIDTH = 0.02
#: floor of the bandwidth, relative to the requirement's scale
BANDWIDTH_FLOOR = 1e-9
#: iterations of the safeguarded Newton solve of the smoothed CDF equation
QUANTILE_ITERATIONS = 40
#: a uniform draw is kept this far inside (0, 1)
_U_EDGE = 1e-12


def draw(dist: Distribution, nominal, u, spread=None):
    """The values of ``dist`` at uniform draws ``u`` ∈ (0, 1), around the parameter's ``nominal``
    value (its median: a parameter perturbed in a report moves the whole distribution);
    ``spread``: σ, σ_ln or the width (default ``dist.spread``; the programs pass it as an input).

    normal: nominal + σ·z, lognormal: nominal·exp(σ_ln·z), z the standard normal truncated at
    ±6 (inverse CDF of u rescaled to [Φ(−6), Φ(6)]); uniform: nominal + (u − ½)·width.

    >>> from diffsense.design.spec.uncertain import Distribution
    >>> d = Distribution("rcs_m2", "m**2", "lognormal", 1.0, 0.6907755278982137, "")
    >>> float(draw(d, 1.0, 0.5)), float(draw(d, 2.0, ndtr(1.0)))      # the median; 2·e^σ
    (1.0, 3.9905246)
    >>> float(2.0 * np.exp(0.6907755278982137))                      # closed form
    3.9905246
    """
    u = jnp.clip(jnp.asarray(u, dtype=float), _U_EDGE, 1.0 - _U_EDGE)
    spread = dist.spread if spread is None else spread
    if dist.kind == "uniform":
        return nominal + (u - 0.5) * spread
    lo = ndtr(-TRUNCATE_SIGMAS)
    z = ndtri(lo + u * (1.0 - 2.0 * lo))
    if dist.kind == "normal":
        return nominal + spread * z
    return nominal * jnp.exp(spread * z)


@jax.custom_jvp
def smooth_quantile(v, h, alpha):
    """The α-quantile of the sample ``v`` (N,) smoothed by a normal kernel of width ``h``: the
    root q of (1/N) Σ Φ((q − v_i)/h) = α (module docstring), differentiable in ``v``, ``h`` and
    α (dq/dα = 1/f̃(q), f̃ the smoothed density, by the implicit function theorem).

    For a sample of two equal halves at −1 and +1 and α = ½ the root is 0 by symmetry:

    >>> float(smooth_quantile(jnp.array([-1.0, 1.0]), 0.5, 0.5))
    0.0
    """
    return _quantile_root(v, h, alpha)


def _quantile_root(v, h, alpha):
    v = jax.lax.stop_gradient(v)
    h = jax.lax.stop_gradient(h)
    alpha = jax.lax.stop_gradient(jnp.asarray(alpha, dtype=v.dtype))
    n = v.shape[0]
    a = jnp.min(v) - 9.0 * h  # F(a) < Φ(−9) ≈ 1e-19 ≤ α
    b = jnp.max(v) + 9.0 * h
    q0 = jnp.sort(v)[jnp.clip(jnp.floor(alpha * n).astype(int), 0, n - 1)]

    def body(_, state):
        a, b, q = state
        z = (q - v) / h
        g = jnp.mean(ndtr(z)) - alpha
        slope = jnp.mean(jnp.exp(-0.5 * z * z)) / (jnp.sqrt(2.0 * jnp.pi) * h)
        a = jnp.where(g < 0, q, a)
        b = jnp.where(g < 0, b, q)
        step = q - g / jnp.where(slope > 0, slope, 1.0)
        inside = (slope > 0) & (step >= a) & (step <= b)
        return a, b, jnp.where(inside, step, 0.5 * (a + b))

    return jax.lax.fori_loop(0, QUANTILE_ITERATIONS, body, (a, b, q0))[2]


@smooth_quantile.defjvp
def _smooth_quantile_jvp(primals, tangents):
    v, h, alpha = primals
    dv, dh, dalpha = tangents
    q = smooth_quantile(v, h, alpha)
    z = (q - v) / h
    phi = jnp.exp(-0.5 * z * z)
    total = jnp.sum(phi)
    w = phi / total
    density = total / (v.shape[0] * h * jnp.sqrt(2.0 * jnp.pi))
    return q, jnp.sum(w * dv) + jnp.sum(w * z) * dh + dalpha / density


def bandwidth(v, scale):
    """The kernel width h = c·√(var v + h₀²) of a sample ``v`` (module docstring)."""
    floor = BANDWIDTH_FLOOR * scale / BANDWIDTH
    return BANDWIDTH * jnp.sqrt(jnp.var(v) + floor * floor)


def sample_parameters(uncertainty: Uncertainty, table, params: dict, u, spreads=None) -> dict:
    """``params`` with every uncertain parameter of ``table`` (a case's parameter table) replaced
    by its draws at the uniform points ``u`` (…, d), columns in the order of the distributions;
    ``spreads`` (d,): the distributions' spreads (default their own)."""
    out = dict(params)
    for k, dist in enumerate(uncertainty.distributions):
        if dist.parameter in table:
            out[dist.parameter] = draw(dist, params[dist.parameter], u[..., k], None if spreads is None else spreads[k])
    return out


def sampled_outputs(spec, case: str, params: dict, wanted, u, spreads=None) -> Dict[str, jnp.ndarray]:
    """The outputs ``wanted`` of ``case`` at every row of the uniform points ``u`` (M, d)
    (output -> (M,)): the chain evaluated with the uncertain parameters drawn from each row."""
    scene = spec.scenes[case]
    table = spec.parameters[case]

    def one(row):
        ev = compute(scene, sample_parameters(spec.uncertain, table, params, row, spreads), frozenset(wanted))
        return {o: jnp.asarray(ev.values[o], dtype=float) for o in wanted}

    return jax.vmap(one)(u)


def design_sample(uncertainty: Uncertainty) -> np.ndarray:
    """The fixed design sample (N, d): scrambled Sobol points seeded by ``uncertainty.seed``."""
    return sobol_points(uncertainty.samples, len(uncertainty.distributions), seed=uncertainty.seed)


class ChanceRequirements:
    """The probabilistic requirements of a spec: their smoothed quantiles as pure functions of
    the case parameters and the inputs θ (sample, spreads, quantile levels and scales are data:
    :meth:`sample`, :meth:`spreads`, :meth:`alphas`)."""

    def __init__(self, spec, sign):
        self.spec = spec
        self.indices = [j for j, r in enumerate(spec.requirements) if getattr(r, "probability", None) is not None]
        self.sign = np.asarray(sign, dtype=float)
        self.cases = sorted({spec.requirements[j].case for j in self.indices})

    def alpha(self, j: int) -> float:
        """The quantile level of requirement j: 1 − p for ``at_least``, p for ``at_most``."""
        p = self.spec.requirements[j].probability
        return 1.0 - p if self.spec.requirements[j].sense == "at_least" else p

    def alphas(self) -> np.ndarray:
        return np.array([self.alpha(j) for j in self.indices], dtype=float)

    def sample(self) -> np.ndarray:
        """The design sample (N, d); (0, 0) without probabilistic requirements."""
        if not self.indices:
            return np.zeros((0, 0))
        return design_sample(self.spec.uncertain)

    def spreads(self) -> np.ndarray:
        if not self.indices:
            return np.zeros((0,))
        return np.array([d.spread for d in self.spec.uncertain.distributions], dtype=float)

    def values(self, params_by_case: dict, inputs) -> Dict[int, jnp.ndarray]:
        """Per probabilistic requirement, the smoothed quantile q̃ of its output (its unit)."""
        sampled = {}
        for case in self.cases:
            wanted = frozenset(self.spec.requirements[j].output for j in self.indices
                               if self.spec.requirements[j].case == case)
            sampled[case] = sampled_outputs(self.spec, case, params_by_case[case], wanted, inputs.sample,
                                            inputs.spreads)
        out = {}
        for k, j in enumerate(self.indices):
            r = self.spec.requirements[j]
            v = sampled[r.case][r.output]
            out[j] = smooth_quantile(v, bandwidth(v, inputs.scales[j]), inputs.alpha[k])
        return out
