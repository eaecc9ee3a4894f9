"""High-precision (mpmath) binomial tail and its inverse, for M-of-N references.

``B(p) = P(Bin(N, p) >= M) = I_p(M, N - M + 1)`` (the regularized incomplete beta function,
``mpmath.betainc``), and ``p`` with ``B(p) = target`` by bisection in ``log p`` over
``[1e-40, 1]`` (B increases in p; 200 halvings of a bracket ln 1e40 = 92 wide leave far less
than 1e-30 relative). Independent of the package, which sums the binomial terms in Loader's
saddle-point form and inverts by Newton's method.
"""

from __future__ import annotations

from mpmath import mp

__all__ = ["tail_mp", "level_mp"]


def tail_mp(p, n: int, m: int):
    """P(Bin(n, p) >= m) (mpmath number)."""
    return mp.betainc(m, n - m + 1, 0, p, regularized=True)


def level_mp(target, n: int, m: int, halvings: int = 200):
    """p with P(Bin(n, p) >= m) = ``target`` (mpmath number, at the working precision)."""
    lo, hi = mp.mpf("1e-40"), mp.mpf(1)
    target = mp.mpf(target)
    for _ in range(halvings):
        mid = mp.sqrt(lo * hi)
        lo, hi = (mid, hi) if tail_mp(mid, n, m) < target else (lo, mid)
    return mp.sqrt(lo * hi)
