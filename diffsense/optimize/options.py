"""Settings of the constrained solvers: one frozen, hashable :class:`SolverOptions`.

``method`` and ``inner`` pick the solver (:func:`diffsense.optimize.entry.solver_for` maps
them to a solve function); the other fields are the tolerances and iteration caps of that
solver. Being hashable, an options value is a static argument: each distinct value is one
jit compilation.
"""

from __future__ import annotations

from dataclasses import dataclass

from diffsense.numerics.checks import check_choice, check_range

#: the solver methods and the augmented Lagrangian's inner solvers
METHODS = ("al", "sqp")
INNER_SOLVERS = ("lbfgsb", "bfgs", "fused")


@dataclass(frozen=True)
class SolverOptions:
    """Static settings of :func:`diffsense.optimize.solve` (hashable; one jit compilation per
    distinct value).

    ``tol``: stationarity and complementarity tolerance (scaled, dimensionless).
    ``feas_tol``: constraint-violation tolerance on the scaled constraints.
    ``max_outer``/``max_inner``: augmented-Lagrangian and inner-solver iteration caps (the
    inner cap is kept small: subproblems are warm-started, and under vmap one slow inner
    solve would hold up the whole batch).
    ``inner``: "fused" (default: BFGS over the bounded reparameterisation run inside the
    outer loop, one evaluation of the problem per trip, :mod:`.al_fused`), "bfgs" (optimistix
    BFGS over the same reparameterisation, nested) or "lbfgsb" (jaxopt L-BFGS-B on the box
    itself, nested); the nested ones are in :mod:`.al_nested`.
    ``history_size``: L-BFGS-B memory (``inner="lbfgsb"`` only).
    ``penalty_init``, ``penalty_growth``, ``penalty_max``: ρ₀, its growth factor and cap.
    ``multiplier_max``: safeguard bound on |λ̃|, |ν̃| (scaled multipliers).
    ``inner_tol_init``: first inner tolerance, divided by 100 per outer iteration down to tol.
    ``feasibility_reduction``: required decrease factor of V before ρ is left unchanged.
    ``polish``/``polish_steps``/``polish_start``: active-set Newton refinement of the KKT
    point (:func:`diffsense.optimize.kkt.polish_newton`), tried in each outer iteration whose
    KKT residual is below ``polish_start``.
    ``active_tol``: scaled constraint value above which an inequality counts as active.
    ``f_scale``: "auto" or a positive number multiplying f; ``constraint_scaling``: scale g, h.
    ``restore``: run the least-infeasibility solve when the answer is infeasible.
    ``max_line_search``: trials per line search (SQP, and the fused AL's BFGS).
    ``method``: "al" (the augmented Lagrangian of :mod:`.al`) or "sqp" (:mod:`.sqp`, for small
    dense problems; uses ``max_sqp``, ``qp_iterations`` and ``elastic_weight`` (the
    interior-point steps and ℓ1 weight of its elastic subproblem) and ``max_line_search``, and
    none of the AL-specific settings).
    """

    tol: float = 1e-8
    feas_tol: float = 1e-8
    max_outer: int = 40
    max_inner: int = 100
    inner: str = "fused"
    history_size: int = 10
    penalty_init: float = 10.0
    penalty_growth: float = 10.0
    penalty_max: float = 1e8
    feasibility_reduction: float = 0.25
    multiplier_max: float = 1e12
    inner_tol_init: float = 1e-3
    polish: bool = True
    polish_steps: int = 4
    polish_start: float = 1e-3
    active_tol: float = 1e-6
    f_scale: object = "auto"
    constraint_scaling: bool = True
    restore: bool = True
    method: str = "al"
    max_sqp: int = 100
    qp_iterations: int = 30
    elastic_weight: float = 1e3
    max_line_search: int = 20

    def __post_init__(self):
        check_choice("inner", self.inner, INNER_SOLVERS, where="SolverOptions")
        check_choice("method", self.method, METHODS, where="SolverOptions")
        check_range("max_sqp", self.max_sqp, 1, None, where="SolverOptions")
        check_range("qp_iterations", self.qp_iterations, 1, None, where="SolverOptions")
        check_range("elastic_weight", self.elastic_weight, 0.0, None, lo_open=True, where="SolverOptions")
        check_range("max_line_search", self.max_line_search, 1, None, where="SolverOptions")
        check_range("tol", self.tol, 0.0, 1.0, lo_open=True, where="SolverOptions")
        check_range("feas_tol", self.feas_tol, 0.0, 1.0, lo_open=True, where="SolverOptions")
        check_range("max_outer", self.max_outer, 1, None, where="SolverOptions")
        check_range("max_inner", self.max_inner, 1, None, where="SolverOptions")
        check_range("penalty_init", self.penalty_init, 0.0, None, lo_open=True, where="SolverOptions")
        check_range("penalty_growth", self.penalty_growth, 1.0, None, lo_open=True, where="SolverOptions")
        check_range("penalty_max", self.penalty_max, self.penalty_init, None, where="SolverOptions")
        check_range("feasibility_reduction", self.feasibility_reduction, 0.0, 1.0, lo_open=True, hi_open=True,
                    where="SolverOptions")
        if self.f_scale != "auto":
            check_range("f_scale", self.f_scale, 0.0, None, lo_open=True, where="SolverOptions")


__all__ = ["SolverOptions", "METHODS", "INNER_SOLVERS"]
