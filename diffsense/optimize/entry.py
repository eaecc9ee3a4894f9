"""The entry point of the constrained solvers: :func:`solve`, :func:`make_solver`, :func:`violation`.

    minimise f(x, θ)  s.t.  g(x, θ) ≤ 0,  h(x, θ) = 0,  lower ≤ x ≤ upper

``SolverOptions.method`` and ``inner`` pick the solve function from a table
(:func:`solver_for`); every method returns the same :class:`~diffsense.optimize.result.Result`:

* ``method="al"`` — augmented Lagrangian (:mod:`.al`), its inner BFGS fused into the outer loop
  (``inner="fused"``, :mod:`.al_fused`) or nested (``"bfgs"``, ``"lbfgsb"``, :mod:`.al_nested`);
* ``method="sqp"`` — sequential quadratic programming (:mod:`.sqp`).

The methods never import this module; it imports them.
"""

from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp

from diffsense.optimize.al_fused import solve_al_fused
from diffsense.optimize.al_nested import solve_al_nested
from diffsense.optimize.compile import jit_with_options
from diffsense.optimize.kernel import inf_norm
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem
from diffsense.optimize.result import Result
from diffsense.optimize.sqp import solve_sqp

#: solve function of each (method, inner solver); the SQP has no inner solver
_SOLVERS = {
    ("al", "fused"): solve_al_fused,
    ("al", "bfgs"): solve_al_nested,
    ("al", "lbfgsb"): solve_al_nested,
    ("sqp", None): solve_sqp,
}


def solver_for(options: SolverOptions) -> Callable[[Problem, object, object, SolverOptions], Result]:
    """The solve function ``fn(problem, x0, theta, options)`` that ``options`` select."""
    return _SOLVERS[(options.method, options.inner if options.method == "al" else None)]


def solve(problem: Problem, x0, theta=None, options: SolverOptions = SolverOptions()) -> Result:
    """Minimise ``problem`` from ``x0`` (units of the variables) at parameters ``theta``.

    With the default ``options``: augmented-Lagrangian outer loop over a bounded inner solve
    with an active-set Newton polish once the KKT residual is below ``polish_start``, and a
    least-infeasibility restoration when the loop ends infeasible (:mod:`.al`); with
    ``options.method="sqp"`` the SQP solver of :mod:`.sqp`. Pure and fixed-shape: jit it, vmap
    it over ``x0`` and ``theta``. Returns a :class:`Result`; ``x`` lies inside [lower, upper]
    whatever happens. Local method: the answer is a KKT point reached from ``x0`` (see
    :mod:`diffsense.optimize.multistart` for several starts).
    """
    return solver_for(options)(problem, x0, theta, options)


def make_solver(problem: Problem, options: SolverOptions = SolverOptions(), *, batched: bool = False,
                compile: str = "optimized"):
    """A jitted ``fn(x0, theta=None) -> Result`` for ``problem`` (compiled once per input shape).

    With ``batched=True`` it is vmapped over a leading axis of ``x0`` and of every leaf of
    ``theta`` (``theta=None`` for problems without parameters). ``compile`` picks XLA options:
    "optimized" (default), "fast" (quicker compilation, slower run; for tests and one-off
    solves) or "default" (XLA's own)."""

    def run(x0, theta=None):
        return solve(problem, x0, theta, options)

    fn = run
    if batched:
        def run_batch(x0, theta=None):
            if theta is None:
                return jax.vmap(lambda x: run(x, None))(x0)
            return jax.vmap(run)(x0, theta)
        fn = run_batch
    return jit_with_options(fn, compile)


def violation(result: Result) -> jax.Array:
    """Largest physical constraint violation max(max(g, 0), |h|) of a result (units of g, h)."""
    return jnp.maximum(inf_norm(jnp.maximum(result.g, 0.0)), inf_norm(result.h))


__all__ = ["solve", "solver_for", "make_solver", "violation"]
