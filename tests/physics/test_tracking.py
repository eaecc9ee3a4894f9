"""Tracking loops: α-β filter relations, the book's lag–noise optimum, servo bandwidth, Kalata.

References used by the assertions:
- Brooker, *Introduction to Sensors for Ranging and Imaging* ("book"): §13.4.1 eqs (13.2)–(13.12)
  (α-β recursion, position transfer function, Benedict–Bordner and critically damped gains);
  §13.6 scripts ``ab_trans.m`` and ``ablag.m`` (B = [α, β−α], A = [1, β+α−2, 1−α]; VRR as the
  sum of squares of the impulse response; lag a·T²(1−α)/β; split-gate σ = ΔR/(2.5√(2 SNR));
  the case a = 10 m/s², f_s = 50 Hz, SNR 10 dB, 3 m gate, α scanned over 0.1:0.01:1);
  §14.7 eqs (14.9)–(14.12) (servo noise bandwidth optimum).
- Independent evaluations: scipy.signal.lfilter/freqz with the book's filter coefficients;
  a plain-Python α-β recursion; scipy Nelder–Mead minimisation of the Benedict–Bordner criterion;
  numpy polynomial roots; scipy.linalg.solve_discrete_are for the steady-state Kalman gain of the
  discrete white-noise-acceleration model; mpmath root finding.
- Published closed forms: Kalata (1984) and Bar-Shalom, Li & Kirubarajan (2001) §6.5.
"""

import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
import scipy.linalg
import scipy.optimize
import scipy.signal

import diffsense  # noqa: F401  (enables float64)
from diffsense.physics import tracking as tr
from diffsense.errors import DomainError
from diffsense.numerics.rootfind import decreasing_root_log

from helpers.function_suite import function_suite

_MEAS = np.sin(0.3 * np.arange(40)) + 0.05 * np.arange(40)


def _book_coefficients(alpha, beta):
    # ab_trans.m / ablag.m: B = [alpha, beta - alpha], A = [1, beta + alpha - 2, 1 - alpha]
    return [alpha, beta - alpha], [1.0, beta + alpha - 2.0, 1.0 - alpha]


def _recursion(alpha, beta, t, z):
    """Plain-Python book eqs (13.2)-(13.5): returns smoothed x, v and predictions."""
    xp = vp = 0.0
    xs, vs, ps = [], [], []
    for m in z:
        r = m - xp
        x = xp + alpha * r
        v = vp + beta / t * r
        xs.append(x)
        vs.append(v)
        ps.append(xp)
        xp, vp = x + t * v, v
    return np.array(xs), np.array(vs), np.array(ps)


def _h_mag(alpha, beta, u, fs):
    return jnp.abs(tr.alpha_beta_position_transfer(alpha, beta, u * fs / 2.0, fs))


def _filter_last(alpha, beta, t):
    x, v = tr.alpha_beta_filter(_MEAS, alpha, beta, t)
    return x[-1] + t * v[-1]


def _pred_lag(a, t, alpha, beta):
    return tr.alpha_beta_acceleration_lag_m(a, t, alpha, beta, predicted=True)


def _kalman_alpha(lam):
    return tr.kalman_steady_state_alpha_beta(lam)[0]


def _kalman_beta(lam):
    return tr.kalman_steady_state_alpha_beta(lam)[1]


_SERVO = [(1e-3, 0.1, 1), (10.0, 1e5, 1), (0.5, 2.0, 0), (-10.0, 60.0, 0), (0.1, 300.0, 1), (10.0, 1e5, 1), (1.0, 2.0, 0)]

