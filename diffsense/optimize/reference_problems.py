"""Reference problems with published or closed-form optima, for tests and benchmarks.

Hock–Schittkowski problems are stated as in W. Hock & K. Schittkowski, *Test Examples for
Nonlinear Programming Codes*, Lecture Notes in Economics and Mathematical Systems 187,
Springer 1981 ("HS" below), with their published starting points, optimal values and
solutions. Constraints written there as c(x) ≥ 0 appear here as g = −c ≤ 0. Multipliers are
given where a source states them: HS071's are the ones printed by the Ipopt documentation's
HS071 example (Wächter & Biegler, Math. Program. 106 (2006) 25–57; sign of the inequality
multiplier flipped to this package's g ≤ 0 convention); others are derived by hand from the
KKT conditions at the published solution (stated per problem).

Each factory returns a :class:`ReferenceProblem`. The servo-bandwidth problem is Brooker,
*Introduction to Sensors for Ranging and Imaging*, eq. 14.11 with its closed-form optimum
eq. 14.12.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple, Optional

import jax.numpy as jnp
import numpy as np

from diffsense.optimize.problem import Problem


class ReferenceProblem(NamedTuple):
    """A problem with its start and published/analytic solution (None where not stated)."""

    name: str
    problem: Problem
    x0: np.ndarray
    theta: Any
    f_star: float
    x_star: Optional[np.ndarray]
    lam_star: Optional[np.ndarray]
    nu_star: Optional[np.ndarray]
    mu_lower_star: Optional[np.ndarray]
    source: str


def _arr(*v):
    return np.asarray(v, dtype=float)


def hs001() -> ReferenceProblem:
    """HS001: Rosenbrock with the inactive bound x₂ ≥ −1.5; f* = 0 at (1, 1)."""
    def f(x, _):
        return 100.0 * (x[1] - x[0] ** 2) ** 2 + (1.0 - x[0]) ** 2
    prob = Problem(f, _arr(-np.inf, -1.5), _arr(np.inf, np.inf))
    return ReferenceProblem("HS001", prob, _arr(-2.0, 1.0), None, 0.0, _arr(1.0, 1.0), None, None,
                            _arr(0.0, 0.0), "HS problem 1")


def hs002() -> ReferenceProblem:
    """HS002: Rosenbrock with the active bound x₂ ≥ 1.5; f* = 0.0504261879 at (1.224370749, 1.5).

    Bound multiplier by hand: μ₂ = ∂f/∂x₂ = 200 (x₂ − x₁²) at the solution."""
    def f(x, _):
        return 100.0 * (x[1] - x[0] ** 2) ** 2 + (1.0 - x[0]) ** 2
    prob = Problem(f, _arr(-np.inf, 1.5), _arr(np.inf, np.inf))
    x1 = 1.224370749
    return ReferenceProblem("HS002", prob, _arr(-2.0, 1.0), None, 0.0504261879, _arr(x1, 1.5), None, None,
                            _arr(0.0, 200.0 * (1.5 - x1 ** 2)), "HS problem 2")


def hs007() -> ReferenceProblem:
    """HS007: equality constrained; f* = −√3 at (0, √3); ν* = 1/(2√3) by hand
    (∂f/∂x₂ = −1 = −ν·2x₂)."""
    def f(x, _):
        return jnp.log1p(x[0] ** 2) - x[1]

    def h(x, _):
        return jnp.array([(1.0 + x[0] ** 2) ** 2 + x[1] ** 2 - 4.0])
    prob = Problem(f, -np.inf * np.ones(2), np.inf * np.ones(2), equality=h)
    return ReferenceProblem("HS007", prob, _arr(2.0, 2.0), None, -math.sqrt(3.0), _arr(0.0, math.sqrt(3.0)),
                            None, _arr(1.0 / (2.0 * math.sqrt(3.0))), None, "HS problem 7")


def hs021() -> ReferenceProblem:
    """HS021: active lower bound x₁ = 2, inactive linear constraint; f* = −99.96 at (2, 0).

    By hand: μ_lower₁ = ∂f/∂x₁ = 0.02·x₁ = 0.04, λ = 0."""
    def f(x, _):
        return 0.01 * x[0] ** 2 + x[1] ** 2 - 100.0

    def g(x, _):
        return jnp.array([-(10.0 * x[0] - x[1] - 10.0)])
    prob = Problem(f, _arr(2.0, -50.0), _arr(50.0, 50.0), inequality=g)
    return ReferenceProblem("HS021", prob, _arr(-1.0, -1.0), None, -99.96, _arr(2.0, 0.0), _arr(0.0), None,
                            _arr(0.04, 0.0), "HS problem 21")


def hs028() -> ReferenceProblem:
    """HS028: linear equality; f* = 0 at (0.5, −0.5, 0.5), ν* = 0 (∇f = 0 there)."""
    def f(x, _):
        return (x[0] + x[1]) ** 2 + (x[1] + x[2]) ** 2

    def h(x, _):
        return jnp.array([x[0] + 2.0 * x[1] + 3.0 * x[2] - 1.0])
    prob = Problem(f, -np.inf * np.ones(3), np.inf * np.ones(3), equality=h)
    return ReferenceProblem("HS028", prob, _arr(-4.0, 1.0, 1.0), None, 0.0, _arr(0.5, -0.5, 0.5), None, _arr(0.0),
                            None, "HS problem 28")


def hs035() -> ReferenceProblem:
    """HS035: convex QP; f* = 1/9 at (4/3, 7/9, 4/9); λ* = 2/9 by hand (∇f = −(2/9)(1, 1, 2))."""
    def f(x, _):
        x1, x2, x3 = x
        return (9.0 - 8.0 * x1 - 6.0 * x2 - 4.0 * x3 + 2.0 * x1 ** 2 + 2.0 * x2 ** 2 + x3 ** 2
                + 2.0 * x1 * x2 + 2.0 * x1 * x3)

    def g(x, _):
        return jnp.array([x[0] + x[1] + 2.0 * x[2] - 3.0])
    prob = Problem(f, np.zeros(3), np.inf * np.ones(3), inequality=g)
    return ReferenceProblem("HS035", prob, _arr(0.5, 0.5, 0.5), None, 1.0 / 9.0, _arr(4 / 3, 7 / 9, 4 / 9),
                            _arr(2.0 / 9.0), None, np.zeros(3), "HS problem 35")


def hs039() -> ReferenceProblem:
    """HS039: two nonlinear equalities; f* = −1 at (1, 1, 0, 0); ν* = (−1, −1) by hand."""
    def f(x, _):
        return -x[0]

    def h(x, _):
        return jnp.array([x[1] - x[0] ** 3 - x[2] ** 2, x[0] ** 2 - x[1] - x[3] ** 2])
    prob = Problem(f, -np.inf * np.ones(4), np.inf * np.ones(4), equality=h)
    return ReferenceProblem("HS039", prob, _arr(2.0, 2.0, 2.0, 2.0), None, -1.0, _arr(1.0, 1.0, 0.0, 0.0), None,
                            _arr(-1.0, -1.0), None, "HS problem 39")


def hs065() -> ReferenceProblem:
    """HS065: f* = 0.9535288567 at (3.650461821, 3.65046168, 4.6204170507)."""
    def f(x, _):
        return (x[0] - x[1]) ** 2 + (x[0] + x[1] - 10.0) ** 2 / 9.0 + (x[2] - 5.0) ** 2

    def g(x, _):
        return jnp.array([x[0] ** 2 + x[1] ** 2 + x[2] ** 2 - 48.0])
    prob = Problem(f, _arr(-4.5, -4.5, -5.0), _arr(4.5, 4.5, 5.0), inequality=g)
    return ReferenceProblem("HS065", prob, _arr(-5.0, 5.0, 0.0), None, 0.9535288567,
                            _arr(3.650461821, 3.65046168, 4.6204170507), None, None, None, "HS problem 65")


def hs071() -> ReferenceProblem:
    """HS071: f* = 17.0140173 at (1, 4.7429994, 3.8211503, 1.3794082); multipliers from the
    Ipopt HS071 example output: λ = 0.5522937, ν = 0.1614686, μ_lower₁ = 1.087871."""
    def f(x, _):
        return x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2]

    def g(x, _):
        return jnp.array([25.0 - x[0] * x[1] * x[2] * x[3]])

    def h(x, _):
        return jnp.array([jnp.sum(x ** 2) - 40.0])
    prob = Problem(f, np.ones(4), 5.0 * np.ones(4), inequality=g, equality=h)
    return ReferenceProblem("HS071", prob, _arr(1.0, 5.0, 5.0, 1.0), None, 17.0140173,
                            _arr(1.0, 4.7429994, 3.8211503, 1.3794082), _arr(0.5522937), _arr(0.1614686),
                            _arr(1.087871, 0.0, 0.0, 0.0), "HS problem 71; Ipopt HS071 example")


def hs076() -> ReferenceProblem:
    """HS076: f* = −4.681818181 at (3/11, 23/11, 0, 6/11). By hand from the KKT conditions at
    that point: λ = (5/11, 0, 0), μ_lower = (0, 0, 19/11, 0)."""
    def f(x, _):
        x1, x2, x3, x4 = x
        return (x1 ** 2 + 0.5 * x2 ** 2 + x3 ** 2 + 0.5 * x4 ** 2 - x1 * x3 + x3 * x4
                - x1 - 3.0 * x2 + x3 - x4)

    def g(x, _):
        x1, x2, x3, x4 = x
        return jnp.array([x1 + 2.0 * x2 + x3 + x4 - 5.0,
                          3.0 * x1 + x2 + 2.0 * x3 - x4 - 4.0,
                          1.5 - x2 - 4.0 * x3])
    prob = Problem(f, np.zeros(4), np.inf * np.ones(4), inequality=g)
    return ReferenceProblem("HS076", prob, _arr(0.5, 0.5, 0.5, 0.5), None, -4.681818181,
                            _arr(3 / 11, 23 / 11, 0.0, 6 / 11), _arr(5 / 11, 0.0, 0.0), None,
                            _arr(0.0, 0.0, 19 / 11, 0.0), "HS problem 76")


def hs100() -> ReferenceProblem:
    """HS100: 7 variables, 4 nonlinear inequalities; f* = 680.6300573 at
    (2.330499, 1.951372, −0.4775414, 4.365726, −0.6244870, 1.038131, 1.594227)."""
    def f(x, _):
        x1, x2, x3, x4, x5, x6, x7 = x
        return ((x1 - 10.0) ** 2 + 5.0 * (x2 - 12.0) ** 2 + x3 ** 4 + 3.0 * (x4 - 11.0) ** 2
                + 10.0 * x5 ** 6 + 7.0 * x6 ** 2 + x7 ** 4 - 4.0 * x6 * x7 - 10.0 * x6 - 8.0 * x7)

    def g(x, _):
        x1, x2, x3, x4, x5, x6, x7 = x
        return -jnp.array([
            127.0 - 2.0 * x1 ** 2 - 3.0 * x2 ** 4 - x3 - 4.0 * x4 ** 2 - 5.0 * x5,
            282.0 - 7.0 * x1 - 3.0 * x2 - 10.0 * x3 ** 2 - x4 + x5,
            196.0 - 23.0 * x1 - x2 ** 2 - 6.0 * x6 ** 2 + 8.0 * x7,
            -4.0 * x1 ** 2 - x2 ** 2 + 3.0 * x1 * x2 - 2.0 * x3 ** 2 - 5.0 * x6 + 11.0 * x7,
        ])
    prob = Problem(f, -np.inf * np.ones(7), np.inf * np.ones(7), inequality=g)
    return ReferenceProblem("HS100", prob, _arr(1.0, 2.0, 0.0, 4.0, 0.0, 1.0, 1.0), None, 680.6300573,
                            _arr(2.330499, 1.951372, -0.4775414, 4.365726, -0.6244870, 1.038131, 1.594227),
                            None, None, None, "HS problem 100")


# ------------------------------------------------------------------- closed-form problems
def servo_theta(theta3db_rad=0.0175, km=1.6, prf_hz=2000.0, beta_tau=1.0, snr=20.0, accel_m_s2=50.0,
                range_m=1000.0) -> dict:
    """Parameters of the servo-bandwidth problem (SI units; ``snr`` is a power ratio)."""
    return {"theta3db_rad": jnp.asarray(theta3db_rad, float), "km": jnp.asarray(km, float),
            "prf_hz": jnp.asarray(prf_hz, float), "beta_tau": jnp.asarray(beta_tau, float),
            "snr": jnp.asarray(snr, float), "accel_m_s2": jnp.asarray(accel_m_s2, float),
            "range_m": jnp.asarray(range_m, float)}


def servo_error_variance(beta_n_hz, t) -> jnp.ndarray:
    """Brooker eq. 14.11: σθ² = θ3dB² βn / (2 km² fr βτ SNR) + at² / (6.25 R² βn⁴) (rad²)."""
    noise = t["theta3db_rad"] ** 2 * beta_n_hz / (2.0 * t["km"] ** 2 * t["prf_hz"] * t["beta_tau"] * t["snr"])
    lag = t["accel_m_s2"] ** 2 / (6.25 * t["range_m"] ** 2 * beta_n_hz ** 4)
    return noise + lag


def servo_optimum_hz(t) -> jnp.ndarray:
    """Brooker eq. 14.12: βo = (1.28 at² km² fr βτ SNR / (θ3dB² R²))^(1/5) (Hz)."""
    return (1.28 * t["accel_m_s2"] ** 2 * t["km"] ** 2 * t["prf_hz"] * t["beta_tau"] * t["snr"]
            / (t["theta3db_rad"] ** 2 * t["range_m"] ** 2)) ** 0.2


def servo_bandwidth(**theta_kw) -> ReferenceProblem:
    """Minimise eq. 14.11 over βn ∈ [0.01, 1000] Hz (log-scaled); optimum eq. 14.12."""
    t = servo_theta(**theta_kw)
    prob = Problem(lambda x, th: servo_error_variance(x[0], th), 0.01, 1000.0, log_scale=True,
                   names=("servo_bandwidth_hz",))
    bo = float(servo_optimum_hz(t))
    return ReferenceProblem("servo_14.12", prob, _arr(1.0), t, float(servo_error_variance(bo, t)), _arr(bo),
                            None, None, None, "Brooker eqs. 14.11-14.12")


def simplex_projection_solution(a) -> np.ndarray:
    """Euclidean projection of ``a`` onto {x ≥ 0, Σx = 1}: x = max(a − τ, 0) with τ from the
    sorted-threshold rule (Held, Wolfe & Crowder, Math. Program. 6 (1974) 62–88)."""
    a = np.asarray(a, dtype=float)
    u = np.sort(a)[::-1]
    css = np.cumsum(u)
    k = np.arange(1, a.size + 1)
    rho = np.max(np.nonzero(u - (css - 1.0) / k > 0)[0]) + 1
    tau = (css[rho - 1] - 1.0) / rho
    return np.maximum(a - tau, 0.0)


def simplex_projection(a=(0.9, 0.6, -0.2, 0.1)) -> ReferenceProblem:
    """QP: minimise ½‖x − θ‖² s.t. Σx − 1 = 0, x ≥ 0 (θ = a). Closed form above; ν = τ − ...:
    with L = ½‖x − a‖² + ν(Σx − 1) − μᵀx, free components give x − a + ν = 0 so ν = τ, and
    bound multipliers μᵢ = ν − aᵢ = τ − aᵢ where xᵢ = 0."""
    a = np.asarray(a, dtype=float)
    prob = Problem(lambda x, th: 0.5 * jnp.sum((x - th) ** 2), np.zeros(a.size), np.inf * np.ones(a.size),
                   equality=lambda x, th: jnp.array([jnp.sum(x) - 1.0]), scale=1.0)
    xs = simplex_projection_solution(a)
    free = xs > 0
    tau = float(np.mean((a - xs)[free]))
    mu = np.where(free, 0.0, tau - a)
    return ReferenceProblem("simplex_projection", prob, np.full(a.size, 1.0 / a.size), jnp.asarray(a),
                            float(0.5 * np.sum((xs - a) ** 2)), xs, None, _arr(tau), mu,
                            "closed form (Held, Wolfe & Crowder 1974)")


ALL_HS = (hs001, hs002, hs007, hs021, hs028, hs035, hs039, hs065, hs071, hs076, hs100)
