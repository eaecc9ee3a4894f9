"""Constrained gradient optimisation of design problems (generic layer; no sensor chains).

    minimise f(x, θ)  s.t.  g(x, θ) ≤ 0,  h(x, θ) = 0,  lower ≤ x ≤ upper

* :mod:`.problem` — :class:`Problem` (functions, bounds, variable scaling, log scaling,
  integer flags).
* :mod:`.constrained` — :func:`solve`: PHR augmented Lagrangian over a bounded inner solve
  (BFGS on a bounded reparameterisation run inside the outer loop by :mod:`.al_fused`, one
  evaluation of the problem per trip; or nested: optimistix BFGS, jaxopt L-BFGS-B),
  active-set Newton polish, least-infeasibility restoration; :func:`make_solver` for a jitted
  solver.
* :mod:`.sqp` — ``SolverOptions(method="sqp")``: SQP with damped BFGS, one linearisation per
  loop trip, an ℓ1 merit line search with second-order correction; its subproblems by
  :mod:`.active_set` (Goldfarb–Idnani dual active-set QP) and, when the linearised constraints
  are inconsistent, as elastic QPs by :mod:`.qp` (dense interior-point QP solver).
* :mod:`.sensitivity` — implicit KKT derivatives dx*/dθ, envelope df*/dθ (shadow prices),
  :func:`differentiable_solver` (custom JVP).
* :mod:`.integer` — integer variables (relax, round, verify neighbours) and catalog choices.
* :mod:`.multistart` — scrambled Sobol / Latin hypercube starts, clustering, success rate.
* :mod:`.batch` — vmapped sweeps over θ, sharded across devices.
* :mod:`.reference_problems` — Hock–Schittkowski and closed-form test problems.
"""

from diffsense.optimize.problem import Problem
from diffsense.optimize.constrained import (
    Conflict,
    KKTResidual,
    Result,
    Scales,
    SolverOptions,
    compiler_options,
    jit_with_options,
    make_solver,
    solve,
    violation,
)
from diffsense.optimize.sensitivity import (
    Sensitivity,
    Solution,
    differentiable_solver,
    kkt_sensitivity,
    shadow_prices,
)
from diffsense.optimize.integer import CatalogResult, MixedIntegerResult, solve_catalog, solve_mixed_integer
from diffsense.optimize.multistart import (
    MultistartResult,
    latin_hypercube,
    make_multistart,
    multistart,
    run_multistart,
    sobol_points,
    start_points,
)
from diffsense.optimize.batch import make_batch_solver, solve_batch

__all__ = [
    "Problem", "SolverOptions", "Result", "KKTResidual", "Conflict", "Scales", "solve", "make_solver",
    "violation", "compiler_options", "jit_with_options", "Sensitivity", "Solution", "kkt_sensitivity", "shadow_prices",
    "differentiable_solver", "MixedIntegerResult", "CatalogResult", "solve_mixed_integer", "solve_catalog",
    "MultistartResult", "sobol_points", "latin_hypercube", "start_points", "multistart", "make_multistart",
    "run_multistart", "solve_batch", "make_batch_solver",
]
