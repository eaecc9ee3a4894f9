"""Lanes split across processes with ``jax.distributed`` give the answers of one process.

The test launches two processes of this file (``python test_distributed.py <id> <port> <out>``)
with a coordinator on a free localhost port; each solves its share of the multistart lanes of
the shipped side-scan sonar design (:func:`diffsense.optimize.distributed.solve_across_processes`)
and runs the design optimiser (whose first step splits its lanes the same way), and process 0
writes what both gathered. The same lanes and optimisation in this (single) process are the
reference.
"""

import os
import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
SPEC = REPO / "designs" / "sidescan_sonar.toml"
N_STARTS = 6


def lane_results(model):
    """The multistart lanes of ``model`` (its initial design and N_STARTS − 1 Latin-hypercube
    starts, every catalog combination), solved through the design optimiser's lane program,
    which splits them across the connected processes
    (:func:`~diffsense.optimize.distributed.solve_across_processes`)."""
    from diffsense.design.optimizer import _thetas, prepare
    from diffsense.design.runner import Lanes, bounds_problem, objective_scale
    from diffsense.optimize.multistart import start_points

    run = prepare(model, n_starts=N_STARTS)
    starts = np.vstack([model.initial[None, :],
                        start_points(bounds_problem(model), N_STARTS - 1, seed=3, method="lhs")])
    C = len(model.combinations)
    x0 = np.repeat(starts, C, axis=0)
    combos = np.tile(np.arange(C), starts.shape[0])
    lower, upper = run.boxes(n=x0.shape[0])
    theta = _thetas(model, model.inputs(), combos, model.limits, objective_scale(model))
    theta, _ = run.search_points(x0, theta, combos)
    return run.solve(Lanes(x0, theta, lower, upper, combos))


def run(out=None):
    """Lanes and optimum of the side-scan design (in whatever processes are connected)."""
    from diffsense.design.model import DesignModel
    from diffsense.design.optimizer import optimize_design
    from diffsense.design.spec import load_spec

    model = DesignModel(load_spec(SPEC))
    res = lane_results(model)
    opt = optimize_design(model, n_starts=N_STARTS, seed=0)
    record = {"x": res.x, "f": res.f, "converged": res.converged, "feasible": res.feasible,
              "opt_x": opt.x, "opt_objective": np.array(opt.objective), "opt_feasible": np.array(opt.feasible)}
    if out is not None:
        np.savez(out, **record)
    return record


def worker(process_id: int, port: int, out: str) -> None:
    sys.path.insert(0, str(REPO))
    import jax

    import diffsense  # noqa: F401  (64-bit mode)
    from diffsense.optimize.distributed import initialize, shutdown

    initialize(f"localhost:{port}", 2, process_id, timeout_s=120)
    assert jax.process_count() == 2 and jax.process_index() == process_id
    run(out if process_id == 0 else None)
    shutdown()


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def test_share_rows_cover_every_row_once():
    from diffsense.optimize.distributed import share_rows

    for n in (1, 2, 7, 80):
        for p in (1, 2, 3, 5):
            rows = np.concatenate([share_rows(n, p, i) for i in range(p)])
            assert rows.tolist() == list(range(n))


def test_single_process_is_solve_in_batches():
    import jax

    from diffsense.optimize.distributed import solve_across_processes

    solver = jax.jit(lambda a, b: {"s": a + b[:, None]})
    a = np.arange(10.0).reshape(5, 2)
    b = np.arange(5.0)
    out = solve_across_processes(solver, 2, a, b)  # calls of 2 rows, the last one padded
    assert np.array_equal(out["s"], a + b[:, None])


def test_two_processes_give_the_results_of_one(tmp_path):
    port = free_port()
    out = tmp_path / "two.npz"
    env = dict(os.environ, JAX_PLATFORMS="cpu", PYTHONPATH=str(REPO))
    procs = [subprocess.Popen([sys.executable, __file__, str(i), str(port), str(out)], env=env, cwd=str(REPO),
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True) for i in range(2)]
    logs = []
    for p in procs:
        try:
            logs.append(p.communicate(timeout=600)[0])
        except subprocess.TimeoutExpired:
            for q in procs:
                q.kill()
            pytest.fail("a process did not finish in 600 s")
    assert all(p.returncode == 0 for p in procs), "\n".join(log[-3000:] for log in logs)
    two = dict(np.load(out))
    one = run()
    assert two["x"].shape == one["x"].shape and two["x"].shape[0] == N_STARTS
    assert np.array_equal(two["converged"], one["converged"]) and np.array_equal(two["feasible"], one["feasible"])
    np.testing.assert_allclose(two["x"], one["x"], rtol=1e-9, atol=0)
    np.testing.assert_allclose(two["f"], one["f"], rtol=1e-9, atol=1e-15)
    assert bool(two["opt_feasible"]) and bool(one["opt_feasible"])
    np.testing.assert_allclose(two["opt_x"], one["opt_x"], rtol=1e-9)
    assert float(two["opt_objective"]) == pytest.approx(float(one["opt_objective"]), rel=1e-9)


if __name__ == "__main__":
    worker(int(sys.argv[1]), int(sys.argv[2]), sys.argv[3])
