"""Post-optimal sensitivity: how the optimal design and objective move per unit change of each
requirement limit.

At the optimum x* of the chosen catalog combination, with integer variables held at their
rounded values, variables on a bound held there and A the set of active requirements
(requirement value v_a(x) on its limit b_a), the continuous free variables y (ln x for
log-scaled variables, x otherwise) satisfy the KKT conditions

    ∇F(y) + Σ_a μ_a ∇v_a(y) = 0,        v_a(y) − b_a = 0   (a ∈ A),

F the objective in its minimised form. Differentiating with respect to the limits b (the
implicit function theorem; Fiacco 1983 §3.2, Nocedal & Wright 2006 §12.8) gives

    [ W   Aᵀ ] [ dy/db ]   [ 0 ]
    [ A   0  ] [ dμ/db ] = [ I ],       W = ∇²F + Σ μ_a ∇²v_a,  A = ∂v_A/∂y,

and the envelope theorem gives the shadow prices dF*/db_a = −μ_a. The multipliers μ are
recomputed from the stationarity condition with the report's own derivatives (least
squares, its residual reported) and compared with the optimiser's multipliers. When as many
requirements are active as there are free variables and A is nonsingular (a vertex), dy/db =
A⁻¹ and W is not needed. The linear algebra — the least-squares multipliers, the KKT system
and its vertex case — is the optimiser's own (:mod:`diffsense.optimize.sensitivity`:
:func:`~diffsense.optimize.sensitivity.stationarity_multipliers`,
:func:`~diffsense.optimize.sensitivity.active_set_derivative`); this module assembles W and A
from the report's derivatives and reads the answer.

W is computed by fourth-order central differences (step 1e-3 in y) of the exact forward-mode
gradients of the Lagrangian, from the report's own evaluation program (no second-derivative
program is compiled); the largest difference between that estimate and the one with half the
step, relative to max |W|, is reported as its error estimate (``hessian_fd_rel_diff``: the
truncation error is O(h⁴), so halving h divides it by 16). Interval requirements are
differentiated at their worst points held fixed, as their first derivatives are (the envelope
theorem); at a worst point inside the box this leaves out the term of the worst point's motion.

Reported per variable: ``free`` (a derivative), ``lower``/``upper`` bound (on it by the
optimiser's own test, :func:`diffsense.optimize.bounds.variables_on_bounds`, which its
answers meet exactly; derivative 0 while the bound stays active), ``integer`` (held at its rounded value: derivative 0 locally, the
rounding may jump), ``not_unique`` (neither the objective nor an active requirement depends
on it to second order: the optimum is a continuum along it and has no derivative). Inactive
requirements have derivative 0 (a small change of their limit leaves the optimum unchanged).
"""

from __future__ import annotations

import math
from typing import List

import numpy as np

from diffsense.design.model import DesignModel
from diffsense.design.runner import bounds_problem
from diffsense.optimize.bounds import variables_on_bounds
from diffsense.design.activity import active_mask
from diffsense.optimize.sensitivity import active_set_derivative, kkt_matrix, stationarity_multipliers
from diffsense.report.inputs import Input

FLAT_TOL = 1e-9


def _status(model: DesignModel, x) -> List[str]:
    """Per variable: "integer", "lower"/"upper" (on that bound, by the optimiser's test) or "free"."""
    on_lo, on_hi = variables_on_bounds(bounds_problem(model), x)
    return ["integer" if model.integer[i] else "lower" if on_lo[i] else "upper" if on_hi[i] else "free"
            for i in range(len(model.variable_names))]