# (name, fn, [(lo, hi, log)], [(arg index, bad value)])
SPECS = [
    ("bb_beta", tr.benedict_bordner_beta, [(0.01, 1.0, 0)], [(0, 0.0), (0, 1.5)]),
    ("cd_alpha", tr.critically_damped_alpha, [(1e-4, 1.0, 1)], [(0, 0.0), (0, 1.2)]),
    ("cd_beta", tr.critically_damped_beta, [(1e-4, 0.99, 0)], [(0, 1.0)]),
    ("filter", _filter_last, [(0.05, 1.0, 0), (0.01, 1.0, 0), (1e-3, 10.0, 1)], [(1, -0.1), (2, 0.0)]),
    ("h_mag", _h_mag, [(0.05, 1.0, 0), (0.01, 1.0, 0), (0.0, 1.0, 0), (1.0, 1e4, 1)], [(2, 1.01), (0, 2.0)]),
    ("vrr_x", tr.alpha_beta_position_variance_ratio, [(0.01, 1.0, 0), (1e-3, 1.0, 0)], [(0, 0.0), (1, 3.5)]),
    ("vrr_v", tr.alpha_beta_velocity_variance_ratio_s2, [(0.01, 1.0, 0), (1e-3, 1.0, 0), (1e-3, 10.0, 1)], [(2, 0.0), (1, 0.0)]),
    ("lag", tr.alpha_beta_acceleration_lag_m, [(-100.0, 100.0, 0), (1e-3, 10.0, 1), (0.01, 1.0, 0), (1e-3, 1.0, 1)], [(1, 0.0), (2, 0.0)]),
    ("lag_pred", _pred_lag, [(-100.0, 100.0, 0), (1e-3, 10.0, 1), (0.01, 1.0, 0), (1e-3, 1.0, 1)], [(3, -1.0)]),
    ("split_gate", tr.split_gate_range_noise_m, [(0.01, 1e3, 1), (-20.0, 100.0, 0)], [(1, 150.0), (0, 0.0)]),
    ("ab_cost", tr.alpha_beta_tracking_cost_m2, [(0.01, 1.0, 0), (1e-3, 1.0, 0), (-100.0, 100.0, 0), (1e-3, 1.0, 1), (1e-3, 10.0, 1)], [(4, -1.0), (3, 0.0)]),
    ("bb_cost", tr.benedict_bordner_tracking_cost_m2, [(0.01, 1.0, 0), (1e-3, 100.0, 1), (1.0, 1e4, 1), (1e-3, 10.0, 1)], [(0, 1.1), (3, -1.0)]),
    ("bb_alpha_opt", tr.benedict_bordner_optimal_alpha, [(0.1, 100.0, 1), (1.0, 1e3, 1), (0.01, 10.0, 1)], [(0, 0.0), (2, 0.0)]),
    ("servo_ka", tr.servo_acceleration_error_constant_s2, [(0.01, 100.0, 1)], [(0, 0.0)]),
    ("servo_lag", tr.servo_dynamic_lag_rad, [(-100.0, 100.0, 0), (0.01, 100.0, 1)], [(1, -1.0)]),
    ("servo_noise", tr.servo_angle_noise_variance_rad2, [(0.01, 100.0, 1)] + [_SERVO[i] for i in (0, 1, 2, 3, 6)], [(0, 0.0), (1, 4.0), (4, -30.0)]),
    ("servo_var", tr.servo_angle_error_variance_rad2, [(0.01, 100.0, 1)] + _SERVO, [(0, 0.0), (1, 4.0), (4, -30.0)]),
    ("servo_opt", tr.servo_optimal_bandwidth_hz, _SERVO, [(0, 0.0), (5, 0.0), (6, -1.0)]),
    ("kalata_index", tr.kalata_tracking_index, [(1e-3, 1e3, 1), (1e-3, 10.0, 1), (1e-3, 1e3, 1)], [(0, 0.0), (2, -1.0)]),
    ("kalman_alpha", _kalman_alpha, [(1e-6, 1e6, 1)], [(0, 0.0)]),
    ("kalman_beta", _kalman_beta, [(1e-6, 1e6, 1)], [(0, -1.0)]),
]
globals().update(function_suite(SPECS, jit_rel=1e-12, jit_atol=1e-300, vmap_rtol=1e-12, value_floor=1e-300))


# --------------------------------------------------------------------------------------------
# α-β filter relations
# --------------------------------------------------------------------------------------------


def test_benedict_bordner_gains_minimise_noise_plus_ramp_transient_eq_13_11():
    # Benedict & Bordner (1962): minimise w·(noise VRR) + Σ(transient error to a ramp)² over
    # both gains; for any weight w the optimum lies on β = α²/(2 − α). Both terms are computed
    # numerically with scipy.signal.lfilter and the book's coefficients.
    n = np.arange(400.0)
    impulse = np.zeros(2000)
    impulse[0] = 1.0

    def cost(p, w):
        a, b = p
        if not (0 < a < 2 and 0 < b < 4 - 2 * a):
            return 1e9
        bb, aa = _book_coefficients(a, b)
        vrr = np.sum(scipy.signal.lfilter(bb, aa, impulse) ** 2)
        err = n - scipy.signal.lfilter(bb, aa, n)
        return w * vrr + np.sum(err**2)

    for w in (3.0, 30.0, 300.0):
        res = scipy.optimize.minimize(cost, [0.5, 0.2], args=(w,), method="Nelder-Mead",
                                      options=dict(xatol=1e-11, fatol=1e-13, maxiter=5000))
        a, b = res.x
        assert float(tr.benedict_bordner_beta(a)) == pytest.approx(b, rel=2e-6)


