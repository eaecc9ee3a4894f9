"""Static scene structure of the radar chain: absent parts are not in the traced program.

A clear-air scene must trace no weather, clutter, multipath or jammer sub-program (not even as
zeros); a scene with every part traces each of them; the clear-air program is smaller.
"""

import jax
import jax.numpy as jnp
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401
from diffsense.scene import complete_parameters, evaluate, evaluator, parameter_table
from diffsense.sensors.parts import count_equations, traced_parts
from diffsense.physics.propagation import radar_horizon_m
from diffsense.sensors.radar import PARTS
from diffsense.scene import Scene

BASE = dict(
    range_m=15e3, peak_power_w=5e4, pulse_width_s=0.5e-6, freq_hz=9.4e9, bandwidth_hz=1.2e6, noise_figure_db=3.0,
    prf_hz=2e3, n_pulses=12.0, antenna_diameter_m=1.5, jammer_power_w=5.0, jammer_gain_db=3.0,
    jammer_bandwidth_hz=50e6, target_height_m=20.0, antenna_height_m=15.0,
    track_alpha=0.5, servo_bandwidth_hz=3.0, positioner_resonance_hz=30.0,
    closing_speed_mps=250.0, scan_period_s=4.0, first_look_range_m=18e3,
)
CLEAR = Scene("radar", [], {"swerling": 1})
FULL = Scene("radar", list(PARTS), {"swerling": 1})


def params(scene, **extra):
    table = parameter_table(scene)
    return complete_parameters(scene, {k: v for k, v in dict(BASE, **extra).items() if k in table})


def jaxpr(scene):
    return jax.make_jaxpr(lambda q: evaluate(scene, q).values)(params(scene))


def test_clear_air_scene_traces_no_part():
    assert traced_parts(jaxpr(CLEAR)) == set()


def test_full_scene_traces_every_part():
    assert traced_parts(jaxpr(FULL)) == set(PARTS)


def test_each_single_part_scene_traces_only_that_part():
    for part in ("rain", "sea_clutter", "multipath", "jammer", "wall_clutter"):
        scene = Scene("radar", [part], {"detectability": "given"})
        jx = jax.make_jaxpr(lambda q: evaluate(scene, q).values)(params(scene, detectability_db=12.0))
        assert traced_parts(jx) == {part}


def test_clear_air_program_is_smaller():
    n_clear = count_equations(jaxpr(CLEAR))
    n_full = count_equations(jaxpr(FULL))
    assert n_clear < n_full
    # the parts are what the full program adds: their sub-programs hold most of its equations
    assert n_full - n_clear > n_clear


# low-altitude maritime scene: multipath lobes and sea clutter through the root finder
SEA = Scene("radar", ["multipath", "sea_clutter"], {"detectability": "given", "polarization": "vertical"})
_SEA_GRAD = jax.jit(jax.value_and_grad(lambda q: sum(jnp.sum(v) for v in evaluator(SEA)(q).values.values())))


@settings(max_examples=30, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.3, 2.0), st.floats(0.7, 1.9), st.floats(9.3, 10.9))
def test_sea_scene_outputs_and_gradients_finite(range_u, sea_state_u, log_ha, log_ht, log_f):
    # ranges from 300 m to 0.95 of the radar horizon (the two-ray model's domain)
    horizon = float(radar_horizon_m(10**log_ha, 10**log_ht))
    p = params(SEA, detectability_db=12.0)
    p.update(
        range_m=jnp.asarray(300.0 * (0.95 * horizon / 300.0) ** range_u, dtype=float), sea_state=jnp.asarray(0.5 + 5.5 * sea_state_u, dtype=float),
        antenna_height_m=jnp.asarray(10**log_ha, dtype=float), target_height_m=jnp.asarray(10**log_ht, dtype=float), freq_hz=jnp.asarray(10**log_f, dtype=float),
    )
    value, grads = _SEA_GRAD(p)
    assert np.isfinite(float(value))
    assert all(np.isfinite(float(g)) for g in grads.values())


def test_multipath_range_beyond_the_horizon_is_rejected():
    import pytest
    from diffsense.errors import DomainError

    inside = params(SEA, detectability_db=12.0, range_m=10e3, antenna_height_m=10.0, target_height_m=10.0)
    assert np.isfinite(float(_SEA_GRAD(inside)[0]))  # 10 km: inside the 26 km horizon
    with pytest.raises(DomainError, match="horizon"):
        evaluate(SEA, dict(inside, range_m=80e3))
