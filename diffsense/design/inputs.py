"""θ: every number a design model's programs read, as named pytrees of arrays.

A compiled program of a spec is a function of its structure (sensor parts, options, the variable
set, the requirement set: static) and of these inputs (traced), so that editing a value in the
spec, moving a slider or adding a worst point changes only the numbers fed to the same program.

* :class:`DesignInputs` — what an evaluation reads: the input vector of every chain parameter
  (:mod:`diffsense.design.layout`), the catalog cost, the objective weights, the requirement
  scales, the interval requirements' boxes and slots (:mod:`diffsense.design.intervals`), and the
  chance constraints' design sample, spreads and quantile levels (:mod:`diffsense.design.chance`).
* :class:`Stage` — which problem a solve is: the design problem, or the canonical second stage
  (:mod:`diffsense.design.canonical`) with its objective cap and the rows whose slack it raises.
* :class:`SolveInputs` — what one solve (a lane of the optimiser) reads: the design inputs, the
  requirement limits (tightened as the step asks), the objective's scale and the stage.
"""

from __future__ import annotations

from typing import NamedTuple, Tuple

import jax


class DesignInputs(NamedTuple):
    """The numbers of an evaluation (every leaf an array).

    ``values`` (n_in,): the input vector (:class:`~diffsense.design.layout.InputLayout`; a solve
    overwrites its variables' and catalog entries); ``cost`` (): the catalog combination's cost;
    ``weights`` (t,): the objective terms' weights; ``scales`` (r,): the requirements' scales;
    ``box`` — (lower, upper, log), each a tuple over the interval requirements of (d,) arrays;
    ``points``: per interval requirement its slots (K_j, d_j); ``sample`` (N, u): the chance
    constraints' uniform design sample; ``spreads`` (u,): their distributions' spreads;
    ``alpha`` (c,): their quantile levels.
    """

    values: jax.Array
    cost: jax.Array
    weights: jax.Array
    scales: jax.Array
    box: Tuple[Tuple[jax.Array, ...], Tuple[jax.Array, ...], Tuple[jax.Array, ...]]
    points: Tuple[jax.Array, ...]
    sample: jax.Array
    spreads: jax.Array
    alpha: jax.Array


class Stage(NamedTuple):
    """Which problem a solve is. ``canonical`` (): False for the design problem, True for the
    canonical second stage; ``objective_cap`` (): its cap on the normalised objective;
    ``inactive`` (m,): the inequality rows whose smallest slack it maximises."""

    canonical: jax.Array
    objective_cap: jax.Array
    inactive: jax.Array


class SolveInputs(NamedTuple):
    """The numbers of one solve: ``design`` (:class:`DesignInputs`, catalog row and variables
    written into its vector by the solve), ``catalog`` (c,): the catalog parameters' values,
    ``limits`` (r,): the requirement limits, ``objective_scale`` (): the objective's
    normalisation, ``stage`` (:class:`Stage`)."""

    design: DesignInputs
    catalog: jax.Array
    limits: jax.Array
    objective_scale: jax.Array
    stage: Stage


__all__ = ["DesignInputs", "Stage", "SolveInputs"]
