"""Shipped designs optimised through the public path: the answer re-evaluated meets every
requirement, stays inside its bounds, and matches closed-form optima where they exist."""

from pathlib import Path

import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.design.model import DesignModel
from diffsense.design.optimizer import optimize_design
from diffsense.design.spec import load_spec
from helpers.paths import DESIGNS



@pytest.fixture(scope="module", params=[1, None], ids=["lanes-in-sequence", "lanes-in-one-vmap"])
def sidescan(request):
    # lockstep=1: lanes one after another (the CPU default); None: every lane in one vmap
    model = DesignModel(load_spec(DESIGNS / "sidescan_sonar.toml"))
    return model, optimize_design(model, n_starts=4, seed=1, lockstep=request.param)


def test_sidescan_optimum_meets_every_requirement_within_bounds(sidescan):
    model, opt = sidescan
    assert opt.feasible and opt.converged
    assert np.all(opt.x >= model.lower) and np.all(opt.x <= model.upper)
    rows = model.requirement_report(opt.x, model.combo_table[opt.combo_index], tol=0.0)
    assert all(r["met"] for r in rows), rows


def test_sidescan_power_is_the_closed_form_minimum(sidescan):
    # Source level grows as 10 log10 P (book eq 12.4 with eq 12.2), nothing else depends on
    # the electrical power: at the optimum the detection margin is zero, so the minimum power
    # is P = P0 10^(-m0/10) with m0 the margin at any P0 and the optimal beam and chirp.
    model, opt = sidescan
    x = opt.x.copy()
    i = model.variable_names.index("electrical_power_w")
    x[i] = 1500.0
    k = [r.output for r in model.requirements].index("snr_margin_db")
    m0 = float(model.evaluate_all(x, model.combo_table[opt.combo_index])[1][k])
    assert opt.x[i] == pytest.approx(1500.0 * 10 ** (-m0 / 10), rel=1e-5)


def test_sidescan_multistart_agrees(sidescan):
    _, opt = sidescan
    assert opt.starts_at_best == opt.starts


@pytest.mark.slow
def test_ore_pass_optimum_meets_every_requirement_and_fills_the_beam_limit():
    model = DesignModel(load_spec(DESIGNS / "ore_pass.toml"))
    opt = optimize_design(model, n_starts=4)
    assert opt.feasible
    rows = {r["output"]: r for r in model.requirement_report(opt.x, model.combo_table[opt.combo_index], tol=0.0)}
    assert all(r["met"] for r in rows.values())
    # the cheapest antenna is the one whose beam just fits the pass: d = 70 lambda / 1.1 deg
    lam = 299792458.0 / float(model.combo_table[opt.combo_index][model.combo_params.index("freq_hz")])
    d = opt.x[model.variable_names.index("antenna_diameter_m")]
    assert d == pytest.approx(70.0 * lam / 1.1, rel=1e-5)  # book 8.16.9: theta(deg) = 70 lambda / d
