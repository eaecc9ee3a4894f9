"""Run time against error of the clutter choices: sea-clutter reflectivity, rain and dust volume
reflectivity (families of ``bench_fidelity.py``; helpers in ``_fidelity_support.py``, timing and
comparison as in ``_fidelity_propagation.py``).

* ``sea_clutter`` — the NRL model (Gregers-Hansen & Mital 2012, the default) against the book's
  constant gamma (gamma sin psi with Barton's sea gamma, book §8.12.4 eq (8.29)). Reference: the NRL
  model's equation evaluated in mpmath at 30 digits (with its psi^4 continuation below 0.1 deg, the
  slope at 0.1 deg by mpmath differentiation); spot value: MATLAB's documented ``seareflectivity``
  example of the NRL model. The constant-gamma row's error is a model-choice difference (over the
  constant-gamma model's own domain, grazing 1-60 deg), not a numerical error.
* ``rain_clutter`` — Marshall-Palmer volume reflectivity eta = pi^5 |K|^2 200 R^1.6 1e-18 / lambda^4
  (book eqs (8.37), (8.39)) against a given eta. Reference: the formula in mpmath.
* ``dust_clutter`` — the book's dust backscatter eta = pi^5 |K|^2 1.125e-19 / (lambda^4 V^1.07)
  (eq (8.45)) with the rock-dust |K|^2. Reference: the formula in mpmath with 1.125e-19 rebuilt from
  the book's sandstorm size-distribution sums (2.25e-9 x 2e-24 m^6 / 4e-14 m^3, eqs (8.43)-(8.44))
  and |K|^2 = |(eps - 1)/(eps + 2)|^2 of eps = 5.23 - j0.26 (book §8.14.2).

Run alone: python benchmarks/_fidelity_clutter.py [--quick]
"""

from __future__ import annotations

import math

import _support

_support.require("_fidelity_clutter.py", "mpmath")

import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import mpmath as mp  # noqa: E402
import numpy as np  # noqa: E402

import diffsense  # noqa: E402,F401  (float64)
from _fidelity_propagation import CHECKS, DPS, C_M_S, _choice, _given_choice, _mpf, _timing  # noqa: E402
from _fidelity_support import Family, main_alone, worst  # noqa: E402
from diffsense.numerics.db import db10  # noqa: E402
from diffsense.physics.clutter import dust_volume_reflectivity_m2_m3, rain_volume_reflectivity_m2_m3  # noqa: E402
from diffsense.physics.propagation.dust import ROCK_DUST_K_SQUARED  # noqa: E402
from diffsense.physics.sea_clutter import sea_clutter_sigma0_db  # noqa: E402

# ---------------------------------------------------------------------------------------------
# Sea clutter: the NRL model in mpmath
# ---------------------------------------------------------------------------------------------

#: NRL model coefficients c1..c5 (Gregers-Hansen & Mital 2012), to the digits of the NRL implementation
NRL_C = {"horizontal": ("-73.0", "20.781", "7.351", "25.65", "0.0054"),
         "vertical": ("-50.796", "25.93", "0.7093", "21.588", "0.00211")}
#: published: MATLAB Radar Toolbox documentation of ``seareflectivity`` (NRL model): sea state 2,
#: grazing 10 deg, 30 GHz, horizontal polarization -> nrcs = 2.1555e-04 (printed to 5 digits)
MATLAB_NRL_EXAMPLE = (30.0, 2.0, 10.0, "horizontal", 2.1555e-4)
#: book Table 12.2: sea state -> wind speed (knots), for the Beaufort force of Barton's gamma
TABLE_12_2 = ((0, 0), (0.5, 2), (1, 5), (2, 10), (3, 15), (6, 35))


def mp_nrl_db(f_ghz, sea_state, psi_deg, polarization):
    """The NRL sigma0 (dB) for psi >= 0.1 deg:
    c1 + c2 log10 sin psi + (27.5 + c3 psi) log10 f / (1 + 0.95 psi) + c4 (1 + SS)^(1/(2 + 0.085 psi + 0.033 SS)) + c5 psi^2."""
    c1, c2, c3, c4, c5 = (mp.mpf(c) for c in NRL_C[polarization])
    f, ss, psi = (x if isinstance(x, mp.mpf) else _mpf(x) for x in (f_ghz, sea_state, psi_deg))
    return (c1 + c2 * mp.log10(mp.sin(mp.radians(psi))) + (mp.mpf("27.5") + c3 * psi) * mp.log10(f) / (1 + mp.mpf("0.95") * psi)
            + c4 * (1 + ss) ** (1 / (2 + mp.mpf("0.085") * psi + mp.mpf("0.033") * ss)) + c5 * psi**2)