def post_optimal_section(model: DesignModel, inputs: List[Input], batch, x, combo_index: int,
                         derivative, req_values, multipliers, objective_scale: float) -> dict:
    """Sensitivities of the optimum (module docstring).

    ``batch``: the report's :class:`~diffsense.report.batch.BatchEvaluator`; ``derivative``:
    the report Jacobian (requirements then objective × inputs); ``req_values``: requirement
    outputs at x; ``multipliers``: the optimiser's multipliers (of the objective normalised by
    ``objective_scale``, :func:`~diffsense.design.runner.objective_scale`)."""
    x = np.asarray(x, dtype=float)
    obj_scale = float(objective_scale)
    req_values = np.asarray(req_values, dtype=float)
    lam_opt = np.asarray(multipliers, dtype=float)
    n_req = len(model.requirements)
    active = active_mask(model, model.requirement_rows(req_values), lam_opt)
    status = _status(model, x)
    var_cols = [next(k for k, inp in enumerate(inputs) if inp.kind == "variable" and inp.param == n)
                for n in model.variable_names]
    free = [i for i, s in enumerate(status) if s == "free"]
    obj_sign = model.spec.objective.sign
    # derivatives in y (ln x for log-scaled variables)
    dy_dx = np.array([x[i] if model.log_scale[i] else 1.0 for i in range(len(x))])
    D = np.asarray(derivative, dtype=float)
    grad_F = obj_sign * D[n_req, var_cols] * dy_dx  # minimised form F = sign * objective value
    jac_v = D[:n_req][:, var_cols] * dy_dx[None, :]
    act = np.flatnonzero(active)
    A = jac_v[np.ix_(act, free)]
    gF = grad_F[free]

    # variables on which neither F nor an active requirement depends to first order
    tiny_F = FLAT_TOL * max(1.0, float(np.max(np.abs(grad_F))) if grad_F.size else 1.0)
    flat_first = [j for j, i in enumerate(free)
                  if abs(gF[j]) <= tiny_F and (A.shape[0] == 0 or np.all(np.abs(A[:, j]) <= FLAT_TOL * max(1.0, np.max(np.abs(A)))))]

    # multipliers from stationarity on the free variables: gF + Aᵀ μ = 0
    mu = np.full(act.size, np.nan)
    stationarity = None
    if act.size and len(free):
        mu, residual = (np.asarray(v) for v in stationarity_multipliers(gF, A))
        stationarity = float(residual)
    shadow_opt = -obj_sign * lam_opt * model.sign / model.scales * obj_scale
    shadow_kkt = np.full(n_req, np.nan)
    shadow_kkt[act] = -obj_sign * mu  # envelope theorem: dF*/db = ∂L/∂b = −μ

    section = {
        "active": [bool(a) for a in active],
        "variable_status": status,
        "shadow_price_optimizer": shadow_opt,
        "shadow_price_kkt": shadow_kkt,
        "stationarity_rel_residual": stationarity,
        "hessian": None,
        "hessian_note": None,
        "hessian_fd_rel_diff": None,
        "dx_dlimit": None,
        "reason": None,
    }

    keep = [j for j in range(len(free)) if j not in flat_first]
    need_hessian = bool(flat_first) or len(keep) != act.size
    W = None
    if need_hessian and len(free):
        W, check = _lagrangian_hessian(model, inputs, batch, x, free, var_cols, act, mu, obj_sign)
        section["hessian"] = "central differences of forward-mode gradients"
        section["hessian_note"] = ("fourth-order central differences (step 1e-3 in y) of the exact gradients; "
                                   "error estimate from the half step in hessian_fd_rel_diff")
        section["hessian_fd_rel_diff"] = check
    flat = []
    if W is not None:
        wmax = max(float(np.max(np.abs(W))), 1e-300)
        flat = [j for j in flat_first if np.all(np.abs(W[j, :]) <= 1e-8 * wmax)]
        keep = [j for j in range(len(free)) if j not in flat]
    elif flat_first:
        flat = flat_first
    for j in flat:
        status[free[j]] = "not_unique"
    section["variable_status"] = status

    dx = np.zeros((len(x), n_req))
    for j in flat:
        dx[free[j], :] = np.nan
    if act.size == 0 or not keep:
        section["dx_dlimit"] = dx
        section["method"] = "no active requirement on a free variable: the optimum does not move with the limits"
        return section
    Ak = A[:, keep]
    # the active constraints are v_A(y) − b = 0: ∂(∇L)/∂b = 0 and ∂c/∂b = −I
    r_b, c_b = np.zeros((len(keep), act.size)), -np.eye(act.size)
    try:
        if len(keep) == act.size and np.linalg.matrix_rank(Ak) == act.size:
            dy, _ = active_set_derivative(None, Ak, r_b, c_b)  # (keep, act)
            section["method"] = "vertex: dy/db = A⁻¹ (as many active requirements as free variables)"
        else:
            if W is None:
                raise np.linalg.LinAlgError("the Hessian of the Lagrangian is not available")
            Wk = W[np.ix_(keep, keep)]
            cond = np.linalg.cond(np.asarray(kkt_matrix(Wk, Ak)))
            if not np.isfinite(cond) or cond > 1e14:
                raise np.linalg.LinAlgError(f"KKT matrix singular (condition number {cond:.3g}): degenerate active set")
            dy, _ = active_set_derivative(Wk, Ak, r_b, c_b)
            section["method"] = "implicit function theorem on the active-set KKT system"
        dy = np.asarray(dy)
    except np.linalg.LinAlgError as exc:
        section["reason"] = str(exc)
        return section
    for jj, j in enumerate(keep):
        i = free[j]
        dx[i, act] = dy[jj] * dy_dx[i]
    section["dx_dlimit"] = dx
    weak = [int(a) for k, a in enumerate(act) if abs(mu[k]) <= 1e-9 * max(1.0, float(np.max(np.abs(mu))))]
    section["weakly_active"] = weak
    return section


