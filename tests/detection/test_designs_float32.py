"""Every shipped design evaluated in float32 at random points of its variable box: no NaN.

The detection functions (thresholds, the Pd series, the required-SNR root, the matched-filter
loss) must give finite values and gradients in float32 wherever the design's variables may go.
Each design runs in a child process started with ``DIFFSENSE_X64=0`` (the rest of the suite
keeps float64): 2000 points drawn with a fixed seed, uniform in each variable's box (in its
logarithm for log-scaled variables, rounded for integer ones), for every catalog combination;
the child evaluates the normalised requirement residuals and the objective with their
gradients with respect to the design variables, every output of every case, and at the first
200 points every output's gradient.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from helpers.paths import DESIGNS, REPO

POINTS = 2000
#: points (the first of the sample) where the gradient of every output is checked too
GRADIENT_POINTS = 200
SEED = 20240611
DESIGN_FILES = sorted(DESIGNS.glob("*.toml"))
# Known NaN outside the detection layer (float32 only): the blackbody band radiance forms its
# prefactor as 2 k^4 T^4 / (h^3 c^2) with k^4 ~ 3.6e-92 and h^3 ~ 2.9e-100, both below float32's
# range, so 0/0 (diffsense/physics/radiance.py); every IRST output is NaN from there on.
_NON_DETECTION_NAN = {}  # designs with a known non-finite float32 result outside detection (none)


def _sample(model, rng, count):
    lo, hi = model.lower, model.upper
    u = rng.random((count, lo.size))
    logs = model.log_scale & (lo > 0)
    x = np.where(logs, np.exp(np.log(np.where(logs, lo, 1.0)) + u * np.log(np.where(logs, hi / lo, 1.0))),
                 lo + u * (hi - lo))
    return np.where(model.integer, np.round(x), x)


def _child(path):
    """Evaluate one design in float32; print a JSON report of the first non-finite entries."""
    import jax
    import jax.numpy as jnp

    from diffsense import DesignModel, load_spec

    model = DesignModel(load_spec(path))
    rng = np.random.default_rng(SEED)
    x_all = jnp.asarray(_sample(model, rng, POINTS), dtype=jnp.float32)
    bad = []
    f32 = lambda tree: jax.tree_util.tree_map(  # noqa: E731
        lambda a: jnp.asarray(a, dtype=jnp.float32) if np.issubdtype(np.asarray(a).dtype, np.floating) else jnp.asarray(a),
        tree)

    def outputs(x, s):
        return {case: ev.values for case, ev in model.evaluate(model.solve_values(x, s)).items()}

    residuals = jax.jit(jax.vmap(lambda x, s: model.residuals(x, s), in_axes=(0, None)))
    jac = jax.jit(jax.vmap(jax.jacfwd(lambda x, s: model.residuals(x, s)), in_axes=(0, None)))
    objective = jax.jit(jax.vmap(model.objective, in_axes=(0, None)))
    grad = jax.jit(jax.vmap(jax.grad(model.objective), in_axes=(0, None)))
    values = jax.jit(jax.vmap(outputs, in_axes=(0, None)))
    # every output's gradient with respect to the design variables, at the first GRADIENT_POINTS
    output_gradients = jax.jit(jax.vmap(jax.jacfwd(outputs), in_axes=(0, None)))
    for k, row in enumerate(model.combo_table):
        theta = f32(model.solve_inputs(model.inputs(k), k, model.limits, 1.0))
        checks = {"residuals": residuals(x_all, theta), "residual_gradients": jac(x_all, theta)}
        if model.objective_terms:
            checks["objective"] = objective(x_all, theta)
            checks["objective_gradient"] = grad(x_all, theta)
        for case, vals in values(x_all, theta).items():
            for name, v in vals.items():
                checks[f"{case}.{name}"] = v
        for case, grads in output_gradients(x_all[:GRADIENT_POINTS], theta).items():
            for name, g in grads.items():
                checks[f"{case}.{name} gradient"] = jnp.concatenate(
                    [g, jnp.full((POINTS - GRADIENT_POINTS,) + g.shape[1:], 0.0, g.dtype)])
        for name, arr in checks.items():
            arr = np.asarray(arr, dtype=float).reshape(POINTS, -1)
            rows = np.nonzero(~np.all(np.isfinite(arr), axis=1))[0]
            if rows.size:
                i = int(rows[0])
                bad.append({"check": name, "count": int(rows.size), "combo": [float(c) for c in row],
                            "point": dict(zip(model.variable_names, map(float, x_all[i])))})
    print(json.dumps(bad))


@pytest.mark.slow
@pytest.mark.parametrize("path", [
    pytest.param(p, marks=pytest.mark.xfail(reason=_NON_DETECTION_NAN[p.stem], strict=False))
    if p.stem in _NON_DETECTION_NAN else p for p in DESIGN_FILES], ids=[p.stem for p in DESIGN_FILES])
def test_design_float32_values_and_gradients_are_finite(path):
    env = dict(os.environ, DIFFSENSE_X64="0", JAX_ENABLE_X64="0")
    env["PYTHONPATH"] = os.pathsep.join(str(p) for p in (REPO, REPO / "tests", env.get("PYTHONPATH", "")) if p)
    proc = subprocess.run([sys.executable, str(Path(__file__).resolve()), str(path)], env=env,
                          capture_output=True, text=True, timeout=1800)
    assert proc.returncode == 0, proc.stderr[-3000:]
    bad = json.loads(proc.stdout.strip().splitlines()[-1])
    assert not bad, json.dumps(bad, indent=1)


if __name__ == "__main__":
    _child(sys.argv[1])