@pytest.mark.parametrize("beta", [1e-3, 0.04, 0.3, 0.81])
def test_critically_damped_gains_give_a_double_pole_eq_13_12(beta):
    # the characteristic polynomial z² + (α + β − 2) z + (1 − α) has a double root 1 − √β
    alpha = float(tr.critically_damped_alpha(beta))
    roots = np.roots([1.0, alpha + beta - 2.0, 1.0 - alpha])
    np.testing.assert_allclose(roots.real, [1 - math.sqrt(beta)] * 2, atol=2e-7)
    assert abs((alpha + beta - 2.0) ** 2 - 4.0 * (1.0 - alpha)) < 1e-14
    assert float(tr.critically_damped_beta(alpha)) == pytest.approx(beta, rel=1e-12)


@pytest.mark.parametrize("alpha, beta", [(0.1, 0.1**2 / 1.9), (0.5, 0.2), (0.9, 0.6), (1.4, 0.9)])
def test_position_transfer_matches_freqz_and_the_recursion_eq_13_10(alpha, beta):
    fs = 1000.0
    f = np.linspace(0.0, fs / 2, 257)
    h = np.asarray(tr.alpha_beta_position_transfer(alpha, beta, f, fs))
    bb, aa = _book_coefficients(alpha, beta)
    _, h_ref = scipy.signal.freqz(bb, aa, worN=f, fs=fs)
    np.testing.assert_allclose(h, h_ref, rtol=1e-12, atol=1e-13)
    # the book's H(z) is the transfer function of the recursion (13.2)-(13.5): DTFT of its
    # impulse response (long enough for the poles to decay)
    imp = np.zeros(4000)
    imp[0] = 1.0
    x, _, _ = _recursion(alpha, beta, 1.0 / fs, imp)
    dtft = np.exp(-2j * np.pi * np.outer(f / fs, np.arange(len(x)))) @ x
    np.testing.assert_allclose(h, dtft, rtol=1e-9, atol=1e-11)
    # and the JAX filter reproduces the plain recursion
    xj, _ = tr.alpha_beta_filter(imp[:300], alpha, beta, 1.0 / fs)
    np.testing.assert_allclose(np.asarray(xj), x[:300], rtol=1e-12, atol=1e-15)


def _grid_pairs():
    out = []
    for a in (0.05, 0.2, 0.5, 0.8, 1.0, 1.5):
        for frac in (0.01, 0.3, 0.7, 0.95):
            out.append((a, frac * (4 - 2 * a)))
    return out


@pytest.mark.parametrize("alpha, beta", _grid_pairs())
def test_variance_reduction_closed_forms_equal_impulse_response_sums(alpha, beta):
    # the book (ablag.m) sums the squared impulse response of H(z); Benedict–Bordner/Kalata give
    # the closed forms. Long impulse responses so the geometric tail is below 1e-15.
    r = max(abs(np.roots([1.0, alpha + beta - 2.0, 1.0 - alpha])))
    n = int(np.ceil(np.log(1e-18) / np.log(r))) + 50
    imp = np.zeros(n)
    imp[0] = 1.0
    bb, aa = _book_coefficients(alpha, beta)
    h = scipy.signal.lfilter(bb, aa, imp)
    assert float(tr.alpha_beta_position_variance_ratio(alpha, beta)) == pytest.approx(np.sum(h**2), rel=1e-11)
    t = 0.37
    _, v, _ = _recursion(alpha, beta, t, imp)
    assert float(tr.alpha_beta_velocity_variance_ratio_s2(alpha, beta, t)) == pytest.approx(np.sum(v**2), rel=1e-11)


@pytest.mark.parametrize("alpha", [0.2, 0.5, 0.9])
def test_acceleration_lag_matches_simulated_steady_state(alpha):
    beta = float(tr.benedict_bordner_beta(alpha))
    a, t = 9.81, 0.02
    n = np.arange(3000)
    truth = 0.5 * a * (n * t) ** 2
    bb, aa = _book_coefficients(alpha, beta)
    smoothed = scipy.signal.lfilter(bb, aa, truth)
    assert float(tr.alpha_beta_acceleration_lag_m(a, t, alpha, beta)) == pytest.approx(truth[-1] - smoothed[-1], rel=1e-8)
    _, _, pred = _recursion(alpha, beta, t, truth)
    assert float(tr.alpha_beta_acceleration_lag_m(a, t, alpha, beta, predicted=True)) == pytest.approx(truth[-1] - pred[-1], rel=1e-8)