def mp_nrl_extended_db(f_ghz, sea_state, psi_deg, polarization):
    """NRL above 0.1 deg; below, L(u) = L(0) + A u - (A - s0)(e^u - 1), u = ln(psi/0.1 deg),
    A = 40/ln 10 (sigma0 ~ psi^4), s0 = dL/du at 0.1 deg (Katzin 1957; Barton 2013 §9.2)."""
    with mp.workdps(DPS):
        psi = _mpf(psi_deg)
        psi0 = mp.mpf("0.1")
        if psi >= psi0:
            return mp_nrl_db(f_ghz, sea_state, psi, polarization)
        l0 = mp_nrl_db(f_ghz, sea_state, psi0, polarization)
        s0 = psi0 * mp.diff(lambda p: mp_nrl_db(f_ghz, sea_state, p, polarization), psi0)
        u = mp.log(psi / psi0)
        a = 40 / mp.log(10)
        return l0 + a * u - (a - s0) * mp.expm1(u)


def mp_constant_gamma_db(f_hz, sea_state, psi_deg):
    """gamma sin psi (dB): 10 log10 gamma = 6 K_B - 10 log10 lambda - 64 (book eq (8.29)), K_B = (v/0.836)^(2/3)
    with v the Table 12.2 wind speed (linear in the sea state between rows) in m/s."""
    with mp.workdps(DPS):
        ss = _mpf(sea_state)
        for (s0, v0), (s1, v1) in zip(TABLE_12_2, TABLE_12_2[1:]):
            if s0 <= ss <= s1:
                knots = v0 + (ss - s0) * mp.mpf(v1 - v0) / (s1 - s0)
                break
        kb = (knots * mp.mpf(1852) / 3600 / mp.mpf("0.836")) ** (mp.mpf(2) / 3)
        lam = C_M_S / _mpf(f_hz)
        return 6 * kb - 10 * mp.log10(lam) - 64 + 10 * mp.log10(mp.sin(mp.radians(_mpf(psi_deg))))


