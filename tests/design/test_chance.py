"""Requirements met with a probability over uncertain inputs: the ``[uncertain]`` section, the
smoothed-quantile chance constraint and the independent Monte Carlo check.

The closed forms: in a radar without clutter the detection margin in dB is
m = m_nom + 10 log10(σ/σ_med) − (NF − NF_nom) − 2 R (α − α_nom) (one term per input), so

* a lognormal RCS of spread s dB makes m normal with standard deviation s: the design meets
  P[m ≥ 0] = p exactly when m_nom = s·Φ⁻¹(p), and the least peak power is
  P* = P0·10^((s·Φ⁻¹(p) − m0)/10) (m0 the nominal margin at P0);
* a normal noise figure of standard deviation σ: P[m ≥ 0] = Φ(m_nom/σ);
* a uniform attenuation on [a, b]: P[m ≥ 0] = (α* − a)/(b − a) with α* = α_nom + m_nom/(2R).
"""

import json
import math
from statistics import NormalDist

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from diffsense.design.chance import smooth_quantile
from diffsense.design.model import DesignModel
from diffsense.design.monte_carlo import check_probabilities, wilson_interval
from diffsense.design.optimizer import optimize_design
from diffsense.design.spec import load_spec, parse_spec
from diffsense.errors import SpecError

RANGE_KM = 320.0


def radar_spec(uncertain, probability=0.95, **extra_fixed):
    fixed = {"freq_hz": "1.3034 GHz", "pulse_width_s": "2 us", "bandwidth_hz": "306.5 kHz", "prf_hz": "360 Hz",
             "n_pulses": 10, "noise_figure_db": "4 dB", "aperture_efficiency": 0.7, "detectability_db": "8.2 dB",
             "gas_attenuation_db_km": "0.003 dB/km", "range_m": f"{RANGE_KM} km", "antenna_diameter_m": "5.5 m",
             "rcs_m2": "1 m^2"}
    fixed.update(extra_fixed)
    for name in uncertain:
        fixed.pop(name, None)
    req = {"output": "detection_margin_db", "at_least": "0 dB"}
    if probability is not None:
        req["probability"] = probability
    return {"sensor": "radar", "parts": ["gas"],
            "options": {"antenna": "circular_aperture", "detectability": "given", "gas_model": "specified"},
            "fixed": fixed, "uncertain": uncertain,
            "variables": {"peak_power_w": {"lower": "100 kW", "upper": "50 MW", "initial": "5 MW"}},
            "requirements": [req], "objective": {"minimize": "peak_power_w"}}


def nominal_margin(model, x):
    ev, _, _ = model.evaluate_all(np.asarray(x, dtype=float), model.combo_table[0])
    return float(ev["main"].values["detection_margin_db"])


# --- the spec --------------------------------------------------------------------------------
@pytest.mark.parametrize("change, key, text", [
    ({"uncertain": {"rcs_m2": {"lognormal": "1 m^2"}}}, "uncertain.rcs_m2.sigma_db", "missing"),
    ({"uncertain": {"rcs_m2": {"gamma": 1}}}, "uncertain.rcs_m2", "exactly one of"),
    ({"uncertain": {"rcs_m2": {"lognormal": "1 m^2", "sigma_db": 3, "sigma": 1}}}, "uncertain.rcs_m2.sigma",
     "unknown key"),
    ({"uncertain": {"rcs_m2": {"lognormal": "-1 m^2", "sigma_db": 3}}}, "uncertain.rcs_m2.lognormal", "positive"),
    ({"uncertain": {"rcs_m2": {"lognormal": "1 m^2", "sigma_db": 0}}}, "uncertain.rcs_m2.sigma_db", "positive"),
    ({"uncertain": {"noise_figure_db": {"normal": "1 dB", "sigma": "0.5 dB"}}}, "uncertain.noise_figure_db",
     "outside the model's domain"),
    ({"uncertain": {"noise_figure_db": {"normal": "5 dB", "sigma": "0.5 K"}}}, "uncertain.noise_figure_db.sigma",
     "spread"),
    ({"uncertain": {"gas_attenuation_db_km": {"uniform": ["0.01 dB/km", "0.001 dB/km"]}}},
     "uncertain.gas_attenuation_db_km.uniform", "lower < upper"),
    ({"uncertain": {"peak_power_w": {"normal": "5 MW", "sigma": "1 kW"}}}, "uncertain.peak_power_w",
     "design variable"),
    ({"uncertain": {"rcs_mm": {"normal": 1, "sigma": 0.1}}}, "uncertain.rcs_mm", "did you mean 'rcs_m2'"),
    ({"uncertain": {"rcs_m2": {"lognormal": 1, "sigma_db": 3}, "check_samples": 1000}}, "uncertain.check_samples",
     "from 100000"),
    ({"uncertain": {"rcs_m2": {"lognormal": 1, "sigma_db": 3}, "samples": 128}},
     "requirements[0].probability", "samples = 400"),
])
def test_bad_uncertain_sections_are_one_clear_spec_error(change, key, text):
    raw = radar_spec({})
    raw.update(change)
    for name in raw["uncertain"]:
        raw["fixed"].pop(name, None)
    with pytest.raises(SpecError) as exc:
        parse_spec(raw)
    assert exc.value.key == key and text in str(exc.value), str(exc.value)


