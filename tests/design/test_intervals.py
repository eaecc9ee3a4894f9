"""Requirements over intervals (semi-infinite constraints): the spec's ``over`` key, and designs
whose binding point is an interior multipath null, re-checked on dense grids of their own."""

from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense import DesignModel, SpecError, load_spec, optimize_design
from diffsense.design.spec import parse_spec
from diffsense.scene import chain_for

SPECS = Path(__file__).parent / "interval_specs"


def _raw(**req_extra):
    req = {"output": "detection_margin_db", "at_least": "0 dB", "over": {"range_m": ["10 km", "20 km"]}}
    req.update(req_extra)
    return {
        "sensor": "radar", "parts": ["multipath"],
        "fixed": {"freq_hz": "9.5 GHz", "antenna_diameter_m": "1 m", "pulse_width_s": "1 us",
                  "bandwidth_hz": "1 MHz", "prf_hz": "2 kHz", "n_pulses": 10, "noise_figure_db": "4 dB",
                  "rcs_m2": "1 m^2", "pd": 0.9, "pfa": 1e-6, "antenna_height_m": "8 m",
                  "target_height_m": "30 m", "sea_state": 1, "range_m": "15 km"},
        "variables": {"peak_power_w": {"lower": "1 W", "upper": "100 MW", "initial": "10 kW"}},
        "requirements": [req], "objective": {"minimize": "peak_power_w"},
    }


def test_over_is_read_in_the_parameters_unit():
    spec = parse_spec(_raw())
    (iv,) = spec.requirements[0].over
    assert (iv.parameter, iv.unit, iv.lower, iv.upper) == ("range_m", "m", 10_000.0, 20_000.0)
    spec = parse_spec(_raw(over={"range_m": {"from": "10 km", "to": "20 km", "log": True}}, over_points=65))
    assert spec.requirements[0].over[0].log is True and spec.requirements[0].over_points == 65


@pytest.mark.parametrize("extra, key, words", [
    ({"over": {"range_m": ["20 km", "10 km"]}}, "requirements[0].over.range_m", "from < to"),
    ({"over": {"rnge_m": ["1 km", "2 km"]}}, "requirements[0].over.rnge_m", "range_m"),
    ({"over": {"peak_power_w": ["1 W", "2 W"]}}, "requirements[0].over.peak_power_w", "design variable"),
    ({"over": {"range_m": ["1 km"]}}, "requirements[0].over.range_m", "[from, to]"),
    ({"over": {"range_m": ["0.1 m", "2 km"]}}, "requirements[0].over.range_m[0]", "domain"),
    ({"over": {"range_m": ["1 s", "2 km"]}}, "requirements[0].over.range_m[0]", "m"),
    ({"over_points": 2}, "requirements[0].over_points", "whole number"),
    ({"over": {}}, "requirements[0].over", "table"),
])
def test_bad_intervals_name_the_key(extra, key, words):
    with pytest.raises(SpecError) as err:
        parse_spec(_raw(**extra))
    assert key in str(err.value) and words in str(err.value)


def test_an_equality_cannot_hold_over_an_interval():
    raw = _raw()
    req = raw["requirements"][0]
    del req["at_least"]
    req["equals"] = "0 dB"
    with pytest.raises(SpecError, match="equality cannot hold over an interval"):
        parse_spec(raw)


def _independent_margins(model, x, combo, req, points):
    """The requirement's output at ``points`` (n, d), evaluated by the chain directly."""
    values = np.asarray(model.layout.values, dtype=float).copy()
    values[model.layout.variable_slots] = np.asarray(x, dtype=float)
    values[model.layout.catalog_slots] = np.asarray(combo, dtype=float)[:-1]
    params = model.parameters(jnp.asarray(values))[req.case]
    scene = model.spec.scenes[req.case]
    chain = chain_for(scene)

    def one(q):
        p = dict(params)
        for k, iv in enumerate(req.over):
            p[iv.parameter] = q[k]
        return chain.compute(scene, p).values[req.output]

    return np.asarray(jax.jit(jax.vmap(one))(jnp.asarray(points)))


@pytest.mark.slow
@pytest.mark.parametrize("name, per_axis", [("multipath_null", 20_011), ("multipath_null_box", 121)])
def test_binding_interior_null_is_met_on_a_dense_grid_and_not_over_designed(name, per_axis):
    spec = load_spec(SPECS / f"{name}.toml")
    model = DesignModel(spec)
    opt = optimize_design(model, n_starts=2)
    assert opt.feasible
    req = spec.requirements[0]
    # an independent grid: uniform in each parameter (the solver searches a log or shifted grid)
    axes = [np.linspace(iv.lower, iv.upper, per_axis) for iv in req.over]
    pts = np.stack([m.ravel() for m in np.meshgrid(*axes, indexing="ij")], axis=-1)
    assert pts.shape[0] >= 10_000
    margin = _independent_margins(model, opt.x, model.combo_table[opt.combo_index], req, pts)
    k = int(np.argmin(margin))
    assert margin[k] >= -1e-6
    # the binding point is the multipath null inside the range interval, and the design is tight
    # there: the smallest margin on the grid is within 0.01 dB of zero
    assert margin[k] <= 0.01
    assert req.over[0].lower + 100.0 < pts[k, 0] < req.over[0].upper - 100.0