def test_unstable_gains_rejected():
    with pytest.raises(DomainError):
        tr.alpha_beta_position_variance_ratio(1.5, 1.2)  # beta >= 4 - 2 alpha
    with pytest.raises(DomainError):
        tr.alpha_beta_position_transfer(0.5, 0.2, 600.0, 1000.0)  # above Nyquist
    with pytest.raises(DomainError):
        tr.alpha_beta_filter(_MEAS, 2.0, 0.1, 0.1)


# --------------------------------------------------------------------------------------------
# The book's range-tracking case (§13.4.1, §13.6 ablag.m)
# --------------------------------------------------------------------------------------------

ACC, FS, SNR_DB, GATE = 10.0, 50.0, 10.0, 3.0


def test_split_gate_noise_book_ablag():
    # sigma = tau / (2.5 sqrt(2 snr)) = 3 / (2.5 sqrt(20)) = 0.26833 m
    sigma = float(tr.split_gate_range_noise_m(GATE, SNR_DB))
    assert sigma == pytest.approx(3.0 / (2.5 * math.sqrt(20.0)), rel=1e-14)
    assert sigma == pytest.approx(0.2683, abs=5e-5)


def test_book_alpha_optimum_matches_grid_mpmath_and_the_books_scan():
    sigma = float(tr.split_gate_range_noise_m(GATE, SNR_DB))
    alpha = float(tr.benedict_bordner_optimal_alpha(ACC, FS, sigma))
    ts = 1.0 / FS

    # 1. dense grid of the cost with the closed-form VRR (spacing 1e-6)
    grid = np.linspace(0.2, 0.4, 200001)
    beta = grid**2 / (2 - grid)
    cost = (ACC * ts**2 * (1 - grid) / beta) ** 2 + sigma**2 * (2 * grid**2 + 2 * beta - 3 * grid * beta) / (grid * (4 - 2 * grid - beta))
    assert alpha == pytest.approx(grid[np.argmin(cost)], abs=1.5e-6)

    # 2. mpmath: root of dJ/dalpha at 30 digits
    mp.mp.dps = 30

    def j(a):
        b = a * a / (2 - a)
        lag = mp.mpf(ACC) * mp.mpf(ts) ** 2 * (1 - a) / b
        vrr = (2 * a * a + 2 * b - 3 * a * b) / (a * (4 - 2 * a - b))
        return lag**2 + mp.mpf(sigma) ** 2 * vrr

    a_mp = mp.findroot(lambda a: mp.diff(j, a), mp.mpf("0.29"))
    assert alpha == pytest.approx(float(a_mp), rel=1e-12)

    # 3. the book's own procedure: alpha = 0.1:0.01:1, VRR = sum of the squared response to an
    #    impulse preceded by 500 zeros (1001 samples), cost lag^2 + sigma_out^2
    sig = np.zeros(1001)
    sig[500] = 1.0
    costs = []
    alphas = np.round(np.arange(0.1, 1.0 + 1e-9, 0.01), 2)
    for a in alphas:
        b = a * a / (2 - a)
        bb, aa = _book_coefficients(a, b)
        vrr = np.sum(scipy.signal.lfilter(bb, aa, sig) ** 2)
        costs.append((ACC * ts**2 * (1 - a) / b) ** 2 + sigma**2 * vrr)
    assert round(alpha, 2) == alphas[int(np.argmin(costs))] == 0.29


@pytest.mark.parametrize("q", [1e-8, 1e-4, 1e-2, 1.0, 1e2, 1e4])
def test_tracking_cost_is_convex_with_interior_optimum(q):
    # J(alpha) with a T^2 / sigma = q: positive second differences on a fine grid of (0, 1],
    # the solver's optimum equals the grid minimum
    alphas = np.linspace(1e-3, 1.0, 20001)
    cost = np.asarray(tr.benedict_bordner_tracking_cost_m2(alphas, q, 1.0, 1.0))
    assert np.all(np.diff(cost, 2) > 0)
    opt = float(tr.benedict_bordner_optimal_alpha(q, 1.0, 1.0))
    assert 0.0 < opt < 1.0
    i = int(np.argmin(cost))
    if 0 < i < len(alphas) - 1:
        assert opt == pytest.approx(alphas[i], abs=1e-4)
    else:  # minimum below the grid or in its last cell
        assert abs(opt - alphas[i]) < 1e-3


