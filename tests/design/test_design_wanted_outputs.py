"""A scene computes only what it contains: chains and the design model evaluated for the outputs
a caller asks for (``Chain.compute(scene, p, wanted=...)``, ``DesignModel.residuals`` and
``DesignModel.objective``).

Reference: the full evaluation (``wanted=None``) of the same chain or model at the same point.
The wanted-only evaluation must return every wanted name with the full evaluation's value (equal
to rtol 1e-14: both run the same operations; only XLA's fusion of the two programs may differ),
and must not trace the range root finds, Pd series and unneeded required-SNR solves.
"""

import collections
import dataclasses
import glob
import os

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401
import diffsense.detection as detection
import diffsense.sensors.radar.chain as radar_chain
from diffsense.physics.received_pulse import received_pulse_width_s
from diffsense.sensors.parts import _sub_jaxprs, count_equations
from diffsense.scene import chain_for, complete_parameters, output_table
from diffsense.design.model import DesignModel
from diffsense.scene import Scene
from diffsense.design.spec import load_spec
from helpers.paths import REPO

ROOT = str(REPO)
DESIGNS = sorted(glob.glob(os.path.join(ROOT, "designs", "*.toml")))
RTOL = 1e-14


def _other_design(model):
    """A design inside the bounds, away from the initial one: 30 % of the way from the lower to
    the upper bound (geometrically for log-scaled variables), integers rounded."""
    lo, hi = model.lower, model.upper
    x = np.where(model.log_scale, lo * (hi / lo) ** 0.3, lo + 0.3 * (hi - lo))
    return np.where(model.integer, np.round(x), x)


def _full_problem(model):
    """(residuals, normalised objective) computed from the full evaluation of every case."""

    def run(x, s):
        _, _, req, objective = model.evaluation(model.solve_values(x, s), s.design)
        residuals = model.sign * (req - s.limits) / model.scales
        return residuals, model.spec.objective.sign * objective / s.objective_scale

    return run


def _wanted_problem(model):
    """(residuals, normalised objective) as the optimiser computes them (wanted outputs only)."""
    def run(x, s):
        rows, objective = model.residuals_and_objective(x, s)
        # a requirement over an interval has one row per slot: its residual is the largest
        per_requirement = jnp.stack([jnp.max(rows[model.row_owner == j]) for j in range(len(model.requirements))])
        return per_requirement, objective

    return run


@pytest.mark.parametrize("path", DESIGNS, ids=lambda p: os.path.basename(p)[:-5])
def test_design_residuals_and_objective_from_wanted_outputs_equal_full_evaluation(path):
    model = DesignModel(load_spec(path))
    full = jax.jit(_full_problem(model))
    wanted = jax.jit(_wanted_problem(model))
    points = [(model.initial, 0), (_other_design(model), len(model.combinations) - 1)]
    for x, combo in points:
        assert np.all(x >= model.lower) and np.all(x <= model.upper)
        theta = model.solve_inputs(model.inputs(combo), combo, model.limits, 3.7)
        args = (jnp.asarray(x), jax.tree_util.tree_map(jnp.asarray, theta))
        (r_full, f_full), (r_wanted, f_wanted) = full(*args), wanted(*args)
        assert np.all(np.isfinite(r_full)) and np.isfinite(f_full)
        np.testing.assert_allclose(np.asarray(r_wanted), np.asarray(r_full), rtol=RTOL, atol=0)
        np.testing.assert_allclose(float(f_wanted), float(f_full), rtol=RTOL, atol=0)


def _count_primitive(jaxpr, name):
    """Occurrences of primitive ``name`` in ``jaxpr`` and its nested sub-programs."""
    total, stack = 0, [jaxpr.jaxpr]
    while stack:
        jx = stack.pop()
        for eqn in jx.eqns:
            total += eqn.primitive.name == name
            stack.extend(_sub_jaxprs(eqn))
    return total


