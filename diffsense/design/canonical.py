"""A canonical optimum when the optimum is not unique: a lexicographic second stage.

When the objective and the active requirements leave some continuous variables free along the
optimal set (the ore-pass radar's pulse width, bandwidth and PRF, say), the first stage's answer
is an arbitrary point of that set. The second stage picks a well-defined one, the *most robust*
design among the optimal ones:

    maximise t  over (x, t)
    subject to  every requirement as in the first stage,
                F(x) ≤ F* + δ·max(|F*|, 1)      (δ = 1e-9: the normalised objective stays optimal),
                g_i(x) + t ≤ 0  for every requirement i inactive at the first answer,
                the integers and the variables on a bound at the first answer held there,

g_i the scaled residual (≤ 0 when met; dB slack for requirements in dB, relative slack
otherwise), so t is the smallest scaled slack of the requirements the optimum does not need
(lexicographic optimisation, Miettinen 1999, *Nonlinear Multiobjective Optimization* §4.2;
the max-min form is the Chebyshev scalarisation of the slacks). When a requirement whose slack
the free variables cannot change sets that minimum, the max-min leaves a set again; the
objective therefore adds 1e-3 × the mean saturated slack s/(1+s) of those requirements, which
moves each free variable until its own requirement's slack saturates or a bound stops it.

The stage runs only when the optimum is flat: some direction z of the free variables (ln x for
log-scaled ones) is orthogonal to the gradients of F and of every active requirement *and* F
and the active requirements change by less than 1e-10 (scaled) along ±1e-3·z — a first- and
second-order test. A unique optimum is returned unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.optimize import Problem, SolverOptions, solve
from diffsense.optimize.bounds import variables_on_bounds

#: relative objective tolerance of the second stage
OBJECTIVE_SLACK = 1e-9
#: scaled residual above which a requirement row counts as active
ACTIVE = 1e-6
#: weight of the tie-breaking mean saturated slack in the second stage
TIE_WEIGHT = 1e-3

RULE = ("the optimum is not unique: among the designs within 1e-9 (relative) of the optimal objective, "
        "the one that maximises the smallest scaled slack of the requirements not active at the optimum, "
        "ties broken by their mean saturated slack s/(1+s) (a lexicographic second stage)")


@dataclass
class Canonical:
    """Outcome of :func:`canonical_optimum`."""

    x: np.ndarray
    flat_directions: int  # dimension of the flat part of the optimal set found
    smallest_slack_before: float
    smallest_slack_after: float
    rule: str


def _flat_directions(model, x, combo, free, rows_fn, f_fn):
    """Orthonormal directions (in y = ln x for log-scaled variables) of the free variables along
    which the objective and the active rows are flat to second order."""
    n = x.size
    to_x = lambda y: jnp.where(model.log_scale, jnp.exp(y), y)  # noqa: E731
    y0 = jnp.where(model.log_scale, jnp.log(jnp.where(model.log_scale, x, 1.0)), x)
    r0 = np.asarray(rows_fn(x))
    active = np.flatnonzero((r0 >= -ACTIVE) | model.row_is_equality)
    gf = np.asarray(jax.grad(lambda y: f_fn(to_x(y)))(y0))
    J = np.asarray(jax.jacfwd(lambda y: rows_fn(to_x(y)))(y0))[active]
    M = np.vstack([gf[None, :], J])[:, free]
    if M.size == 0:
        return np.zeros((n, 0)), active
    _, s, vt = np.linalg.svd(M)
    rank = int(np.sum(s > 1e-8 * max(s.max(), 1e-300)))
    null = vt[rank:].T  # (n_free, k)
    flat = []
    f0 = float(f_fn(x))
    for k in range(null.shape[1]):
        z = np.zeros(n)
        z[free] = null[:, k]
        ok = True
        for sgn in (1.0, -1.0):
            xt = to_x(y0 + sgn * 1e-3 * z)
            if abs(float(f_fn(xt)) - f0) > 1e-10 * max(abs(f0), 1.0):
                ok = False
            if active.size and np.max(np.abs(np.asarray(rows_fn(xt))[active] - r0[active])) > 1e-10:
                ok = False
        if ok:
            flat.append(z)
    return (np.stack(flat, axis=1) if flat else np.zeros((n, 0))), active


def canonical_optimum(model: DesignModel, x, combo_index: int, options: Optional[SolverOptions] = None) -> Optional[Canonical]:
    """The second stage (module docstring) at the first-stage answer ``x`` of catalog combination
    ``combo_index``; ``None`` when the optimum is unique (no flat direction) or no requirement
    is inactive. The answer is accepted only if it meets every requirement."""
    x = np.asarray(x, dtype=float)
    combo = jnp.asarray(model.combo_table[combo_index])
    limits = jnp.asarray(model.limits)
    rows_fn = jax.jit(lambda xx: model.residuals(xx, combo, limits))
    f_fn = jax.jit(lambda xx: model.objective(xx, combo))
    base = Problem(lambda xx, _: f_fn(xx), model.lower, model.upper, log_scale=model.log_scale,
                   integer=model.integer)
    on_lo, on_hi = variables_on_bounds(base, x)
    free = np.flatnonzero(~model.integer & ~on_lo & ~on_hi)
    if free.size == 0:
        return None
    flat, active = _flat_directions(model, jnp.asarray(x), combo, free, rows_fn, f_fn)
    r0 = np.asarray(rows_fn(jnp.asarray(x)))
    inactive = np.setdiff1d(np.arange(r0.size), active)
    if flat.shape[1] == 0 or inactive.size == 0:
        return None
    f_star = float(f_fn(jnp.asarray(x)))
    f_cap = f_star + OBJECTIVE_SLACK * max(abs(f_star), 1.0)
    held = ~np.isin(np.arange(x.size), free)
    t_hi = float(np.max(-r0[inactive])) * 10.0 + 1.0
    lower = np.append(np.where(held, x, model.lower), 0.0)
    upper = np.append(np.where(held, x, model.upper), t_hi)
    eq = model.row_is_equality

    def g(v, _):
        xx, t = v[:-1], v[-1]
        r = model.residuals(xx, combo, limits)
        parts = [r[~eq], jnp.reshape(model.objective(xx, combo) - f_cap, (1,)), r[inactive] + t]
        return jnp.concatenate(parts)

    def h(v, _):
        return model.residuals(v[:-1], combo, limits)[eq]

    def objective(v, _):
        # max-min slack, then (weight TIE_WEIGHT) the mean saturated slack s/(1+s): the max-min
        # alone leaves a set when a held requirement sets the smallest slack
        slack = jnp.maximum(-model.residuals(v[:-1], combo, limits)[inactive], 0.0)
        return -(v[-1] + TIE_WEIGHT * jnp.mean(slack / (1.0 + slack)))

    problem = Problem(objective, lower, upper, inequality=g, equality=h if eq.any() else None,
                      log_scale=np.append(model.log_scale, False))
    t0 = max(float(np.min(-r0[inactive])), 0.0)
    res = solve(problem, jnp.asarray(np.append(x, t0)), None, options or SolverOptions(polish=False))
    x2 = np.asarray(res.x[:-1], dtype=float)
    rep = model.requirement_report(x2, model.combo_table[combo_index])
    if not all(r["met"] for r in rep) or float(f_fn(jnp.asarray(x2))) > f_cap + 1e-12 * max(abs(f_star), 1.0):
        return None
    r2 = np.asarray(rows_fn(jnp.asarray(x2)))
    return Canonical(x2, int(flat.shape[1]), float(np.min(-r0[inactive])), float(np.min(-r2[inactive])), RULE)