def test_book_alpha_optimum_gradient_matches_central_differences():
    sigma = float(tr.split_gate_range_noise_m(GATE, SNR_DB))
    g = jax.grad(tr.benedict_bordner_optimal_alpha, argnums=(0, 1, 2))(ACC, FS, sigma)
    args = [ACC, FS, sigma]
    for i in range(3):
        h = 1e-5 * args[i]
        hi = list(args)
        lo = list(args)
        hi[i] += h
        lo[i] -= h
        fd = (float(tr.benedict_bordner_optimal_alpha(*hi)) - float(tr.benedict_bordner_optimal_alpha(*lo))) / (2 * h)
        assert float(g[i]) == pytest.approx(fd, rel=1e-6)
    # the optimum depends on a T^2 / sigma only (J/sigma^2 is a function of it and alpha)
    assert float(tr.benedict_bordner_optimal_alpha(2 * ACC, FS, 2 * sigma)) == pytest.approx(
        float(tr.benedict_bordner_optimal_alpha(ACC, FS, sigma)), rel=1e-12)


# --------------------------------------------------------------------------------------------
# Servo bandwidth (book 14.7)
# --------------------------------------------------------------------------------------------

SERVO_CASES = [
    # theta_3dB, f_r, beta*tau, SNR dB, a_t, R, k_m
    (0.026, 2000.0, 1.0, 13.0, 50.0, 1000.0, 1.6),
    (0.0175, 10e3, 0.613, 20.0, 300.0, 200.0, 1.6),
    (0.05, 500.0, 1.2, 3.0, 5.0, 2e4, 1.2),
    (0.002, 20e3, 1.0, 40.0, 100.0, 5e4, 1.9),
]


@pytest.mark.parametrize("case", SERVO_CASES)
def test_servo_gradient_solve_lands_on_closed_form_eq_14_12(case):
    beta_o = float(tr.servo_optimal_bandwidth_hz(*case))

    dvar = jax.jit(jax.grad(lambda b: tr.servo_angle_error_variance_rad2(b, *case)))
    d2 = jax.jit(jax.grad(dvar))

    # root of -d sigma^2/d beta_n (decreasing) found without the closed form
    solve = jax.jit(lambda: decreasing_root_log(lambda b: -dvar(b), 1e-3, 1e4).root)
    root = float(solve())
    assert root == pytest.approx(beta_o, rel=1e-9)  # brief: 1e-6; measured <= 3.3e-11
    # and by Newton on the gradient with the Hessian from autodiff, started below the optimum
    # (d sigma^2/d beta_n is concave increasing there, so the iterates rise monotonically)
    b = beta_o / 3.0
    for _ in range(60):
        b = b - float(dvar(b)) / float(d2(b))
    assert b == pytest.approx(beta_o, rel=1e-10)
    # a minimum: the variance rises on both sides
    v0 = float(tr.servo_angle_error_variance_rad2(beta_o, *case))
    assert v0 < float(tr.servo_angle_error_variance_rad2(0.99 * beta_o, *case))
    assert v0 < float(tr.servo_angle_error_variance_rad2(1.01 * beta_o, *case))


def test_servo_lag_term_is_the_squared_dynamic_lag_eq_14_10():
    # (14.11)'s second term is eps_t^2 with eps_t = (a_t/R)/(2.5 beta_n^2) (14.10): at very high
    # SNR the variance reduces to it
    theta, fr, bt, a, r, km = 0.02, 1000.0, 1.0, 30.0, 800.0, 1.6
    for bn in (0.5, 2.0, 8.0):
        var = float(tr.servo_angle_error_variance_rad2(bn, theta, fr, bt, 100.0, a, r, km))
        lag = float(tr.servo_dynamic_lag_rad(a / r, bn))
        noise = theta**2 * bn / (2 * km**2 * fr * bt * 1e10)
        assert var == pytest.approx(lag**2 + noise, rel=1e-14)
        assert lag == pytest.approx((a / r) / float(tr.servo_acceleration_error_constant_s2(bn)), rel=1e-15)


