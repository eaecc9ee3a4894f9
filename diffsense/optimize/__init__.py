"""Constrained gradient optimisation of design problems (generic layer; no sensor chains).

    minimise f(x, θ)  s.t.  g(x, θ) ≤ 0,  h(x, θ) = 0,  lower ≤ x ≤ upper

* :mod:`.problem` — :class:`Problem` (functions, bounds, variable scaling, log scaling,
  integer flags).
* :mod:`.entry` — :func:`solve` (the method chosen by :class:`SolverOptions`, from
  :mod:`.options`; every method returns the :class:`Result` of :mod:`.result`), :func:`make_solver`
  for a jitted solver, :func:`violation`. The methods:

  * :mod:`.al` — PHR augmented Lagrangian over a bounded inner solve, active-set Newton polish,
    least-infeasibility restoration; its inner BFGS fused into the outer loop (:mod:`.al_fused`,
    one evaluation of the problem per trip) or nested (:mod:`.al_nested`: optimistix BFGS,
    jaxopt L-BFGS-B);
  * :mod:`.sqp` — ``SolverOptions(method="sqp")``: SQP with damped BFGS, one linearisation per
    loop trip, an ℓ1 merit line search with second-order correction; its subproblems by
    :mod:`.active_set` (Goldfarb–Idnani dual active-set QP) and, when the linearised
    constraints are inconsistent, as elastic QPs by :mod:`.qp` (dense interior-point QP solver).

  What they share: :mod:`.kernel` (scaled model, linearisation, function scales), :mod:`.kkt`
  (KKT residuals, convergence test, active-set KKT equations and their Newton polish),
  :mod:`.bounds` (the one "on a bound" tolerance, snapping, bound multipliers, the box
  reparameterisation); :mod:`.compile` (XLA option presets).
* :mod:`.sensitivity` — implicit KKT derivatives dx*/dθ, envelope df*/dθ (shadow prices),
  :func:`differentiable_solver` (custom JVP).
* :mod:`.lanes` — many solves of one problem (starts, catalog options, integer neighbours,
  re-solves) through one compiled program, in fixed-size batches; best lane per group.
* :mod:`.integer` — integer variables (relax, round, verify neighbours) and catalog choices.
* :mod:`.multistart` — scrambled Sobol / Latin hypercube starts, clustering, success rate.
* :mod:`.batch` — vmapped sweeps over θ, sharded across devices.
* :mod:`.reference_problems` — Hock–Schittkowski and closed-form test problems.
"""

from diffsense.optimize.problem import Problem
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.result import Conflict, KKTResidual, Result, Scales
from diffsense.optimize.compile import compiler_options, jit_with_options
from diffsense.optimize.entry import make_solver, solve, violation
from diffsense.optimize.sensitivity import (
    Sensitivity,
    Solution,
    differentiable_solver,
    kkt_sensitivity,
    shadow_prices,
)
from diffsense.optimize.lanes import Lanes, best_per_group, lane_grid, make_lane_solver, solve_lanes
from diffsense.optimize.integer import (
    CatalogResult,
    MixedIntegerResult,
    integer_neighbours,
    solve_catalog,
    solve_mixed_integer,
)
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
    "differentiable_solver", "Lanes", "lane_grid", "make_lane_solver", "solve_lanes", "best_per_group",
    "MixedIntegerResult", "CatalogResult", "solve_mixed_integer", "solve_catalog", "integer_neighbours",
    "MultistartResult", "sobol_points", "latin_hypercube", "start_points", "multistart", "make_multistart",
    "run_multistart", "solve_batch", "make_batch_solver",
]