def _lagrangian_hessian(model, inputs, batch, x, free, var_cols, act, mu, obj_sign):
    """W over the free variables (in y) by :func:`_hessian_by_differences`, and its error
    estimate: the largest difference from the estimate with half the step, relative to max |W|."""
    if not batch.tangents_available:
        raise np.linalg.LinAlgError(f"no derivatives available for the Hessian ({batch.tangents_error})")
    base = {k: float(inp.value) for k, inp in enumerate(inputs)}
    for i, k in enumerate(var_cols):
        base[k] = float(x[i])
    logs = [bool(model.log_scale[i]) for i in free]
    cols = [var_cols[i] for i in free]
    y0 = np.array([math.log(x[i]) if model.log_scale[i] else x[i] for i in free])
    mu_full = np.zeros(len(model.requirements))
    mu_full[act] = np.nan_to_num(mu)
    W = _hessian_by_differences(batch, inputs, base, cols, logs, y0, mu_full, obj_sign, 1e-3)
    W_half = _hessian_by_differences(batch, inputs, base, cols, logs, y0, mu_full, obj_sign, 5e-4)
    check = float(np.max(np.abs(W - W_half)) / max(float(np.max(np.abs(W))), 1e-300))
    return W, check


def _hessian_by_differences(batch, inputs, base, cols, logs, y0, mu_full, obj_sign, h: float = 1e-3):
    """W by fourth-order central differences (step ``h`` in y) of the forward-mode gradient."""
    v0 = np.array([base[k] for k in range(len(inputs))])
    n = len(cols)
    rows, tans = [], []
    for j in range(n):
        for s in (-2, -1, 1, 2):
            yj = y0.copy()
            yj[j] += s * h * (1.0 if logs[j] else max(1.0, abs(y0[j])))
            r = v0.copy()
            for q, k in enumerate(cols):
                r[k] = math.exp(yj[q]) if logs[q] else yj[q]
            for t in range(n):
                tv = np.zeros(len(inputs))
                tv[cols[t]] = math.exp(yj[t]) if logs[t] else 1.0  # tangent of x along y_t
                rows.append(r)
                tans.append(tv)
    _, (_, req_t, obj_t) = batch(np.array(rows), np.array(tans))
    g = (obj_sign * np.asarray(obj_t) + np.asarray(req_t) @ mu_full).reshape(n, 4, n)
    W = np.zeros((n, n))
    for j in range(n):
        hj = h * (1.0 if logs[j] else max(1.0, abs(y0[j])))
        fm2, fm1, fp1, fp2 = g[j]
        W[:, j] = (fm2 - 8.0 * fm1 + 8.0 * fp1 - fp2) / (12.0 * hj)
    return 0.5 * (W + W.T)


__all__ = ["post_optimal_section"]
