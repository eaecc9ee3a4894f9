"""mpmath references shared by the tests of the exact single-pulse CFAR detectors (OS, GO, SO:
tests/detection/test_cfar_ordered.py and test_cfar_greatest_smallest.py), at the working
precision of the test module (30 digits).

Each detector test supplies its own law of the noise estimate X (Laplace transform, density, law
of the Poisson count J | X ~ Poisson(T X)); what is common is here:

- the single-pulse detection probability for a known threshold t: Swerling 1/2
  ``exp(-t/(1+S))``, Swerling 3/4 ``(1 + t (S/2)/(1+S/2)^2) exp(-t/(1+S/2))``, Swerling 0 the
  Marcum Q function as the Poisson mixture ``sum_K Pois(K; S) Q(1+K, t)``;
- ``E_X[Pd_fixed(T X)]`` by mpmath.quad over a given density (the definition of Pd);
- the Swerling 0 detection probability as the exact discrete series ``P(J <= K) = sum_j P(J = j)
  P(K >= j)``, ``K ~ Poisson(S)`` (because ``Pd_fixed(t) = P(Poisson(t) <= K)``);
- roots (bisection, then mpmath's Anderson-Bjorck method to ~1e-28) of multipliers and known-noise
  requirements, and the distance of a computed SNR from the root of a reference Pd (one Newton
  step: residual over slope, exact to second order).
"""

import mpmath as mp


def snr_linear(snr_db):
    return mp.mpf(10) ** (mp.mpf(snr_db) / 10)


def root_decreasing(f, lo, hi):
    """Root of a decreasing f in [lo, hi]: bisection to 1e-8, then Anderson-Bjorck."""
    lo, hi = mp.mpf(lo), mp.mpf(hi)
    while hi - lo > mp.mpf("1e-8"):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if f(mid) > 0 else (lo, mid)
    # Anderson-Bjorck: a bracketing method, so no step leaves [lo, hi]
    return mp.findroot(f, (lo, hi), solver="anderson", tol=mp.mpf(10) ** (-2 * mp.mp.dps + 4))


def multiplier(log_laplace, pfa, log_lo, log_hi):
    """T with log L(T) = log pfa, searched in log T between log_lo and log_hi."""
    target = mp.log(mp.mpf(pfa))
    return mp.exp(root_decreasing(lambda s: log_laplace(mp.exp(s)) - target, log_lo, log_hi))


def pd_fixed(snr, t, swerling):
    """Single-pulse Pd for a threshold t on the unit-mean noise scale (known noise)."""
    if swerling in (1, 2):
        return mp.exp(-t / (1 + snr))
    if swerling in (3, 4):
        return (1 + t * (snr / 2) / (1 + snr / 2) ** 2) * mp.exp(-t / (1 + snr / 2))
    # Marcum Q: sum_K Pois(K; S) Q(1 + K, t), Q(1 + K, t) = Q(K, t) + t^K e^-t / K!
    # the terms fall faster than geometrically (ratio S/K < 1/2) beyond K = 2S + 10: stop there
    # once they are below 1e-(dps+5)
    total, q, pois_t, p_k, kk = mp.mpf(0), mp.exp(-t), mp.exp(-t), mp.exp(-snr), 0
    small = mp.mpf(10) ** (-mp.mp.dps - 5)
    while kk <= 2 * snr + 10 or p_k > small:
        total += p_k * q
        kk += 1
        pois_t *= t / kk
        q += pois_t
        p_k *= snr / kk
    return total


def pd_quad(density, snr_db, t, swerling, points):
    """mpmath.quad of the definition E_X[Pd_fixed(T X)] over the density of X."""
    snr = snr_linear(snr_db)
    return mp.quad(lambda x: density(x) * pd_fixed(snr, t * x, swerling), points)


def count_terms(snr):
    """Terms of the series in j: P(K >= j) < 1e-40 beyond, K ~ Poisson(snr)."""
    return int(snr + 15 * mp.sqrt(snr + 1) + 80)


def pd_steady_series(pmf, snr_db):
    """Swerling 0: sum_j P(J = j) P(K >= j), K ~ Poisson(S), over the given law of J."""
    snr = snr_linear(snr_db)
    j_max = min(len(pmf) - 1, count_terms(snr))
    assert j_max == count_terms(snr), "law of J computed to too few terms for this SNR"
    total, p_k, below = mp.mpf(0), mp.exp(-snr), mp.mpf(0)
    for j in range(j_max + 1):
        total += pmf[j] * (1 - below)  # P(K >= j) = 1 - P(K < j)
        below += p_k
        p_k *= snr / (j + 1)
    return total


def newton_distance_db(pd_ref, x_db, pd_target):
    """Distance (dB) of x_db from the root of pd_ref(x) = pd_target: residual over slope."""
    x = mp.mpf(x_db)
    h = mp.mpf("1e-8")
    slope = (pd_ref(x + h) - pd_ref(x - h)) / (2 * h)
    return float((pd_ref(x) - mp.mpf(pd_target)) / slope)


def known_noise_db(pd, pfa, swerling):
    """Known-noise single-pulse requirement (dB): root of Pd_fixed(S, -ln Pfa) = pd."""
    t = -mp.log(mp.mpf(pfa))
    if swerling in (1, 2):
        return float(10 * mp.log10(t / -mp.log(mp.mpf(pd)) - 1))
    return float(root_decreasing(lambda x: mp.mpf(pd) - pd_fixed(snr_linear(x), t, swerling), -20, 40))
