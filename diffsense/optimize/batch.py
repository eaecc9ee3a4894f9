"""Batches of problems (a sweep over θ, many specs) in one compiled, sharded call.

``solve_batch`` maps :func:`diffsense.optimize.solve` over a leading batch axis of x0 and of
every θ leaf. ``make_batch_solver`` jits that and, with ``shard=True``, splits the batch
across all available devices: a 1-D ``jax.sharding.Mesh`` named "batch" over the devices and
``NamedSharding(mesh, PartitionSpec("batch"))`` on every input and output. Inside the program
the batch is reshaped to (devices, problems per device) and vmapped over the device axis, the
sharded one, so XLA's SPMD partitioner gives each device its own problems.

How a device goes through its problems is ``lockstep`` (:func:`map_in_lockstep`). A vmapped
batch advances in lockstep: every while loop of the solve runs as many trips as its slowest
problem needs, on every problem. ``lockstep="auto"`` (default of ``make_batch_solver``) solves
them one after another (``jax.lax.map``) on CPU, where the work is then the sum of the
problems' own work, and all in one vmap on an accelerator, which is wide enough to run them
side by side. Across devices the loops still advance together (the partitioned program
all-reduces each loop's "still running" flag), so a device waits for the slowest device's
current problem. Measured on the ore-pass model at B = 256 (``benchmarks/bench_design.py``,
section 3): see the README's speed table. (Per-device independent programs via
``jax.shard_map``/``pmap`` are not used: in JAX 0.10 lineax, which optimistix's BFGS uses,
rejects the sharding-annotated shapes it sees inside them.) The batch is padded to a multiple
of (devices × lockstep) by repeating its last element and trimmed again. On a machine with one
device the sharded and unsharded programs are the same. On CPU, XLA can be told to expose
several host devices with ``XLA_FLAGS=--xla_force_host_platform_device_count=N`` (set before
JAX starts)."""

from __future__ import annotations

from typing import Optional, Sequence, Union

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from diffsense.errors import DomainError
from diffsense.optimize.compile import jit_with_options
from diffsense.optimize.entry import solve
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.result import Result
from diffsense.optimize.problem import Problem


def _batch_size(x0, thetas) -> int:
    sizes = set()
    if np.ndim(x0) == 2:
        sizes.add(int(np.shape(x0)[0]))
    for leaf in jax.tree_util.tree_leaves(thetas):
        if np.ndim(leaf) == 0:
            raise DomainError("solve_batch: every theta leaf needs a leading batch axis")
        sizes.add(int(np.shape(leaf)[0]))
    if len(sizes) != 1:
        raise DomainError(f"solve_batch: inconsistent batch sizes {sorted(sizes)} (x0 rows and theta leaves)")
    return sizes.pop()


def resolve_lockstep(lockstep: Union[int, str, None]) -> Optional[int]:
    """The ``lockstep`` setting as a count or None: "auto" is 1 on CPU (lanes one after
    another) and None on an accelerator (every lane in one vmap)."""
    if lockstep == "auto":
        return 1 if jax.default_backend() == "cpu" else None
    if lockstep is not None and (not isinstance(lockstep, (int, np.integer)) or lockstep < 1):
        raise DomainError(f"lockstep must be 'auto', None or a positive integer; got {lockstep!r}")
    return lockstep