def sea_clutter_family(quick: bool) -> Family:
    psis = np.geomspace(1.0, 60.0, 12 if quick else 80)
    freqs = (1.0, 10.0, 35.0) if quick else (0.5, 1.0, 3.0, 5.6, 10.0, 16.0, 35.0)
    states = (1.0, 3.0, 6.0) if quick else (1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
    grid = [(f, s, p) for f in freqs for s in states for p in psis]
    f, ss, psi = (np.array(v, dtype=float) for v in zip(*grid))
    ref = np.array([float(mp_nrl_extended_db(*g, pol)) for pol in ("horizontal", "vertical") for g in grid])
    args = (jnp.asarray(np.radians(psi)), jnp.asarray(f * 1e9), jnp.asarray(ss))
    kw = _timing(quick)

    def nrl(p, fr, s):
        return jnp.concatenate([sea_clutter_sigma0_db(p, fr, s, "nrl", pol) for pol in ("horizontal", "vertical")])

    nrl_c, nrl_v = _choice("nrl", nrl, args, ref=ref, per_element=2, **kw)
    # the continuation below 0.1 deg and the published example
    low = np.geomspace(1e-3, 0.0999, 6 if quick else 40)
    lgrid = [(fg, s, p) for fg in freqs for s in (0.0,) + states for p in low]
    lf, ls, lp = (np.array(v, dtype=float) for v in zip(*lgrid))
    lref = np.array([float(mp_nrl_extended_db(*g, pol)) for pol in ("horizontal", "vertical") for g in lgrid])
    lgot = np.asarray(jax.jit(nrl)(jnp.asarray(np.radians(lp)), jnp.asarray(lf * 1e9), jnp.asarray(ls)))
    ef, es, epsi, epol, enrcs = MATLAB_NRL_EXAMPLE
    example_pkg = 10 ** (float(sea_clutter_sigma0_db(math.radians(epsi), ef * 1e9, es, "nrl", epol)) / 10)
    example_ref = 10 ** (float(mp_nrl_extended_db(ef, es, epsi, epol)) / 10)
    CHECKS.update(nrl_continuation_db=worst(lgot, lref), nrl_matlab_package=example_pkg, nrl_matlab_mpmath=example_ref)
    nrl_c.note = (f"psi^4 continuation, 0.001-0.1 deg (sea states 0-6): worst {worst(lgot, lref):.1e} dB; MATLAB's "
                  f"seareflectivity example (SS 2, 10 deg, 30 GHz, H) 2.1555e-04: package {example_pkg:.4e}, "
                  f"mpmath {example_ref:.4e}")

    def cgamma(p, fr, s):
        return sea_clutter_sigma0_db(p, fr, s, "constant_gamma")

    cg_c, cg_v = _choice("constant_gamma", cgamma, args, **kw)
    both = np.concatenate([cg_v, cg_v])  # polarization-free, against NRL H and V
    cg_c.error_vs_exact, cg_c.error_vs_reference = worst(both, nrl_v), worst(both, ref)
    own = np.array([float(mp_constant_gamma_db(fg * 1e9, s, p)) for fg, s, p in grid])
    diff = both - ref
    CHECKS.update(constant_gamma_own_formula_db=worst(cg_v, own), constant_gamma_vs_nrl_db=(float(diff.min()), float(diff.max())))
    cg_c.note = (f"a model-choice difference (constant gamma omits the NRL model's frequency, polarization and "
                 f"grazing dependence), from {diff.min():+.1f} to {diff.max():+.1f} dB; against its own formula "
                 f"gamma sin psi in mpmath: {worst(cg_v, own):.1e} dB")
    return Family(
        key="sea_clutter",
        title="Sea-clutter reflectivity sigma0",
        domain=(f"grazing angles 1-60 deg ({len(psis)} log-spaced; the constant-gamma model's plateau domain) x "
                f"{', '.join(f'{x:g}' for x in freqs)} GHz x sea states {', '.join(f'{x:g}' for x in states)} x "
                f"H and V (constant gamma is polarization-free: compared with both)"),
        error_unit="dB",
        reference=("the NRL model (V. Gregers-Hansen and R. Mital, NRL/MR/5310--12-9346, 2012; IEEE Trans. AES "
                   "48(4):3512-3524, 2012) evaluated in mpmath at 30 digits, with its psi^4 continuation below 0.1 deg; "
                   "spot value: MATLAB's documented seareflectivity example (2.1555e-04)"),
        exact="nrl",
        default="nrl",
        why_default=("fitted to measured reflectivities (Nathanson's tables, 0.5-35 GHz, sea state 0-6, 0.1-60 deg; "
                     "mean absolute deviation 2.2-2.6 dB) and continued to the grazing angles of a ship radar; "
                     "constant gamma holds in the plateau region only and ignores polarization"),
        choices=[nrl_c, cg_c],
        fast=None,
        fast_bound=(f"bound 0.01 dB: constant gamma is another model ({cg_c.error_vs_reference:.0f} dB from NRL at "
                    f"worst), not an approximation of it"),
    )


# ---------------------------------------------------------------------------------------------
# Volume clutter: rain (Marshall-Palmer) and dust, defining formulas in mpmath
# ---------------------------------------------------------------------------------------------

VOLUME_FREQS_GHZ = (0.3, 1.0, 3.0, 10.0, 35.0, 94.0, 299.792458)


def mp_rain_eta_db(rain_mm_h, wavelength_m, a=200, b="1.6", k_squared="0.93"):
    """10 log10 eta, eta = pi^5 |K|^2 (a R^b 1e-18) / lambda^4 (m^2/m^3), in mpmath."""
    with mp.workdps(DPS):
        eta = mp.pi**5 * mp.mpf(k_squared) * mp.mpf(a) * _mpf(rain_mm_h) ** mp.mpf(b) * mp.mpf("1e-18") / _mpf(wavelength_m) ** 4
        return 10 * mp.log10(eta)


def rain_clutter_family(quick: bool) -> Family:
    rates = np.geomspace(0.1, 500.0, 12 if quick else 200)
    freqs = VOLUME_FREQS_GHZ[1:5] if quick else VOLUME_FREQS_GHZ
    grid = [(r, C_M_S / (fg * 1e9)) for fg in freqs for r in rates]
    r, lam = (np.array(v, dtype=float) for v in zip(*grid))
    ref = np.array([float(mp_rain_eta_db(*g)) for g in grid])
    kw = _timing(quick)
    mp_c, vals = _choice("marshall_palmer", lambda rr, ll: db10(rain_volume_reflectivity_m2_m3(rr, ll)),
                         (jnp.asarray(r), jnp.asarray(lam)), ref=ref, **kw)
    mp_c.note = ("Z = 200 R^1.6 (Marshall & Palmer 1948), K^2 = 0.93 (water), Rayleigh scattering: the formula's own "
                 "error; above ~10 GHz Mie scattering by large drops departs from it by several dB (not measured here)")
    given = _given_choice((jnp.asarray(vals),), **kw)
    given.note = "a given eta: its error is the user's"
    return Family(
        key="rain_clutter",
        title="Rain volume clutter reflectivity eta (10 log10, m^2/m^3)",
        domain=(f"rain rates 0.1-500 mm/h ({len(rates)} log-spaced) x {', '.join(f'{x:g}' for x in freqs)} GHz"),
        error_unit="dB",
        reference="eta = pi^5 K^2 (200 R^1.6 x 1e-18 m^6/m^3) / lambda^4 (book eqs (8.37), (8.39); Marshall & Palmer 1948) in mpmath",
        exact="marshall_palmer",
        default="marshall_palmer",
        why_default="computes eta from the rain rate the path attenuation uses too; 'specified' takes the user's eta",
        choices=[mp_c, given],
        fast=None,
        fast_bound="no other computed choice (a given eta is the user's number)",
    )


def mp_rock_dust_k_squared():
    """|K|^2 = |(eps - 1)/(eps + 2)|^2 for the book's rock dust eps = 5.23 - j0.26, in mpmath."""
    with mp.workdps(DPS):
        eps = mp.mpc("5.23", "-0.26")
        return abs((eps - 1) / (eps + 2)) ** 2


def mp_dust_eta_db(wavelength_m, visibility_m):
    """10 log10 eta, eta = pi^5 |K|^2 (2.25e-9 x 2e-24 / 4e-14) / (lambda^4 V^1.07), in mpmath."""
    with mp.workdps(DPS):
        z_factor = mp.mpf("2.25e-9") * mp.mpf("2e-24") / mp.mpf("4e-14")
        eta = (mp.pi**5 * mp_rock_dust_k_squared() * z_factor
               / (_mpf(wavelength_m) ** 4 * _mpf(visibility_m) ** mp.mpf("1.07")))
        return 10 * mp.log10(eta)


def dust_clutter_family(quick: bool) -> Family:
    vis = np.geomspace(1.0, 1e5, 12 if quick else 200)
    freqs = VOLUME_FREQS_GHZ[1::2] if quick else VOLUME_FREQS_GHZ
    grid = [(C_M_S / (fg * 1e9), v) for fg in freqs for v in vis]
    lam, v = (np.array(x, dtype=float) for x in zip(*grid))
    ref = np.array([float(mp_dust_eta_db(*g)) for g in grid])
    kw = _timing(quick)
    fn = lambda ll, vv: db10(dust_volume_reflectivity_m2_m3(ll, vv, ROCK_DUST_K_SQUARED))  # noqa: E731
    book, _ = _choice("book eq (8.45)", fn, (jnp.asarray(lam), jnp.asarray(v)), ref=ref, **kw)
    CHECKS.update(dust_k_squared_relative=abs(ROCK_DUST_K_SQUARED / float(mp_rock_dust_k_squared()) - 1))
    book.note = (f"rock-dust K^2 = abs((eps - 1)/(eps + 2))^2 {ROCK_DUST_K_SQUARED:.10f} against {float(mp_rock_dust_k_squared()):.10f} (mpmath); "
                 "Rayleigh regime (2 pi a / lambda < 1) assumed, as in the book")
    return Family(
        key="dust_clutter",
        title="Dust volume clutter reflectivity eta (10 log10, m^2/m^3)",
        domain=f"visibility 1 m-100 km ({len(vis)} log-spaced) x {', '.join(f'{x:g}' for x in freqs)} GHz, rock dust",
        error_unit="dB",
        reference=("eta = pi^5 K^2 Z / lambda^4 with Z = 2.25e-9 V^-1.07 (sum P_i D_i^6)/(sum P_i r_i^3), the book's "
                   "sandstorm sums 2e-24 m^6 and 4e-14 m^3 (Brooker §8.14.2 eqs (8.42)-(8.45), after Ghobrial & Sharief "
                   "1987), K^2 = abs((eps - 1)/(eps + 2))^2 of eps = 5.23 - j0.26, all in mpmath"),
        exact="book eq (8.45)",
        default="book eq (8.45)",
        why_default="the package's only dust backscatter model",
        choices=[book],
        fast=None,
        fast_bound="a single choice",
    )


def run(quick: bool) -> list:
    """The clutter families (see the module docstring)."""
    return [sea_clutter_family(quick), rain_clutter_family(quick), dust_clutter_family(quick)]


if __name__ == "__main__":
    main_alone(run, __doc__)
