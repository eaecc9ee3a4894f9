"""The shipped FMCW designs (designs/fmcw_seeker.toml, designs/automotive_corner_radar.toml),
optimised through the public path, meet every requirement and land on the closed forms their
active requirements give:

* seeker (Brooker §11.12.4): the 0.5 m resolution sets Δf = c/(2 · 0.5 m) (the book's 300 MHz);
  the 2.5× oversampling of the 1 km beat sets T_b = 2.5 · 2 Δf R / (c f_s) (the book's 500 µs);
  the antenna is the smallest whose SINR at 1 km in rain equals the Swerling 1 requirement
  ln Pfa / ln Pd − 1, solved here with mpmath from the radar equation and the leakage model
  (the rain and gas attenuations taken from the ITU functions of diffsense.physics);
* corner radar: Δf = c/(2 · 0.15 m); the 20° beam sets d = k λ / θ; the car's beat at 150 m
  with its 50 m/s Doppler sets T_b; the pedestrian at 80 m sets the power, linear in P.

The optimisations are heavy (about a minute each on one core): marked slow.
"""

import math

import mpmath as mp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.design.model import DesignModel
from diffsense.design.optimizer import optimize_design
from diffsense.design.spec import load_spec
from diffsense.optimize import SolverOptions
from diffsense.physics.propagation.gas import gas_attenuation_db_per_km
from diffsense.physics.propagation.rain import rain_attenuation_db_per_km
from helpers.paths import DESIGNS

C = 299792458.0
K_B = mp.mpf("1.380649e-23")
T0 = mp.mpf(290)
MARGIN = 1e-7
_CACHE = {}


def optimum(name):
    if name not in _CACHE:
        model = DesignModel(load_spec(DESIGNS / f"{name}.toml"))
        _CACHE[name] = (model, optimize_design(model, n_starts=2, seed=0, margin=MARGIN,
                                               options=SolverOptions(polish=True)))
    return _CACHE[name]


def meets_requirements(model, opt):
    assert opt.feasible and opt.converged, opt.unmet
    assert np.all(opt.x >= model.lower) and np.all(opt.x <= model.upper)
    rows = model.requirement_report(opt.x, model.combo_table[opt.combo_index], tol=0.0)
    assert all(r["met"] for r in rows), rows


def x_of(model, opt):
    return dict(zip(model.variable_names, (float(v) for v in opt.x)))


def db(x):
    return 10 * mp.log10(x)


def swerling1_required_snr(pd, pfa):
    """Swerling 1, one sample: Pd = Pfa^(1/(1+S)) (Marcum & Swerling 1960) → S = ln Pfa / ln Pd − 1."""
    return mp.log(pfa) / mp.log(pd) - 1


@pytest.mark.parametrize("name", ["fmcw_seeker", "automotive_corner_radar"])
def test_spec_loads_and_builds(name):
    spec = load_spec(DESIGNS / f"{name}.toml")
    model = DesignModel(spec)
    assert spec.sensor == "fmcw"
    assert {"sweep_time_s", "antenna_diameter_m", "sweep_bandwidth_hz"} <= set(model.variable_names)


@pytest.mark.slow
def test_seeker_optimum_is_the_books_sweep_and_the_least_antenna():
    model, opt = optimum("fmcw_seeker")
    meets_requirements(model, opt)
    x = x_of(model, opt)
    df = C / (2 * 0.5)
    assert x["sweep_bandwidth_hz"] == pytest.approx(df, rel=1e-5)
    tb = 2.5 * 2 * df * 1000.0 / (C * 10e6)
    assert x["sweep_time_s"] == pytest.approx(tb, rel=1e-5)
    assert x["sweep_time_s"] == pytest.approx(500e-6, rel=1e-3)  # the book's 500 µs (c = 3e8 there)
    # the antenna: SINR(1 km, rain) = required, with the leakage floor (Stove 1992)
    lam = mp.mpf(C) / mp.mpf(94e9)
    alpha = mp.mpf(float(rain_attenuation_db_per_km(94e9, 4.0, "horizontal"))) + mp.mpf(
        float(gas_attenuation_db_per_km(94e9, 1013.25, 288.15, 7.5)))
    r = mp.mpf(1000)
    beta = mp.mpf("1.3") * mp.mpf(10e6) / 4096
    noise = K_B * T0 * beta * 10 ** mp.mpf("1.5")
    fb = mp.mpf(df) * 2 * r / (C * mp.mpf(x["sweep_time_s"]))
    leak = (mp.mpf("0.1") * 10 ** mp.mpf(-3) * 10 ** ((-90 - 20 * mp.log10(fb / mp.mpf(1e5))) / 10)
            * 4 * mp.sin(mp.pi * fb * mp.mpf(1e-9)) ** 2 * beta)
    need = swerling1_required_snr(mp.mpf("0.9"), mp.mpf("1e-6"))

    def sinr(d):
        gain = 4 * mp.pi * mp.mpf("0.7") * (mp.pi * d**2 / 4) / lam**2
        pr = mp.mpf("0.1") * gain**2 * lam**2 * 10 / ((4 * mp.pi) ** 3 * r**4) * 10 ** (-2 * alpha * r / 1000 / 10)
        return pr / (noise + leak)

    d = mp.findroot(lambda d: db(sinr(d)) - db(need), mp.mpf("0.1"))
    assert x["antenna_diameter_m"] == pytest.approx(float(d), rel=1e-5)


@pytest.mark.slow
def test_corner_radar_optimum_meets_the_closed_forms():
    model, opt = optimum("automotive_corner_radar")
    meets_requirements(model, opt)
    x = x_of(model, opt)
    lam = C / 76.5e9
    assert x["sweep_bandwidth_hz"] == pytest.approx(C / (2 * 0.15), rel=1e-5)
    assert x["antenna_diameter_m"] == pytest.approx((70 * math.pi / 180) * lam / math.radians(20.0), rel=1e-5)
    fd = 2 * 50.0 / lam
    fb = 20e6 / 2.5 - fd
    assert x["sweep_time_s"] == pytest.approx(2 * x["sweep_bandwidth_hz"] * 150.0 / (C * fb), rel=1e-5)
    # power: the pedestrian's SNR at 80 m equals the Swerling 1 requirement (linear in P)
    lam_m = mp.mpf(C) / mp.mpf(76.5e9)
    d = mp.mpf(x["antenna_diameter_m"])
    gain = 4 * mp.pi * mp.mpf("0.7") * (mp.pi * d**2 / 4) / lam_m**2
    r = mp.mpf(80)
    alpha = mp.mpf(float(rain_attenuation_db_per_km(76.5e9, 25.0, "horizontal")))
    pr_per_w = gain**2 * lam_m**2 * mp.mpf("0.1") / ((4 * mp.pi) ** 3 * r**4) * 10 ** ((-2 * alpha * r / 1000 - 2) / 10)
    noise = K_B * T0 * mp.mpf("1.5") * mp.mpf(20e6) / 1024 * 10 ** mp.mpf("1.2") / 128
    power = swerling1_required_snr(mp.mpf("0.9"), mp.mpf("1e-6")) * noise / pr_per_w
    assert x["transmit_power_w"] == pytest.approx(float(power), rel=1e-5)
