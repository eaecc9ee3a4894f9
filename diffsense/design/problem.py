"""The optimiser's problem of a design model: one problem for every step, the stage passed as data.

Every solve of :func:`diffsense.design.optimizer.optimize_design` — the relaxation, the integer
neighbours, the near misses, the exchange rounds and the canonical second stage — is a lane of
one compiled program (:mod:`diffsense.design.programs`), so they must all be one problem whose
differences are inputs (:class:`~diffsense.design.inputs.SolveInputs`). Its variables are the
design x and one more, t, the smallest slack of the canonical stage (held at 0 by its bounds in
the other steps); with r(x) the requirement rows (:meth:`DesignModel.residuals`) and F(x) the
normalised objective:

* design problem (``stage.canonical`` False): minimise F(x) subject to r(x) ≤ 0 (= 0 for
  equalities); the extra rows below are −1, inactive;
* canonical stage (True): maximise t + 10⁻³ · mean over the rows of ``stage.inactive`` of
  s/(1 + s), s = max(−r, 0), subject to r(x) ≤ 0, F(x) − cap ≤ 0 and r_i(x) + t ≤ 0 for those
  rows (:mod:`diffsense.design.canonical`).

The model is evaluated once per call (:attr:`~diffsense.optimize.Problem.combined`): the
objective, the rows and the stage's rows all come from that evaluation.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from diffsense.design.inputs import SolveInputs
from diffsense.optimize import Problem
from diffsense.optimize.problem import default_scales

#: weight of the tie-breaking mean saturated slack in the canonical stage
TIE_WEIGHT = 1e-3


def variable_scales(model: "DesignModel", lower=None, upper=None) -> np.ndarray:
    """The solver's typical magnitude of each design variable and of t, as :class:`Problem`
    chooses them from bounds (:func:`~diffsense.optimize.problem.default_scales`): the model's
    box (t: 1) unless ``lower``/``upper`` (n + 1,) are given."""
    lower = np.append(model.lower, 0.0) if lower is None else np.asarray(lower, dtype=float)
    upper = np.append(model.upper, 1.0) if upper is None else np.asarray(upper, dtype=float)
    return default_scales(lower, upper, np.append(model.log_scale, False))


def design_problem(model: "DesignModel") -> Problem:
    """The problem of every solve of ``model`` (module docstring): variables (x, t), θ a
    :class:`SolveInputs`. Its bounds and scales are placeholders: each lane gives its own."""
    ineq = ~model.row_is_equality
    eq = model.row_is_equality
    m, p = int(ineq.sum()), int(eq.sum())

    def fgh(xt, s: SolveInputs):
        x, t = xt[:-1], xt[-1]
        r, f = model.residuals_and_objective(x, s)
        g = r[ineq]
        canonical = s.stage.canonical
        inactive = s.stage.inactive
        slack = jnp.maximum(-g, 0.0)
        count = jnp.maximum(jnp.sum(inactive), 1)
        tie = jnp.sum(jnp.where(inactive, slack / (1.0 + slack), 0.0)) / count
        objective = jnp.where(canonical, -(t + TIE_WEIGHT * tie), f)
        cap = jnp.where(canonical, f - s.stage.objective_cap, -1.0)
        raised = jnp.where(canonical & inactive, g + t, -1.0)
        return objective, jnp.concatenate([g, jnp.reshape(cap, (1,)), raised]), r[eq]

    lower = np.append(model.lower, 0.0)
    upper = np.append(model.upper, 0.0)
    return Problem(lambda xt, s: fgh(xt, s)[0], lower, upper,
                   inequality=lambda xt, s: fgh(xt, s)[1],
                   equality=(lambda xt, s: fgh(xt, s)[2]) if p else None,
                   log_scale=np.append(model.log_scale, False), integer=np.append(model.integer, False),
                   names=list(model.variable_names) + ["t"], combined=fgh, sizes=(2 * m + 1, p))


def requirement_problem(model: "DesignModel") -> Problem:
    """The design problem in x alone (no t, no stage): minimise the normalised objective subject
    to the requirement rows, θ a :class:`SolveInputs` (trade studies' continuation)."""
    ineq = ~model.row_is_equality
    eq = model.row_is_equality

    def fgh(x, s: SolveInputs):
        r, f = model.residuals_and_objective(x, s)
        return f, r[ineq], r[eq]

    return Problem(lambda x, s: fgh(x, s)[0], model.lower, model.upper, inequality=lambda x, s: fgh(x, s)[1],
                   equality=(lambda x, s: fgh(x, s)[2]) if eq.any() else None, log_scale=model.log_scale,
                   integer=model.integer, names=list(model.variable_names), combined=fgh,
                   sizes=(int(ineq.sum()), int(eq.sum())))


__all__ = ["design_problem", "requirement_problem", "variable_scales", "TIE_WEIGHT"]
