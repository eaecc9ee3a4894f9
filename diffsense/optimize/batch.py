"""Batches of problems (a sweep over θ, many specs) in one vectorised, sharded call.

``solve_batch`` vmaps :func:`diffsense.optimize.solve` over a leading batch axis of x0 and
of every θ leaf. ``make_batch_solver`` jits that and, with ``shard=True``, splits the batch
across all available devices: a 1-D ``jax.sharding.Mesh`` named "batch" over the devices and
``NamedSharding(mesh, PartitionSpec("batch"))`` on every input and output; XLA's SPMD
partitioner then gives each device its slice. The problems are independent, but the vmapped
while loops are not: their predicate is "any element still running", so the partitioned
program all-reduces one boolean per loop iteration and the devices advance in lockstep (as
the elements of a vmapped batch already do on one device). Measured on this project's
2-core CPU with 2 forced host devices, sharding gains little or loses (servo sweep +10 %,
HS071 batch −30 %: XLA:CPU already spreads one device's batched work over the cores, and
the lockstep costs; see benchmarks/bench_optimizer.py); the point is multi-accelerator hosts. (Per-device independent loops via ``jax.shard_map``/``pmap`` are
not used: in JAX 0.10 lineax, which optimistix's BFGS uses, rejects the sharding-annotated
shapes it sees inside them.) The batch is padded to a multiple of the device count by
repeating its last element and trimmed again. On a machine with one device the sharded and
unsharded programs are the same. On CPU, XLA can be told to expose several host devices with
``XLA_FLAGS=--xla_force_host_platform_device_count=N`` (set before JAX starts).
"""

from __future__ import annotations

from typing import Optional, Sequence

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from .._checks import DomainError
from .constrained import Result, SolverOptions, jit_with_options, solve
from .problem import Problem


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


def solve_batch(problem: Problem, x0, thetas, options: SolverOptions = SolverOptions()) -> Result:
    """Solve B problems: ``x0`` (B, n) or a shared (n,), ``thetas`` a pytree whose leaves have a
    leading axis B (or None with x0 (B, n)). Returns a :class:`Result` batched along axis 0."""
    x0 = jnp.asarray(x0, float)
    if thetas is None:
        if x0.ndim != 2:
            raise DomainError("solve_batch: with thetas=None, x0 must be (B, n)")
        return jax.vmap(lambda x: solve(problem, x, None, options))(x0)
    if x0.ndim == 1:
        return jax.vmap(lambda th: solve(problem, x0, th, options))(thetas)
    return jax.vmap(lambda x, th: solve(problem, x, th, options))(x0, thetas)


def batch_mesh(devices: Optional[Sequence] = None) -> Mesh:
    """A 1-D device mesh with axis name "batch" over ``devices`` (default: all devices)."""
    devs = np.asarray(jax.devices() if devices is None else list(devices))
    return Mesh(devs, ("batch",))


def make_batch_solver(problem: Problem, options: SolverOptions = SolverOptions(), *, shard: bool = True,
                      devices: Optional[Sequence] = None, compile: str = "optimized"):
    """A function ``fn(x0, thetas) -> Result`` solving a batch (see :func:`solve_batch`).

    ``shard=True`` places the batch on a 1-D mesh over ``devices`` (default all) with
    ``NamedSharding(mesh, P("batch"))`` and pads B to a multiple of the device count; the
    returned arrays keep that sharding (after trimming the padding). ``shard=False`` is one
    jitted vmap on the default device. One compilation per (padded) batch shape."""
    def run(x0, thetas):
        return solve_batch(problem, x0, thetas, options)

    if not shard:
        return jit_with_options(run, compile)

    mesh = batch_mesh(devices)
    n_dev = mesh.devices.size
    sharding = NamedSharding(mesh, PartitionSpec("batch"))
    replicated = NamedSharding(mesh, PartitionSpec())
    cache = {}

    def fn(x0, thetas=None):
        B = _batch_size(x0, thetas)
        pad = (-B) % n_dev
        shared_x0 = np.ndim(x0) == 1

        def pad_leaf(a):
            a = jnp.asarray(a)
            if pad == 0:
                return a
            return jnp.concatenate([a, jnp.repeat(a[-1:], pad, axis=0)], axis=0)

        x0p = jnp.asarray(x0, float) if shared_x0 else pad_leaf(jnp.asarray(x0, float))
        thp = jax.tree_util.tree_map(pad_leaf, thetas)
        key = (shared_x0, jax.tree_util.tree_structure(thp))
        if key not in cache:
            x_sh = replicated if shared_x0 else sharding
            th_sh = jax.tree_util.tree_map(lambda _: sharding, thp)
            cache[key] = jit_with_options(run, compile, in_shardings=(x_sh, th_sh), out_shardings=sharding)
        x0p = jax.device_put(x0p, replicated if shared_x0 else sharding)
        thp = jax.device_put(thp, jax.tree_util.tree_map(lambda _: sharding, thp))
        out = cache[key](x0p, thp)
        if pad:
            out = jax.tree_util.tree_map(lambda a: a[:B], out)
        return out

    return fn


__all__ = ["solve_batch", "make_batch_solver", "batch_mesh"]
