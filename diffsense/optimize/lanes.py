"""Lanes: many solves of one problem through one compiled program, driven from the host.

A *lane* is one solve of a :class:`~diffsense.optimize.problem.Problem`: a start x0,
parameters θ and a box (lower, upper). A study is a set of lanes — the starts of a multistart,
the options of a catalog (θ carries the option's row, the box may fix what the option fixes),
the integer neighbours of a relaxed optimum (the box pins the integers,
:func:`diffsense.optimize.integer.integer_neighbours`), a re-solve with other θ — and every
lane goes through one jitted program (:func:`make_lane_solver`) that takes θ and the box as
arguments, so all the steps of a study reuse one compilation (a design model's copy in a
compiled program costs seconds).

How the program goes through its lanes is ``lockstep`` (see
:func:`diffsense.optimize.batch.map_in_lockstep`): a vmapped batch advances in lockstep, each
while loop of the solve running as many trips as its slowest lane needs, on every lane;
``lockstep=1`` runs the lanes one after another inside the program (the work is the sum of
the lanes' own work), None all in one vmap, "auto" 1 on CPU and None on an accelerator.
Measured on the ore-pass design (80 lanes, 2-core CPU, ``benchmarks/bench_design.py``
section 5): 0.68 s one after another against 3.8 s with 10 lanes per vmap and 7.0 s with all
80 in one vmap.

:func:`solve_in_batches` calls a program on batches of a fixed number of lanes (the last one
padded by repeating its final lane, optionally pinned at its start so that it costs nothing),
so a later step with another number of lanes reuses the first step's compiled program;
:func:`best_per_group` picks the best feasible lane of each group (a catalog option, a start's
neighbours).
"""

from __future__ import annotations

import concurrent.futures
import os
from typing import Any, NamedTuple, Optional, Union

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.optimize.batch import map_in_lockstep, resolve_lockstep
from diffsense.optimize.compile import call_compiling_alongside, jit_with_options
from diffsense.optimize.entry import solve
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem
from diffsense.optimize.result import Result


class Lanes(NamedTuple):
    """Lanes of a study (NumPy arrays; leading axis: the lane).

    ``x0``: starts (L, n); ``theta``: parameters, a pytree whose leaves have a leading axis L
    (None for a problem without parameters); ``lower``, ``upper``: boxes (L, n); ``group``:
    (L,) index of the group each lane belongs to (its catalog option, its start, ...)."""

    x0: np.ndarray
    theta: Any
    lower: np.ndarray
    upper: np.ndarray
    group: np.ndarray


def take(tree, rows):
    """The rows ``rows`` of every leaf of a pytree of arrays (NumPy)."""
    return jax.tree_util.tree_map(lambda a: np.asarray(a)[rows], tree)


def lane_grid(starts, group_thetas=None, *, lower, upper, n_groups: Optional[int] = None) -> Lanes:
    """Every (start, group) pair as a lane, start-major (lanes k·G … (k+1)·G − 1 are start k's
    groups), each in the box (``lower``, ``upper``) (n,). ``group_thetas``: pytree whose leaves
    have a leading axis of G groups (each group's θ), or None (θ None, G = ``n_groups`` or 1).

    >>> lanes = lane_grid([[0.1], [0.9]], np.array([10.0, 20.0, 30.0]), lower=[0.0], upper=[1.0])
    >>> lanes.x0[:, 0].tolist(), lanes.theta.tolist(), lanes.group.tolist()
    ([0.1, 0.1, 0.1, 0.9, 0.9, 0.9], [10.0, 20.0, 30.0, 10.0, 20.0, 30.0], [0, 1, 2, 0, 1, 2])
    """
    starts = np.atleast_2d(np.asarray(starts, dtype=float))
    n_s = starts.shape[0]
    leaves = jax.tree_util.tree_leaves(group_thetas)
    G = int(np.shape(leaves[0])[0]) if leaves else (1 if n_groups is None else int(n_groups))
    group = np.tile(np.arange(G), n_s)
    x0 = np.repeat(starts, G, axis=0)
    theta = None if group_thetas is None else take(group_thetas, group)
    box = (np.broadcast_to(np.asarray(lower, dtype=float), x0.shape),
           np.broadcast_to(np.asarray(upper, dtype=float), x0.shape))
    return Lanes(x0, theta, box[0], box[1], group)


def pin_variables(lower, upper, x, mask):
    """Boxes (lower, upper), rows like ``x``, with the variables of ``mask`` fixed at their
    value in ``x`` (lower = upper = x): a lane solved in that box holds them there exactly."""
    x = np.asarray(x, dtype=float)
    lower = np.where(mask, x, np.broadcast_to(lower, x.shape))
    upper = np.where(mask, x, np.broadcast_to(upper, x.shape))
    return lower, upper


def lane_program(problem: Problem, options: SolverOptions = SolverOptions(),
                 lockstep: Union[int, str, None] = None):
    """The pure function ``fn(x0, theta, lower, upper, scale=None) -> Result`` solving lanes
    (leading axis of every argument; ``theta`` may be None; ``scale``, the variables' typical
    magnitudes per lane, replaces the problem's own when given) with ``lockstep`` lanes per
    vmap (module docstring); jit it, or use :func:`make_lane_solver`. The lane count must be a
    multiple of a lockstep count."""
    k = resolve_lockstep(lockstep)

    def one(x0, theta, lower, upper, scale=None):
        return solve(problem.with_bounds(lower, upper, scale), x0, theta, options)

    def run(x0, theta, lower, upper, scale=None):
        if scale is None:
            return map_in_lockstep(one, (x0, theta, lower, upper), k)
        return map_in_lockstep(one, (x0, theta, lower, upper, scale), k)

    return run


