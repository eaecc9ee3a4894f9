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

The solver meets the objective cap to its feasibility tolerance, which is measured in scaled
variables and may exceed δ; the answer is then moved back along the segment from the first
stage's answer (in ln x for log-scaled variables) to the nearest of a few points that meets the
cap exactly (:func:`_within_cap`).

Everything here runs through the optimiser's one lane program (:mod:`diffsense.design.problem`):
the gradients and the values of the test are the linearisations of lanes whose box pins every
variable at the point asked about, and the second stage is a lane whose stage input says so.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import jax
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.design.problem import variable_scales
from diffsense.design.programs import rows_of, stack
from diffsense.design.runner import Lanes, Runner, bounds_problem, objective_scale
from diffsense.optimize import SolverOptions
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


class _Linearised:
    """Values and derivatives of the problem at points, from lanes pinned there: the normalised
    objective F, every requirement row r (inequalities and equalities, :attr:`row_owner`
    order) and their Jacobians with respect to x."""

    def __init__(self, model: DesignModel, run, theta, points):
        points = np.atleast_2d(points)
        k = points.shape[0]
        x0 = np.hstack([points, np.zeros((k, 1))])
        res = run.solve(Lanes(x0, stack([theta] * k), x0, x0, np.zeros(k, dtype=int)))
        ineq = ~model.row_is_equality
        m = int(ineq.sum())
        n = points.shape[1]
        self.f = np.asarray(res.f, dtype=float)
        self.rows = np.zeros((k, ineq.size))
        self.rows[:, ineq] = res.g[:, :m]
        self.rows[:, ~ineq] = res.h
        jac = np.asarray(res.jacobian, dtype=float)[:, :, :n]
        self.grad_f = jac[:, 0, :]
        self.jac_rows = np.zeros((k, ineq.size, n))
        self.jac_rows[:, ineq, :] = jac[:, 1:1 + m, :]
        self.jac_rows[:, ~ineq, :] = jac[:, 1 + 2 * m + 1:, :]


def _flat_directions(model: DesignModel, run, theta, x, free):
    """Orthonormal directions (in y = ln x for log-scaled variables) of the free variables along
    which the objective and the active rows are flat to second order, and the active rows."""
    n = x.size
    y0 = _to_y(model, x)
    at = _Linearised(model, run, theta, x)
    r0 = at.rows[0]
    active = np.flatnonzero((r0 >= -ACTIVE) | model.row_is_equality)
    dx_dy = np.where(model.log_scale, x, 1.0)
    gf = at.grad_f[0] * dx_dy
    J = (at.jac_rows[0] * dx_dy[None, :])[active]
    M = np.vstack([gf[None, :], J])[:, free]
    if M.size == 0:
        return np.zeros((n, 0)), active, at
    _, s, vt = np.linalg.svd(M)
    rank = int(np.sum(s > 1e-8 * max(s.max(), 1e-300)))
    null = vt[rank:].T  # (n_free, k)
    if null.shape[1] == 0:
        return np.zeros((n, 0)), active, at
    zs = np.zeros((null.shape[1], n))
    zs[:, free] = null.T
    trial = np.vstack([_to_x(model, y0 + sgn * 1e-3 * z) for z in zs for sgn in (1.0, -1.0)])
    probe = _Linearised(model, run, theta, trial)
    f0 = float(at.f[0])
    flat = []
    for k, z in enumerate(zs):
        ok = True
        for i in (2 * k, 2 * k + 1):
            if abs(float(probe.f[i]) - f0) > 1e-10 * max(abs(f0), 1.0):
                ok = False
            if active.size and np.max(np.abs(probe.rows[i][active] - r0[active])) > 1e-10:
                ok = False
        if ok:
            flat.append(z)
    return (np.stack(flat, axis=1) if flat else np.zeros((n, 0))), active, at


