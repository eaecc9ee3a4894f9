"""Book worked example 9.2.2 (Brooker): threshold and false-alarm time for Pfa = 1e-10.

Noise variance ψ = 1 V², pulse 0.3 µs, matched bandwidth β = 1/τ = 3.33 MHz:
Vt = sqrt(-2 ψ ln Pfa) = 6.79 V and Tfa = 1/(Pfa β) = 3.0e3 s (50 min).
"""

import math

import jax
import pytest

import diffsense  # noqa: F401
import diffsense.detection as det


def test_pfa_example_voltage_threshold_6_79_v_book_9_2_2():
    # book prints 3 significant digits: tolerance half a unit of the last digit
    vt = float(det.voltage_threshold(1e-10, 1.0))
    assert abs(vt - 6.79) <= 0.005
    # Rayleigh envelope: Pfa = exp(-Vt²/(2ψ)), so the threshold gives back Pfa (closed form)
    assert math.exp(-vt * vt / 2.0) == pytest.approx(1e-10, rel=1e-12)


def test_pfa_example_power_threshold_is_the_voltage_threshold_squared_over_two():
    # the square-law threshold on Gamma(1, 1) noise is T = -ln Pfa = Vt²/(2ψ) (book eq 9.14)
    t = float(det.threshold(1e-10, 1))
    assert t == pytest.approx(-math.log(1e-10), rel=1e-12)
    assert t == pytest.approx(float(det.voltage_threshold(1e-10, 1.0)) ** 2 / 2.0, rel=1e-12)
    assert float(det.pfa_from_threshold(t, 1)) == pytest.approx(1e-10, rel=1e-10)


def test_pfa_example_false_alarm_time_3e3_s_book_9_2_2():
    # β = 3.33 MHz as printed: Tfa = 3003 s; the book rounds to 3.0e3 s (2 digits): 1 % tolerance
    tfa = float(det.false_alarm_time_s(1e-10, 3.33e6))
    assert abs(tfa / 3.0e3 - 1) < 0.01
    # with the exact β = 1/τ it is exactly 3000 s
    assert float(det.false_alarm_time_s(1e-10, 1.0 / 0.3e-6)) == pytest.approx(3000.0, rel=1e-12)
    assert tfa / 60 == pytest.approx(50.0, rel=0.01)  # "50 min"


def test_pfa_example_threshold_derivative_closed_form():
    # dVt/dPfa = -ψ / (Pfa Vt) from Vt = sqrt(-2 ψ ln Pfa)
    pfa = 1e-10
    g = float(jax.grad(lambda p: det.voltage_threshold(p, 1.0))(pfa))
    vt = math.sqrt(-2 * math.log(pfa))
    assert g == pytest.approx(-1.0 / (pfa * vt), rel=1e-12)
