"""Batched and sharded solves: a θ sweep against Brooker eq. 14.12, and the sharded program
(4 forced host devices, in a subprocess) against the unsharded one."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.optimize import SolverOptions, make_batch_solver, solve_batch
from diffsense.optimize import reference_problems as rp
from diffsense.optimize.compile import jit_with_options
from helpers.paths import REPO



def _servo_sweep(B):
    P = rp.servo_bandwidth()
    th = {k: jnp.broadcast_to(v, (B,)) for k, v in P.theta.items()}
    th["snr"] = jnp.logspace(0.0, 3.0, B)
    th["range_m"] = jnp.linspace(300.0, 30000.0, B)
    return P, th


def test_theta_sweep_matches_book_14_12():
    P, th = _servo_sweep(64)
    run = jit_with_options(lambda x0, t: solve_batch(P.problem, x0, t), "fast")
    r = run(jnp.array([1.0]), th)
    assert r.x.shape == (64, 1) and np.all(np.asarray(r.converged))
    np.testing.assert_allclose(np.asarray(r.x[:, 0]), np.asarray(rp.servo_optimum_hz(th)), rtol=1e-6)


def test_batch_over_starts_and_parameters_hs071():
    # HS071 from four starts (one batch over x0 with theta=None): all reach f* = 17.0140173
    P = rp.hs071()
    x0 = jnp.array([[1.0, 5.0, 5.0, 1.0], [2.0, 2.0, 2.0, 2.0], [4.0, 1.0, 4.0, 1.0], [1.5, 4.5, 3.5, 1.5]])
    r = make_batch_solver(P.problem, SolverOptions(), shard=False, compile="fast")(x0, None)
    np.testing.assert_allclose(np.asarray(r.f), P.f_star, rtol=1e-8)


def test_single_device_sharded_equals_unsharded_and_bad_batches_raise():
    P, th = _servo_sweep(10)
    sharded = make_batch_solver(P.problem, SolverOptions(), shard=True, compile="fast")(jnp.array([1.0]), th)
    plain = make_batch_solver(P.problem, SolverOptions(), shard=False, compile="fast")(jnp.array([1.0]), th)
    np.testing.assert_allclose(np.asarray(sharded.x), np.asarray(plain.x), rtol=1e-14)
    bad = dict(th, snr=th["snr"][:5])
    with pytest.raises(DomainError):
        make_batch_solver(P.problem, SolverOptions(), shard=True, compile="fast")(jnp.array([1.0]), bad)


_SCRIPT = textwrap.dedent("""
    import json, jax, jax.numpy as jnp, numpy as np
    import diffsense
    from diffsense.optimize import SolverOptions, make_batch_solver
    from diffsense.optimize import reference_problems as rp
    P = rp.servo_bandwidth()
    B = 10  # not a multiple of the 4 devices: exercises padding
    th = {k: jnp.broadcast_to(v, (B,)) for k, v in P.theta.items()}
    th["snr"] = jnp.logspace(0.0, 3.0, B)
    sharded = make_batch_solver(P.problem, SolverOptions(), shard=True, compile="fast")(jnp.array([1.0]), th)
    plain = make_batch_solver(P.problem, SolverOptions(), shard=False, compile="fast")(jnp.array([1.0]), th)
    x0s = jnp.stack([jnp.array([1.0, 5.0, 5.0, 1.0])] * 6) * jnp.linspace(0.9, 1.1, 6)[:, None]
    H = rp.hs071()
    hs_sh = make_batch_solver(H.problem, SolverOptions(), shard=True, compile="fast")(x0s, None)
    hs_pl = make_batch_solver(H.problem, SolverOptions(), shard=False, compile="fast")(x0s, None)
    print(json.dumps({
        "devices": jax.device_count(),
        "shard_devices": len(sharded.x.sharding.device_set),
        "x_sharded": np.asarray(sharded.x).ravel().tolist(),
        "x_plain": np.asarray(plain.x).ravel().tolist(),
        "bo": np.asarray(rp.servo_optimum_hz(th)).tolist(),
        "conv_equal": bool(np.array_equal(np.asarray(sharded.converged), np.asarray(plain.converged))),
        "hs_f_sharded": np.asarray(hs_sh.f).tolist(),
        "hs_f_plain": np.asarray(hs_pl.f).tolist(),
    }))
""")


def test_sharded_over_four_host_devices_equals_unsharded():
    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=4", JAX_PLATFORMS="cpu")
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run([sys.executable, "-c", _SCRIPT], capture_output=True, text=True, env=env, timeout=300,
                         cwd=str(REPO))
    assert out.returncode == 0, out.stderr[-3000:]
    res = json.loads(out.stdout.strip().splitlines()[-1])
    assert res["devices"] == 4 and res["shard_devices"] == 4
    assert res["conv_equal"]
    np.testing.assert_allclose(res["x_sharded"], res["x_plain"], rtol=1e-13)
    np.testing.assert_allclose(res["x_sharded"], res["bo"], rtol=1e-6)  # Brooker eq. 14.12
    np.testing.assert_allclose(res["hs_f_sharded"], res["hs_f_plain"], rtol=1e-13)
    np.testing.assert_allclose(res["hs_f_sharded"], 17.0140173, rtol=1e-8)  # HS071 published optimum