def test_ore_pass_residuals_trace_no_range_root_find_and_no_pd_series(monkeypatch):
    """ore_pass.toml constrains faded_snr_margin_db and cheap outputs: its residual function
    needs the exact N-pulse required SNR and nothing else of the detection layer."""
    spec = load_spec(os.path.join(ROOT, "designs", "ore_pass.toml"))
    # the requirements at their one design range: the interval search (tested below) repeats the
    # chain at its grid points
    point_spec = dataclasses.replace(spec, requirements=[dataclasses.replace(r, over=()) for r in spec.requirements])
    model = DesignModel(point_spec)
    calls = collections.Counter()

    def spy(module, name):
        fn = getattr(module, name)

        def counted(*args, **kwargs):
            calls[name] += 1
            return fn(*args, **kwargs)

        monkeypatch.setattr(module, name, counted)

    spy(radar_chain, "decreasing_root_log")
    spy(detection, "pd")
    spy(detection, "required_snr_db")
    def args_of(m):
        theta = m.solve_inputs(m.inputs(0), 0, m.limits, 1.0)
        return jnp.asarray(m.initial), jax.tree_util.tree_map(jnp.asarray, theta)

    args = args_of(model)

    # the chains are jitted sub-programs whose traces JAX keeps: trace them afresh here
    jax.clear_caches()
    full = jax.make_jaxpr(lambda *a: _full_problem(model)(*a)[0])(*args)
    full_calls = dict(calls)
    calls.clear()
    jax.clear_caches()
    wanted = jax.make_jaxpr(model.residuals)(*args)
    # full: detection-range root find, Pd series, required SNR for N pulses and for 1 pulse
    assert full_calls == {"decreasing_root_log": 1, "pd": 1, "required_snr_db": 2}
    assert dict(calls) == {"required_snr_db": 1}

    # the while loops left are exactly those of the N-pulse required-SNR solve and the root find
    # of the received pulse's two half-amplitude crossings (the range resolution's width, both
    # crossings in one loop, until converged, without derivatives: physics.received_pulse)
    solve_only = jax.make_jaxpr(lambda pd, pfa, n: detection.required_snr_db(pd, pfa, n, 0))(0.95, 1e-12, 16.0)
    width_only = jax.make_jaxpr(lambda t, b: received_pulse_width_s(t, b, "two_tuned"))(2e-8, 5e7)
    n_solve = _count_primitive(solve_only, "while")
    n_width = _count_primitive(width_only, "while")
    assert n_solve >= 1 and n_width == 1
    assert _count_primitive(wanted, "while") == n_solve + n_width < _count_primitive(full, "while")
    assert count_equations(wanted) < count_equations(full)

    # with the spec's requirements over range intervals: still no detection-range root find and no Pd series
    calls.clear()
    jax.clear_caches()
    interval_model = DesignModel(spec)
    jax.make_jaxpr(interval_model.residuals)(*args_of(interval_model))
    assert calls["required_snr_db"] >= 1 and calls["decreasing_root_log"] == 0 and calls["pd"] == 0


# --- chains ------------------------------------------------------------------------------------

_RADAR = dict(range_m=5e3, peak_power_w=1e4, pulse_width_s=2e-7, freq_hz=9.5e9, bandwidth_hz=3e6, noise_figure_db=5.0,
              prf_hz=5e3, antenna_diameter_m=1.0, n_pulses=16.0)