def make_lane_solver(problem: Problem, options: SolverOptions = SolverOptions(), *,
                     lockstep: Union[int, str, None] = "auto", compile: str = "optimized"):
    """:func:`lane_program` jitted with the XLA options of ``compile`` (compiled once per
    number of lanes)."""
    return jit_with_options(lane_program(problem, options, lockstep), compile)


def solve_in_batches(solver, batch: int, *columns, alongside=None, threads: Optional[int] = None,
                     pin_padding: bool = False):
    """``solver(*columns)`` over the rows of ``columns`` (pytrees whose leaves have a leading
    row axis) in calls of exactly ``batch`` rows, the last one padded by repeating its final
    row, so every call reuses the program compiled for the first. With ``pin_padding`` the
    columns are a lane program's ``(x0, θ, lower, upper, …)`` and each padding row's box is
    pinned at its start (lower = upper = x0): the solver returns such a lane at once, so a
    call of one real lane does not solve it ``batch`` times (on CPU the lanes of a call run one
    after another). Padding rows' results are dropped either way. With ``alongside``, the
    first call's compilation runs in a background thread while this thread calls
    ``alongside()`` (:func:`diffsense.optimize.compile.call_compiling_alongside`). Returns the
    outputs as NumPy arrays, one row per input row.

    The first call runs here (it compiles the program when needed); the others run on
    ``threads`` threads (default: the cores this process may use, :func:`worker_count`): a
    compiled program runs without Python's global interpreter lock, so on a 2-core machine two
    batches run at once. Each batch's answer does not depend on which thread ran it."""
    n = int(jax.tree_util.tree_leaves(columns)[0].shape[0])
    if n == 0:
        raise DomainError("solve_in_batches: no rows to solve")

    def call(start, first=False):
        rows = np.arange(start, min(start + batch, n))
        padded = np.concatenate([rows, np.full(batch - rows.size, rows[-1])])
        # host arrays go to the compiled call as they are (jnp.asarray outside a trace would
        # compile a small staging program per shape)
        args = tuple(take(c, padded) for c in columns)
        if pin_padding and rows.size < batch:
            start = np.asarray(args[0])
            pinned = np.arange(batch) >= rows.size
            args = args[:2] + tuple(np.where(pinned[:, None], start, np.asarray(a)) for a in args[2:4]) + args[4:]
        res = call_compiling_alongside(solver, args, alongside) if first and alongside is not None else solver(*args)
        return jax.tree_util.tree_map(lambda a, k=rows.size: np.asarray(a)[:k], res)

    starts = list(range(0, n, batch))
    outs = [call(starts[0], first=True)]
    rest = starts[1:]
    workers = min(len(rest), worker_count() if threads is None else int(threads))
    if workers > 1:
        with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
            outs += list(pool.map(call, rest))
    else:
        outs += [call(s) for s in rest]
    return jax.tree_util.tree_map(lambda *a: np.concatenate(a), *outs)


def worker_count() -> int:
    """The cores this process may run on (its CPU affinity), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def solve_lanes(solver, lanes: Lanes, batch: Optional[int] = None, alongside=None) -> Result:
    """The :class:`Result` of every lane (NumPy), by a solver of :func:`make_lane_solver`, in
    calls of ``batch`` lanes (default: all in one call); see :func:`solve_in_batches`."""
    batch = lanes.x0.shape[0] if batch is None else batch
    return solve_in_batches(solver, batch, lanes.x0, lanes.theta, lanes.lower, lanes.upper, alongside=alongside,
                            pin_padding=True)


def best_per_group(result: Result, group, n_groups: int, ok=None):
    """(rows, found): for each group g < ``n_groups``, the lane of ``group == g`` with the
    lowest f among those that are ``ok`` (default: feasible) with a finite f — the first such
    lane on ties — or, when there is none, the least infeasible lane (smallest scaled
    violation); ``found[g]`` tells which. Every group needs a lane.

    >>> from types import SimpleNamespace as NS
    >>> r = NS(f=np.array([3.0, 1.0, 2.0, 5.0]), feasible=np.array([True, False, True, False]),
    ...        kkt=NS(feasibility=np.array([0.0, 0.2, 0.0, 0.1])))
    >>> rows, found = best_per_group(r, np.array([0, 0, 0, 1]), 2)
    >>> rows.tolist(), found.tolist()
    ([2, 3], [True, False])
    """
    f = np.asarray(result.f)
    ok = np.asarray(result.feasible if ok is None else ok, dtype=bool)
    violation = np.asarray(result.kkt.feasibility)
    group = np.asarray(group)
    rows = np.zeros(n_groups, dtype=int)
    found = np.zeros(n_groups, dtype=bool)
    for g in range(n_groups):
        idx = np.flatnonzero(group == g)
        if idx.size == 0:
            raise DomainError(f"best_per_group: group {g} has no lane")
        score = np.where(ok[idx] & np.isfinite(f[idx]), f[idx], np.inf)
        found[g] = bool(np.isfinite(score).any())
        rows[g] = idx[int(np.argmin(score))] if found[g] else idx[int(np.argmin(violation[idx]))]
    return rows, found


__all__ = ["Lanes", "take", "lane_grid", "pin_variables", "lane_program", "make_lane_solver", "solve_in_batches",
           "solve_lanes", "best_per_group"]
