"""Platform motion in the angle servo: the lag follows the angular acceleration a/R + Ω̇ (book eq
14.10 with the ship's motion of 14.9.1 added to the target's geometric acceleration)."""

import math

import pytest

import diffsense  # noqa: F401
from diffsense.scene import Scene, complete_parameters, evaluator

SCENE = Scene("radar", ["tracking"], {"antenna": "circular_aperture", "detectability": "given",
                                       "matched_filter": "matched"})
PARAMS = dict(range_m=2e3, peak_power_w=5e3, pulse_width_s=0.2e-6, freq_hz=16e9, bandwidth_hz=5e6,
              noise_figure_db=5.0, prf_hz=5e3, antenna_diameter_m=1.2, detectability_db=15.0, track_alpha=0.05,
              servo_bandwidth_hz=2.9, positioner_resonance_hz=30.0, target_acceleration_m_s2=5.0)
EVAL = evaluator(SCENE)


def _lag(**extra):
    return float(EVAL(complete_parameters(SCENE, dict(PARAMS, **extra)))["angle_lag_rad"])


def test_a_fixed_mount_is_the_default():
    assert _lag() == pytest.approx(_lag(platform_angular_acceleration_rad_s2=0.0), rel=0, abs=0)


def test_ship_roll_adds_to_the_geometric_acceleration_in_the_lag():
    # roll +-25 deg with a 5 s period: peak angular acceleration A w^2 = 0.436 rad * (2 pi / 5 s)^2
    roll = math.radians(25.0) * (2.0 * math.pi / 5.0) ** 2
    assert roll == pytest.approx(0.689, abs=1e-3)
    ka = 2.5 * 2.9**2  # book eq 14.9
    expected = (5.0 / 2e3 + roll) / ka  # book eq 14.10 with a/R + the platform's acceleration
    assert _lag(platform_angular_acceleration_rad_s2=roll) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(0.033, abs=5e-4)  # the 33 mrad lag of an unstabilised mount