CHAIN_CASES = {
    "radar_book_linear_clutter_self_screening_jammer": (
        Scene("radar", ["rain", "rain_clutter", "jammer"], {"detectability": "book", "detector": "linear", "swerling": 1}),
        dict(_RADAR, jammer_power_w=10.0, jammer_gain_db=3.0, jammer_bandwidth_hz=1e8)),
    "radar_coherent_gas": (Scene("radar", ["gas"], {"integration": "coherent", "swerling": 1}), _RADAR),
    "radar_exact_noncoherent": (Scene("radar"), _RADAR),
    "radar_exact_dust_wall_tracking": (
        Scene("radar", ["dust", "wall_clutter", "tracking"]),
        dict(_RADAR, range_m=300.0, freq_hz=94e9, pulse_width_s=2e-8, bandwidth_hz=5e7, antenna_diameter_m=0.25,
             track_alpha=0.5, servo_bandwidth_hz=2.0, positioner_resonance_hz=30.0)),
    "radar_given_multipath_sea": (
        Scene("radar", ["multipath", "sea_clutter"], {"detectability": "given"}), dict(_RADAR, detectability_db=13.0)),
    "lidar_apd_threshold_haze_sun": (Scene("lidar", ["haze", "sun"], {"target": "point"}), dict(range_m=500.0)),
    "lidar_heterodyne_square_law": (Scene("lidar", [], {"detector": "heterodyne"}), dict(range_m=2e3)),
    "sonar_active": (Scene("sonar", ["sea_noise"]), dict(range_m=500.0, freq_hz=1e5)),
    "sonar_passive": (Scene("sonar", ["sea_noise"], {"mode": "passive"}),
                      dict(range_m=2e3, freq_hz=1e4, source_level_db=140.0)),
    "radiometer_gas": (Scene("radiometer", ["gas"]), {}),
    "infrared_haze": (Scene("infrared", ["haze"], {"detector": "given"}), {}),
    "ultrasonic_pulse_echo": (Scene("ultrasonic", ["receiver_noise"], {"mode": "pulse_echo"}),
                              dict(range_m=3.0, target_strength_db=-10.0)),
}
# outputs whose computation a chain may skip (root finds, series, exact solves, and what they feed)
EXPENSIVE = ("pd", "detection_range_m", "detection_range_found", "burn_through_range_m", "required_snr_db",
             "snr_margin_db", "integration_gain_db", "pulses_needed")
# detectability modes not covered by the shipped designs: their values are compared below (a
# compile each; the shipped designs compare the exact, given and threshold modes)
VALUE_CASES = ("radar_book_linear_clutter_self_screening_jammer", "radar_coherent_gas", "radar_exact_noncoherent",
               "lidar_heterodyne_square_law", "ultrasonic_pulse_echo")


def _chain_case(case):
    scene, params = CHAIN_CASES[case]
    return scene, chain_for(scene), complete_parameters(scene, params)


def _expensive_sets(scene):
    names = output_table(scene)
    return [frozenset({"snr_db"})] + [frozenset({n}) for n in EXPENSIVE if n in names]


@pytest.mark.parametrize("case", sorted(CHAIN_CASES))
def test_chain_returns_every_wanted_output_and_skips_the_rest(case):
    scene, chain, p = _chain_case(case)
    cheap = [n for n in output_table(scene) if n not in EXPENSIVE]
    jaxprs = {}
    for wanted in _expensive_sets(scene) + [frozenset(cheap[::3])]:
        jaxprs[wanted], got = jax.make_jaxpr(lambda q: chain.compute(scene, q, wanted=wanted).values,
                                             return_shape=True)(p)
        assert wanted <= set(got), (case, sorted(wanted - set(got)))
        if wanted == {"snr_db"}:
            assert not {"detection_range_m", "detection_range_found", "burn_through_range_m"} & set(got)
    # the SNR alone traces no detection series or solve (while loops) and no range root find
    # (a 100-step scan)
    snr_only, with_range = jaxprs[frozenset({"snr_db"})], jaxprs[frozenset({"detection_range_m"})]
    assert _count_primitive(snr_only, "while") == 0
    assert _count_primitive(snr_only, "scan") < _count_primitive(with_range, "scan")


@pytest.mark.parametrize("case", VALUE_CASES)
def test_chain_wanted_outputs_equal_the_full_evaluation(case):
    """Each output has one formula whatever is wanted (``wanted`` only decides what is traced),
    so the values are compared once per scene, for all the skippable outputs together."""
    scene, chain, p = _chain_case(case)
    wanted = frozenset().union(*_expensive_sets(scene))
    full, values = jax.jit(lambda q: (chain.compute(scene, q).values,
                                      chain.compute(scene, q, wanted=wanted).values))(p)
    assert set(full) == set(output_table(scene)) and wanted <= set(values)
    for name in values:
        np.testing.assert_allclose(np.asarray(values[name]), np.asarray(full[name]), rtol=RTOL, atol=0,
                                   err_msg=f"{case}: {name}")