def map_in_lockstep(fn, args, lockstep: Optional[int]):
    """``fn`` over the leading axis of every leaf of ``args`` (a tuple of pytrees), ``lockstep``
    rows at a time in one ``jax.vmap`` and the groups one after another by ``jax.lax.map``
    (``None``: every row in one vmap; 1: one row at a time, unbatched). A vmapped group
    advances in lockstep: each while loop runs as many trips as its slowest row needs, on every
    row; in sequence, the work is the sum of the rows' own work. The row count must be a
    multiple of ``lockstep``."""
    n = jax.tree_util.tree_leaves(args)[0].shape[0]
    k = n if lockstep is None else int(lockstep)
    if k >= n:
        return jax.vmap(fn)(*args)
    if k == 1:
        return jax.lax.map(lambda a: fn(*a), args)
    if n % k:
        raise ValueError(f"map_in_lockstep: {n} rows are not a multiple of lockstep={k}")
    grouped = jax.tree_util.tree_map(lambda a: a.reshape((n // k, k) + a.shape[1:]), args)
    out = jax.lax.map(lambda a: jax.vmap(fn)(*a), grouped)
    return jax.tree_util.tree_map(lambda a: a.reshape((n,) + a.shape[2:]), out)


def solve_batch(problem: Problem, x0, thetas, options: SolverOptions = SolverOptions(),
                lockstep: Union[int, str, None] = None) -> Result:
    """Solve B problems: ``x0`` (B, n) or a shared (n,), ``thetas`` a pytree whose leaves have a
    leading axis B (or None with x0 (B, n)). Returns a :class:`Result` batched along axis 0.
    ``lockstep`` (see :func:`map_in_lockstep`; "auto" picks by backend): None (default here)
    solves the whole batch in one vmap; B must be a multiple of a count."""
    x0 = jnp.asarray(x0, float)
    k = resolve_lockstep(lockstep)
    if thetas is None:
        if x0.ndim != 2:
            raise DomainError("solve_batch: with thetas=None, x0 must be (B, n)")
        return map_in_lockstep(lambda x: solve(problem, x, None, options), (x0,), k)
    if x0.ndim == 1:
        return map_in_lockstep(lambda th: solve(problem, x0, th, options), (thetas,), k)
    return map_in_lockstep(lambda x, th: solve(problem, x, th, options), (x0, thetas), k)


def batch_mesh(devices: Optional[Sequence] = None) -> Mesh:
    """A 1-D device mesh with axis name "batch" over ``devices`` (default: all devices)."""
    devs = np.asarray(jax.devices() if devices is None else list(devices))
    return Mesh(devs, ("batch",))


def make_batch_solver(problem: Problem, options: SolverOptions = SolverOptions(), *, shard: bool = True,
                      devices: Optional[Sequence] = None, compile: str = "optimized",
                      lockstep: Union[int, str, None] = "auto"):
    """A function ``fn(x0, thetas) -> Result`` solving a batch (see :func:`solve_batch`).

    ``shard=True`` places the batch on a 1-D mesh over ``devices`` (default all) with
    ``NamedSharding(mesh, P("batch"))``; the returned arrays keep that sharding. ``shard=False``
    is one jitted program on the default device. ``lockstep`` sets how each device goes through
    its share (:func:`map_in_lockstep`): "auto" (default) one problem after another on CPU and
    all in one vmap on an accelerator, None all in one vmap, a count that many per vmap. B is
    padded to a multiple of (devices × lockstep) by repeating its last problem, and trimmed
    again. One compilation per (padded) batch shape."""
    k = resolve_lockstep(lockstep)
    mesh = batch_mesh(devices) if shard else None
    if mesh is not None:
        sharding = NamedSharding(mesh, PartitionSpec("batch"))
        replicated = NamedSharding(mesh, PartitionSpec())
    n_dev = 1 if mesh is None else mesh.devices.size
    multiple = n_dev * (1 if k is None else k)
    cache = {}

    def per_device(x0, thetas):
        return solve_batch(problem, x0, thetas, options, k)

    def run(x0, thetas):
        if n_dev == 1:
            return per_device(x0, thetas)
        # (n_dev · b, ...) -> (n_dev, b, ...): the vmapped axis is the sharded one, so each
        # device goes through its own b problems
        split = lambda a: a.reshape((n_dev, a.shape[0] // n_dev) + a.shape[1:])  # noqa: E731
        th = jax.tree_util.tree_map(split, thetas)
        if x0.ndim == 1:
            out = jax.vmap(lambda t: per_device(x0, t))(th)
        else:
            out = jax.vmap(per_device)(split(x0), th)
        return jax.tree_util.tree_map(lambda a: a.reshape((a.shape[0] * a.shape[1],) + a.shape[2:]), out)

    def fn(x0, thetas=None):
        B = _batch_size(x0, thetas)
        pad = (-B) % multiple
        shared_x0 = np.ndim(x0) == 1

        def pad_leaf(a):
            a = jnp.asarray(a)
            if pad == 0:
                return a
            return jnp.concatenate([a, jnp.repeat(a[-1:], pad, axis=0)], axis=0)

        x0p = jnp.asarray(x0, float) if shared_x0 else pad_leaf(jnp.asarray(x0, float))
        thp = jax.tree_util.tree_map(pad_leaf, thetas)
        key = (shared_x0, jax.tree_util.tree_structure(thp))
        if mesh is None:
            if key not in cache:
                cache[key] = jit_with_options(run, compile)
        else:
            x_sh = replicated if shared_x0 else sharding
            th_sh = jax.tree_util.tree_map(lambda _: sharding, thp)
            if key not in cache:
                cache[key] = jit_with_options(run, compile, in_shardings=(x_sh, th_sh), out_shardings=sharding)
            x0p = jax.device_put(x0p, x_sh)
            thp = jax.device_put(thp, th_sh)
        out = cache[key](x0p, thp)
        if pad:
            out = jax.tree_util.tree_map(lambda a: a[:B], out)
        return out

    return fn


__all__ = ["solve_batch", "make_batch_solver", "batch_mesh", "map_in_lockstep", "resolve_lockstep"]
