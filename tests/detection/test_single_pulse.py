"""One-sample detection (diffsense.detection.single_pulse): the Swerling 1/2 closed forms it
uses must agree with the package's series (pd with N = 1.0 as an array, the exact root solve)
and with a 30-digit mpmath evaluation of Pd = Pfa^(1/(1+S)) inverted by findroot."""

import jax
import jax.numpy as jnp
import mpmath as mp
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.detection import pd, required_snr_db
from diffsense.detection.single_pulse import single_pulse_pd, single_pulse_required_snr_db
from diffsense.errors import DomainError

MPMATH_DPS = 30
GRID = [(pd_t, pfa) for pd_t in (0.1, 0.5, 0.9, 0.999) for pfa in (1e-2, 1e-6, 1e-12)]


@pytest.mark.parametrize("swerling", [1, 2])
@pytest.mark.parametrize("pd_t,pfa", GRID)
def test_closed_form_required_snr_matches_series_solver_and_mpmath(swerling, pd_t, pfa):
    closed = float(single_pulse_required_snr_db(pd_t, pfa, swerling))
    series = float(required_snr_db(pd_t, pfa, jnp.asarray(1.0), swerling))
    s = mp.findroot(lambda x: mp.mpf(pfa) ** (1 / (1 + 10 ** (x / 10))) - mp.mpf(pd_t), closed)
    assert abs(closed - float(s)) < 1e-10
    assert abs(closed - series) < 1e-9


@pytest.mark.parametrize("swerling", [1, 2])
@pytest.mark.parametrize("snr_db", [-60.0, -10.0, 5.0, 21.14, 40.0, 90.0])
def test_closed_form_pd_matches_series(swerling, snr_db):
    closed = float(single_pulse_pd(snr_db, 1e-6, swerling))
    series = float(pd(min(max(snr_db, -50.0), 80.0), 1e-6, jnp.asarray(1.0), swerling))
    assert closed == pytest.approx(series, abs=1e-13)


def test_gradients_match_central_differences_and_domain_is_refused():
    g = float(jax.grad(lambda p: single_pulse_required_snr_db(p, 1e-6, 1))(0.9))
    h = 1e-6
    fd = (float(single_pulse_required_snr_db(0.9 + h, 1e-6, 1)) - float(single_pulse_required_snr_db(0.9 - h, 1e-6, 1))) / (2 * h)
    assert g == pytest.approx(fd, rel=1e-7)
    with pytest.raises(DomainError):
        single_pulse_required_snr_db.__wrapped__(1e-7, 1e-6, 1)  # pd below pfa
    assert jnp.isnan(single_pulse_required_snr_db(1e-7, 1e-6, 1))  # traced: NaN