def canonical_optimum(model: DesignModel, x, combo_index: int, options: Optional[SolverOptions] = None, *,
                      run=None, theta=None) -> Optional[Canonical]:
    """The second stage (module docstring) at the first-stage answer ``x`` of catalog combination
    ``combo_index``; ``None`` when the optimum is unique (no flat direction) or no requirement
    is inactive. The answer is accepted only if it meets every requirement.

    ``run``: the optimiser's lane runner (:class:`~diffsense.design.optimizer.Runner`; a new one
    with ``options`` otherwise); ``theta``: the θ of the answer's lane (its interval slots; by
    default a search at ``x`` sets them)."""

    x = np.asarray(x, dtype=float)
    if run is None:
        run = Runner(model, options or SolverOptions(polish=False), "auto", 1)
    if theta is None:
        design = model.inputs(combo_index)
        theta = model.solve_inputs(design, combo_index, model.limits, objective_scale(model))
        V, inputs = model.programs.design_inputs(x[None, :], [combo_index])
        theta = theta._replace(design=rows_of(inputs, 0))
    theta = theta._replace(limits=np.asarray(model.limits, dtype=float))
    on_lo, on_hi = variables_on_bounds(_bounds(model), x)
    free = np.flatnonzero(~model.integer & ~on_lo & ~on_hi)
    if free.size == 0:
        return None
    flat, active, at = _flat_directions(model, run, theta, x, free)
    r0 = at.rows[0]
    inactive = np.setdiff1d(np.arange(r0.size), active)
    if flat.shape[1] == 0 or inactive.size == 0:
        return None
    f_star = float(at.f[0])
    f_cap = f_star + OBJECTIVE_SLACK * max(abs(f_star), 1.0)
    held = ~np.isin(np.arange(x.size), free)
    t_hi = float(np.max(-r0[inactive])) * 10.0 + 1.0
    lower = np.append(np.where(held, x, model.lower), 0.0)
    upper = np.append(np.where(held, x, model.upper), t_hi)
    ineq = np.flatnonzero(~model.row_is_equality)
    mask = np.isin(ineq, inactive)
    stage = model.stage(True, f_cap, mask)
    t0 = max(float(np.min(-r0[inactive])), 0.0)
    lane = Lanes(np.append(x, t0)[None, :], _one(theta._replace(stage=stage)), lower[None, :], upper[None, :],
                 np.array([combo_index]))
    res = run.solve(lane, scale=variable_scales(model, lower, upper))
    x2, r2 = _within_cap(model, run, theta, x, np.asarray(res.x[0, :-1], dtype=float), f_cap)
    if x2 is None:
        return None
    rep = model.programs.reports(x2[None, :], [combo_index])[0]
    if not all(r["met"] for r in rep):
        return None
    return Canonical(x2, int(flat.shape[1]), float(np.min(-r0[inactive])), float(np.min(-r2[inactive])), RULE)


#: fractions of the way from the first stage's answer to the second's tried by :func:`_within_cap`
CAP_STEPS = (1.0, 0.999, 0.99, 0.9, 0.5, 0.1)


def _to_y(model: DesignModel, x):
    """y = ln x for the log-scaled variables, x otherwise."""
    return np.where(model.log_scale, np.log(np.where(model.log_scale, x, 1.0)), x)


def _to_x(model: DesignModel, y):
    """The inverse of :func:`_to_y`."""
    return np.where(model.log_scale, np.exp(y), y)


def _within_cap(model: DesignModel, run, theta, x, x2, f_cap):
    """The second stage's answer, or the point nearest to it on the segment from the first
    stage's answer ``x`` (in y = ln x for log-scaled variables) whose objective is within the
    cap and whose rows are met (the solver meets the cap only to its feasibility tolerance, in
    scaled units, which may exceed the cap's 1e-9); ``(None, None)`` when no such point moves off
    ``x``. Returns (point, its requirement rows)."""
    y0, y2 = _to_y(model, x), _to_y(model, x2)
    points = np.stack([np.where(model.integer, x2, _to_x(model, y0 + lam * (y2 - y0))) for lam in CAP_STEPS])
    at = _Linearised(model, run, theta, points)
    ok = (at.f <= f_cap) & np.all(at.rows[:, ~model.row_is_equality] <= 0.0, axis=1)
    if not ok.any():
        return None, None
    k = int(np.argmax(ok))
    return points[k], at.rows[k]


def _one(tree):
    """``tree`` with a leading axis of one row."""
    return jax.tree_util.tree_map(lambda a: np.asarray(a)[None], tree)


def _bounds(model: DesignModel):
    return bounds_problem(model)
