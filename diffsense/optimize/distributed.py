"""Independent solves (lanes) split across processes, on one machine or a cluster, with
``jax.distributed``.

Every process runs the same program. :func:`initialize` connects the processes
(:func:`jax.distributed.initialize`: a coordinator at ``host:port`` that process 0 serves, the
number of processes and each one's index); :func:`solve_across_processes` then gives process i
the i-th contiguous share of the rows (lanes) of a batch, solves it with the ordinary lane
machinery (:func:`diffsense.optimize.lanes.solve_in_batches`), and gathers every share on every
process with :func:`jax.experimental.multihost_utils.process_allgather`, so that each process
ends with the results of all lanes, in order, as if it had solved them alone. Lanes are
independent, so the answer does not depend on the number of processes (up to the XLA program
compiled for another number of lanes per call, which runs the same per-lane solve).

With one process (nothing initialised) :func:`solve_across_processes` is
:func:`~diffsense.optimize.lanes.solve_in_batches`.

Arguments of :func:`initialize` not given are read from the environment:
``JAX_COORDINATOR_ADDRESS`` (JAX's own variable, e.g. ``10.0.0.1:12345``),
``DIFFSENSE_NUM_PROCESSES`` and ``DIFFSENSE_PROCESS_ID``; when none is set JAX's cluster
detection (Slurm, Open MPI, Kubernetes, Cloud TPU) fills them in.
"""

from __future__ import annotations

import math
import os
from typing import Optional

import jax
import numpy as np

from diffsense.errors import DomainError
from diffsense.optimize.lanes import solve_in_batches, take

#: environment variables read by :func:`initialize` (besides JAX's ``JAX_COORDINATOR_ADDRESS``)
ENV_NUM_PROCESSES = "DIFFSENSE_NUM_PROCESSES"
ENV_PROCESS_ID = "DIFFSENSE_PROCESS_ID"


def _env_int(name: str) -> Optional[int]:
    text = os.environ.get(name)
    if text is None or text == "":
        return None
    try:
        return int(text)
    except ValueError:
        raise DomainError(f"environment variable {name} must be a whole number; got {text!r}") from None


def initialize(coordinator_address: Optional[str] = None, num_processes: Optional[int] = None,
               process_id: Optional[int] = None, *, timeout_s: int = 300) -> None:
    """Connect this process to the others (:func:`jax.distributed.initialize`) on CPU; the
    arguments default to the environment (module docstring). Call once, before any other JAX
    computation."""
    coordinator_address = coordinator_address or os.environ.get("JAX_COORDINATOR_ADDRESS")
    num_processes = _env_int(ENV_NUM_PROCESSES) if num_processes is None else int(num_processes)
    process_id = _env_int(ENV_PROCESS_ID) if process_id is None else int(process_id)
    if num_processes is not None and process_id is not None and not 0 <= process_id < num_processes:
        raise DomainError(f"process_id must lie in [0, {num_processes}); got {process_id}")
    jax.distributed.initialize(coordinator_address, num_processes, process_id,
                               initialization_timeout=int(timeout_s))


def shutdown() -> None:
    """Disconnect from the other processes (:func:`jax.distributed.shutdown`)."""
    jax.distributed.shutdown()


def share_rows(n_rows: int, n_processes: int, index: int) -> np.ndarray:
    """Rows of process ``index`` out of ``n_processes``: the ``index``-th contiguous block of
    ⌈n_rows / n_processes⌉ rows, cut at ``n_rows`` (the last blocks may be short or empty).

    >>> [share_rows(5, 2, i).tolist() for i in range(2)]
    [[0, 1, 2], [3, 4]]
    >>> [share_rows(2, 3, i).tolist() for i in range(3)]
    [[0], [1], []]
    """
    per = math.ceil(n_rows / n_processes)
    return np.arange(index * per, min((index + 1) * per, n_rows))


def solve_across_processes(solver, batch: Optional[int], *columns, alongside=None, pin_padding: bool = False):
    """``solver(*columns)`` over the rows of ``columns`` (pytrees whose leaves have a leading row
    axis), each process solving its share (:func:`share_rows`) in calls of ``batch`` rows
    (default: the share's size, ⌈rows / processes⌉) and every process receiving all results,
    as NumPy arrays in row order; ``alongside`` and ``pin_padding`` as in
    :func:`~diffsense.optimize.lanes.solve_in_batches`.

    Every process must call this with the same ``solver``, ``batch`` and row count. Each share
    is padded to ⌈rows / processes⌉ rows by repeating its last row (the gather needs equal
    shapes); padded results are dropped.
    """
    n = int(jax.tree_util.tree_leaves(columns)[0].shape[0])
    if n == 0:
        raise DomainError("solve_across_processes: no rows to solve")
    count, index = jax.process_count(), jax.process_index()
    per = math.ceil(n / count)
    batch = per if batch is None else int(batch)
    if count == 1:
        return solve_in_batches(solver, batch, *columns, alongside=alongside, pin_padding=pin_padding)
    from jax.experimental import multihost_utils

    mine = share_rows(n, count, index)
    padded = np.concatenate([mine, np.full(per - mine.size, mine[-1] if mine.size else n - 1)])
    local = solve_in_batches(solver, batch, *(take(c, padded) for c in columns), alongside=alongside,
                             pin_padding=pin_padding)
    gathered = multihost_utils.process_allgather(local, tiled=True)
    return jax.tree_util.tree_map(lambda a: np.asarray(a)[:n], gathered)


__all__ = ["initialize", "shutdown", "share_rows", "solve_across_processes", "ENV_NUM_PROCESSES", "ENV_PROCESS_ID"]