def test_bad_probabilities_are_spec_errors():
    raw = radar_spec({"rcs_m2": {"lognormal": "1 m^2", "sigma_db": 3}})
    raw["requirements"][0]["probability"] = 1.0
    with pytest.raises(SpecError, match="between 0 and 1"):
        parse_spec(raw)
    raw["requirements"][0].update(probability=0.9, equals="0 dB")
    del raw["requirements"][0]["at_least"]
    with pytest.raises(SpecError, match="probability 0"):
        parse_spec(raw)
    raw = radar_spec({})
    del raw["uncertain"]
    raw["requirements"][0]["probability"] = 0.9
    with pytest.raises(SpecError, match=r"needs an \[uncertain\] table"):
        parse_spec(raw)
    raw = radar_spec({"rcs_m2": {"lognormal": "1 m^2", "sigma_db": 3}})
    raw["fixed"]["rcs_m2"] = "1 m^2"
    with pytest.raises(SpecError, match="is uncertain: remove it here") as exc:
        parse_spec(raw)
    assert exc.value.key == "fixed.rcs_m2"


def test_the_nominal_value_is_the_median_and_units_convert():
    spec = parse_spec(radar_spec({"rcs_m2": {"lognormal": "3 dBsm", "sigma_db": "3 dB"},
                                  "noise_figure_db": {"normal": "5 dB", "sigma": "0.5 dB"},
                                  "gas_attenuation_db_km": {"uniform": ["0 dB/km", "0.01 dB/km"]}}))
    assert spec.fixed["main"]["rcs_m2"] == pytest.approx(10 ** 0.3, rel=1e-12)
    assert spec.fixed["main"]["noise_figure_db"] == 5.0
    assert spec.fixed["main"]["gas_attenuation_db_km"] == pytest.approx(0.005, rel=1e-12)
    lognormal = spec.uncertain.distributions[0]
    assert lognormal.spread == pytest.approx(3.0 * math.log(10.0) / 10.0, rel=1e-15)  # nepers
    assert spec.requirements[0].probability == 0.95
    assert (spec.uncertain.samples, spec.uncertain.check_samples, spec.uncertain.confidence) == (4096, 100_000, 0.99)


# --- the smoothed quantile -------------------------------------------------------------------
def test_smooth_quantile_is_the_quantile_and_its_derivative_the_implicit_one():
    rng = np.random.default_rng(7)
    v = jnp.asarray(rng.normal(size=4096))
    h = 0.02
    q = float(smooth_quantile(v, h, 0.05))
    # the kernel CDF at q equals alpha, and q is within a sample spacing of the empirical quantile
    assert float(jnp.mean(jax.scipy.special.ndtr((q - v) / h))) == pytest.approx(0.05, abs=1e-12)
    assert q == pytest.approx(float(np.quantile(np.asarray(v), 0.05)), abs=0.03)
    # gradient against central differences along a random direction, and in h
    d = jnp.asarray(rng.normal(size=4096))
    f = lambda t: smooth_quantile(v + t * d, h, 0.05)  # noqa: E731
    g = jax.jvp(f, (0.0,), (1.0,))[1]
    eps = 1e-5
    assert float(g) == pytest.approx(float((f(eps) - f(-eps)) / (2 * eps)), rel=1e-6)
    gh = jax.grad(lambda hh: smooth_quantile(v, hh, 0.05))(h)
    assert float(gh) == pytest.approx(float((smooth_quantile(v, h + eps, 0.05) - smooth_quantile(v, h - eps, 0.05))
                                            / (2 * eps)), rel=1e-5)
    # second derivative exists (the report's Hessian) and is finite
    assert np.isfinite(float(jax.grad(jax.grad(f))(0.0)))


def test_wilson_interval_matches_the_formula_and_covers_the_proportion():
    # closed form at k = n/2: centre 1/2, half-width z/(2 sqrt(n + z^2))
    z = NormalDist().inv_cdf(0.975)
    lo, hi = wilson_interval(500, 1000, 0.95)
    assert 0.5 - lo == pytest.approx(z / (2 * math.sqrt(1000 + z * z)), rel=1e-12)
    assert hi - 0.5 == pytest.approx(z / (2 * math.sqrt(1000 + z * z)), rel=1e-12)
    assert wilson_interval(0, 100)[0] == 0.0 and wilson_interval(100, 100)[1] == 1.0


# --- acceptance: closed form and independent check ---------------------------------------------
@pytest.fixture(scope="module")
def lognormal_rcs_optimum():
    spec = parse_spec(radar_spec({"rcs_m2": {"lognormal": "1 m^2", "sigma_db": 3}}, probability=0.95))
    model = DesignModel(spec)
    res = optimize_design(model, n_starts=2)
    return model, res