def test_servo_noise_term_is_the_first_term_of_eq_14_11():
    theta, fr, bt, a, r, km, snr_db = 0.02, 1000.0, 1.0, 30.0, 800.0, 1.6, 20.0
    for bn in (0.5, 2.0, 8.0):
        noise = float(tr.servo_angle_noise_variance_rad2(bn, theta, fr, bt, snr_db, km))
        assert noise == pytest.approx(theta**2 * bn / (2 * km**2 * fr * bt * 100.0), rel=1e-14)
        var = float(tr.servo_angle_error_variance_rad2(bn, theta, fr, bt, snr_db, a, r, km))
        assert var - noise == pytest.approx(float(tr.servo_dynamic_lag_rad(a / r, bn)) ** 2, rel=1e-12)


@pytest.mark.parametrize("alpha", [0.05, 0.3, 0.8, 1.0])
def test_general_tracking_cost_is_lag_squared_plus_smoothed_noise(alpha):
    a, fs, sigma = 10.0, 50.0, 0.27
    beta = float(tr.benedict_bordner_beta(alpha))
    cost = float(tr.alpha_beta_tracking_cost_m2(alpha, beta, a, 1.0 / fs, sigma))
    assert cost == pytest.approx(float(tr.benedict_bordner_tracking_cost_m2(alpha, a, fs, sigma)), rel=1e-15)
    lag = float(tr.alpha_beta_acceleration_lag_m(a, 1.0 / fs, alpha, beta))
    vrr = float(tr.alpha_beta_position_variance_ratio(alpha, beta))
    assert cost == pytest.approx(lag**2 + sigma**2 * vrr, rel=1e-15)


# --------------------------------------------------------------------------------------------
# Kalata tracking index and steady-state Kalman gains
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("sigma_a, t, sigma_n", [(0.1, 1.0, 50.0), (5.0, 0.1, 2.0), (30.0, 1.0, 10.0), (2.0, 4.0, 0.5), (1e-3, 0.05, 3.0)])
def test_kalman_alpha_beta_match_riccati_steady_state(sigma_a, t, sigma_n):
    # Discrete white-noise-acceleration model: F = [[1, T], [0, 1]], Q = sigma_a^2 G G^T with
    # G = [T^2/2, T]^T, H = [1, 0], R = sigma_n^2. The steady-state gain K = P H^T / (H P H^T + R)
    # of the predicted covariance P from the discrete algebraic Riccati equation gives
    # alpha = K[0], beta = K[1] T.
    f = np.array([[1.0, t], [0.0, 1.0]])
    g = np.array([[t * t / 2], [t]])
    q = sigma_a**2 * (g @ g.T)
    h = np.array([[1.0, 0.0]])
    p = scipy.linalg.solve_discrete_are(f.T, h.T, q, np.array([[sigma_n**2]]))
    k = (p @ h.T) / (h @ p @ h.T + sigma_n**2)
    lam = float(tr.kalata_tracking_index(sigma_a, t, sigma_n))
    assert lam == pytest.approx(sigma_a * t * t / sigma_n, rel=1e-15)
    alpha, beta = (float(x) for x in tr.kalman_steady_state_alpha_beta(lam))
    assert alpha == pytest.approx(k[0, 0], rel=1e-8)
    assert beta == pytest.approx(k[1, 0] * t, rel=1e-8)


@pytest.mark.parametrize("lam", [1e-8, 1e-3, 0.5, 1.0, 30.0, 1e4, 1e7])
def test_kalman_gains_equal_published_forms_in_mpmath(lam):
    # Bar-Shalom et al. (2001) §6.5: alpha = -(L^2 + 8L - (L + 4) sqrt(L^2 + 8L))/8,
    # beta = (L^2 + 4L - L sqrt(L^2 + 8L))/4; Kalata (1984): beta^2/(1 - alpha) = L^2 and
    # beta = 2(2 - alpha) - 4 sqrt(1 - alpha). 60 digits absorb the cancellation at large L.
    mp.mp.dps = 60
    L = mp.mpf(lam)
    s = mp.sqrt(L * L + 8 * L)
    a_ref = -(L * L + 8 * L - (L + 4) * s) / 8
    b_ref = (L * L + 4 * L - L * s) / 4
    alpha, beta = (float(x) for x in tr.kalman_steady_state_alpha_beta(lam))
    assert alpha == pytest.approx(float(a_ref), rel=1e-14)
    assert beta == pytest.approx(float(b_ref), rel=1e-13)
    assert float(b_ref / mp.sqrt(1 - a_ref)) == pytest.approx(lam, rel=1e-14)
    assert float(2 * (2 - a_ref) - 4 * mp.sqrt(1 - a_ref)) == pytest.approx(float(b_ref), rel=1e-14)
