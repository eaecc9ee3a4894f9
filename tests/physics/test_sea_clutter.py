"""Sea-clutter reflectivity: the NRL model, its ψ⁴ continuation below 0.1°, constant γ, domains.

References used by the assertions:
- MATLAB Radar Toolbox documentation of ``seareflectivity`` (NRL model by Gregers-Hansen and
  Mital): sea state 2, grazing 10°, 30 GHz, default (horizontal) polarization prints
  ``nrcs = 2.1555e-04``.
- The NRL formula (Gregers-Hansen & Mital 2012) written out here with a second, 4-digit
  transcription of its vertical-polarization coefficients (c1 −50.79, c4 21.58 against the
  package's −50.796, 21.588: agreement to the rounding, 0.01-0.03 dB).
- Katzin (1957) / Barton (2013): σ° ∝ ψ⁴ far below the critical angle (slope 40 dB/decade).
- Book §8.12.4 eq (8.29) (Barton's γ) with the book's Table 12.2.
"""

import math

import jax
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.physics import sea_clutter as sc
from diffsense.physics.sea_state import beaufort_from_sea_state

DEG = math.pi / 180


def test_nrl_reproduces_matlab_seareflectivity_example():
    got = 10 ** (float(sc.nrl_sea_clutter_sigma0_db(30e9, 2.0, 10 * DEG)) / 10)
    assert got == pytest.approx(2.1555e-4, abs=0.00005e-4)
    assert float(sc.sea_clutter_sigma0(10 * DEG, 30e9, 2.0)) == pytest.approx(got, rel=1e-12)


def test_nrl_vertical_against_the_printed_coefficient_table():
    for f_ghz, ss, psi in ((3.0, 1.0, 0.5), (9.5, 4.0, 3.0), (35.0, 6.0, 45.0)):
        want = (-50.79 + 25.93 * math.log10(math.sin(psi * DEG)) + (27.5 + 0.7093 * psi) * math.log10(f_ghz) / (1 + 0.95 * psi)
                + 21.58 * (1 + ss) ** (1 / (2 + 0.085 * psi + 0.033 * ss)) + 0.00211 * psi**2)
        got = float(sc.nrl_sea_clutter_sigma0_db(f_ghz * 1e9, ss, psi * DEG, "vertical"))
        assert got == pytest.approx(want, abs=0.01 + 0.008 * (1 + ss) ** 0.5)


def test_continuation_below_0_1_deg_is_c1_and_tends_to_psi4():
    f, ss = 9.5e9, 4.0
    psi0 = 0.1 * DEG
    for pol in ("horizontal", "vertical"):
        fn = lambda p: sc.sea_clutter_sigma0_db(p, f, ss, "nrl", pol)
        slope = lambda p: float(jax.grad(fn)(p)) * p  # dB per neper of ψ
        # continuous value and slope at 0.1°
        assert float(fn(psi0 * (1 - 1e-9))) == pytest.approx(float(fn(psi0 * (1 + 1e-9))), abs=1e-6)
        assert slope(psi0 * (1 - 1e-9)) == pytest.approx(slope(psi0 * (1 + 1e-9)), abs=1e-5)
        # the NRL slope at 0.1° is below ψ⁴; far below, the slope is 40 dB/decade = 17.37 dB/neper
        assert slope(psi0) < 40 / math.log(10)
        assert slope(1e-4 * DEG) == pytest.approx(40 / math.log(10), rel=1e-3)
        # monotone, finite down to 0.001° and at the ship-radar angle 0.05°
        psis = np.geomspace(1e-3, 1.0, 60) * DEG
        vals = np.array([float(fn(p)) for p in psis])
        assert np.all(np.diff(vals) > 0) and np.all(np.isfinite(vals))
        assert np.isfinite(slope(0.05 * DEG))


def test_constant_gamma_is_barton_gamma_sin_psi_in_the_plateau():
    lam = 0.03
    kb = float(beaufort_from_sea_state(3.0))
    for psi in (1.0, 10.0, 60.0):
        want = 6 * kb - 10 * math.log10(lam) - 64 + 10 * math.log10(math.sin(psi * DEG))
        got = float(sc.sea_clutter_sigma0_db(psi * DEG, 299792458.0 / lam, 3.0, "constant_gamma"))
        assert got == pytest.approx(want, abs=1e-10)


@pytest.mark.parametrize(
    "call",
    [
        lambda: sc.sea_clutter_sigma0_db(0.5 * DEG, 10e9, 3.0, "constant_gamma"),  # below the plateau
        lambda: sc.sea_clutter_sigma0_db(70 * DEG, 10e9, 3.0, "constant_gamma"),
        lambda: sc.sea_clutter_sigma0_db(1 * DEG, 40e9, 3.0),  # NRL above 35 GHz
        lambda: sc.sea_clutter_sigma0_db(1 * DEG, 0.4e9, 3.0),
        lambda: sc.sea_clutter_sigma0_db(1 * DEG, 10e9, 7.0),  # sea state above 6
        lambda: sc.sea_clutter_sigma0_db(61 * DEG, 10e9, 3.0),
        lambda: sc.sea_clutter_sigma0_db(0.0, 10e9, 3.0),
        lambda: sc.nrl_sea_clutter_sigma0_db(10e9, 3.0, 0.05 * DEG),  # the fitted model itself stops at 0.1°
        lambda: sc.sea_clutter_sigma0_db(1 * DEG, 10e9, 3.0, "git"),
        lambda: sc.sea_clutter_sigma0_db(1 * DEG, 10e9, 3.0, "nrl", "circular"),
    ],
)
def test_domains_are_enforced(call):
    with pytest.raises(DomainError):
        call()


def test_gradients_finite_over_the_nrl_domain():
    g = jax.jit(jax.grad(lambda p, f, s: sc.sea_clutter_sigma0_db(p, f, s), argnums=(0, 1, 2)))
    for p in (0.01, 0.05, 0.1, 1.0, 30.0, 60.0):
        for f in (0.5e9, 10e9, 35e9):
            for s in (0.0, 3.0, 6.0):
                assert all(np.isfinite(float(x)) for x in g(p * DEG, f, s))