def test_chance_constrained_power_matches_the_closed_form(lognormal_rcs_optimum):
    model, res = lognormal_rcs_optimum
    assert res.feasible and res.converged
    p0 = model.initial[0]
    m0 = nominal_margin(model, [p0])
    s, p = 3.0, 0.95
    p_star = p0 * 10 ** ((s * NormalDist().inv_cdf(p) - m0) / 10)
    # smoothing bias (h^2/2) f'(q) and the Sobol sample's error: 2.3e-4 relative (0.001 dB) here
    assert res.x[0] == pytest.approx(p_star, rel=1e-3)
    # the exact probability at the optimum (the margin is normal in dB with sd s)
    exact = NormalDist().cdf(nominal_margin(model, res.x) / s)
    assert exact == pytest.approx(p, abs=1e-4)


def test_independent_monte_carlo_confirms_the_asked_probability(lognormal_rcs_optimum):
    model, res = lognormal_rcs_optimum
    checks = check_probabilities(model, res.x, model.combo_table[0])
    chk = checks[0]
    assert chk.samples >= 100_000 and chk.seed == model.spec.uncertain.seed
    assert chk.lower <= 0.95 <= chk.upper and chk.status == "consistent", chk
    # and the interval covers the closed-form probability at the same design
    exact = NormalDist().cdf(nominal_margin(model, res.x) / 3.0)
    assert chk.lower <= exact <= chk.upper


def test_gradients_of_the_chance_row_are_finite_and_match_differences(lognormal_rcs_optimum):
    model, res = lognormal_rcs_optimum
    theta = jax.tree_util.tree_map(jnp.asarray, model.solve_inputs(model.inputs(0), 0, model.limits, 1.0))
    fn = jax.jit(lambda x: model.residuals(x, theta)[0])
    x = jnp.asarray(res.x)
    g = jax.grad(fn)(x)
    H = jax.hessian(fn)(x)
    assert np.all(np.isfinite(np.asarray(g))) and np.all(np.isfinite(np.asarray(H)))
    # the margin's quantile moves as 10 log10 P: d/dP = 10/(P ln 10)
    assert float(g[0]) == pytest.approx(-10.0 / (float(x[0]) * math.log(10.0)), rel=1e-6)
    # the multiplier is positive: the chance constraint is active
    assert res.multipliers[0] > 0


@pytest.mark.parametrize("uncertain, power_w, closed_form", [
    ({"noise_figure_db": {"normal": "10 dB", "sigma": "1.5 dB"}}, 5e6,
     lambda m: NormalDist().cdf(m / 1.5)),
    ({"gas_attenuation_db_km": {"uniform": ["0 dB/km", "0.02 dB/km"]}}, 2e6,
     lambda m: min(1.0, max(0.0, (0.01 + m / (2 * RANGE_KM)) / 0.02))),
])
def test_monte_carlo_probability_of_a_deterministic_requirement_matches_closed_forms(uncertain, power_w, closed_form):
    model = DesignModel(parse_spec(radar_spec(uncertain, probability=None)))
    x = np.array([power_w])
    m = nominal_margin(model, x)
    exact = closed_form(m)
    assert 0.05 < exact < 0.95  # a probability the check must resolve
    chk = check_probabilities(model, x, model.combo_table[0])[0]
    assert chk.asked is None and chk.status is None
    assert chk.lower <= exact <= chk.upper, (exact, chk)


def test_evaluate_prints_and_writes_each_requirements_probability(tmp_path):
    from typer.testing import CliRunner

    from diffsense.cli import app

    spec = tmp_path / "uncertain.toml"
    spec.write_text("""
sensor = "radar"
parts = ["gas"]
[options]
antenna = "circular_aperture"
detectability = "given"
gas_model = "specified"
[fixed]
freq_hz = "1.3034 GHz"
pulse_width_s = "2 us"
bandwidth_hz = "306.5 kHz"
prf_hz = "360 Hz"
n_pulses = 10
noise_figure_db = "4 dB"
aperture_efficiency = 0.7
detectability_db = "8.2 dB"
gas_attenuation_db_km = "0.003 dB/km"
range_m = "320 km"
antenna_diameter_m = "5.5 m"
[uncertain]
rcs_m2 = { lognormal = "1 m^2", sigma_db = 3 }
[variables.peak_power_w]
lower = "100 kW"
upper = "50 MW"
initial = "5 MW"
[[requirements]]
name = "detect with 95 %"
output = "detection_margin_db"
at_least = "0 dB"
probability = 0.95
[objective]
minimize = "peak_power_w"
""")
    out = tmp_path / "eval.json"
    result = CliRunner().invoke(app, ["evaluate", str(spec), "--json", str(out)])
    assert result.exit_code == 0, result.output
    assert "Probability met under the declared uncertainty" in result.output
    row = json.loads(out.read_text())["requirements"][0]
    chk = row["probability"]
    assert chk["asked"] == 0.95 and chk["samples"] == 100_000 and chk["status"] == "above"
    # at 5 MW the margin is 7.41 dB: P = Phi(7.41/3) = 0.9932 (closed form), inside the interval
    exact = NormalDist().cdf(nominal_margin(DesignModel(load_spec(spec)), [5e6]) / 3.0)
    assert chk["interval"][0] <= exact <= chk["interval"][1]
