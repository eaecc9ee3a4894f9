"""Run time against error of the propagation choices: gaseous attenuation, rain, cloud/fog and sea
multipath (families of ``bench_fidelity.py``; helpers in ``_fidelity_support.py``).

Families and their independent references (all evaluated here with mpmath at 30 digits, none of
them calls the code under test):

* ``gas_attenuation`` — ITU-R P.676-12 Annex 1 line-by-line (the package's exact choice) against
  the P.676-10 Annex 2 closed forms and a given ("specified") dB/km. Reference: the Annex 1
  equations (1)-(9) evaluated in mpmath from the line tables (Tables 1 and 2, as transcribed in
  :mod:`diffsense.physics.propagation.gas`); checked itself against the ITU-R SG3 validation
  examples for P.676-12.
* ``rain_attenuation`` — ITU-R P.838-3 against a given dB/km. Reference: eqs. (1)-(5) in mpmath
  with Tables 1-4 transcribed here a second time; spot values: the ITU-R SG3 validation examples
  for P.838-3 (k, alpha, gamma_R).
* ``cloud_attenuation`` — ITU-R P.840-7 (the package's only choice). Reference: the double-Debye
  permittivity and Rayleigh absorption, eqs. (2)-(10), in mpmath; spot value: the ratio of the
  ITU-R SG3 validation examples for P.840-8 at 29 and 14.25 GHz.
* ``multipath_earth`` — two-ray sea multipath over the curved 4/3 earth (Blake's cubic for the
  specular point) against the flat-earth geometry. Reference: the exact specular point on the
  4/3-earth sphere found by root-finding (equal grazing angles of the incident and reflected rays)
  to 30 digits, the path difference, grazing angle and divergence factor from it, the Fresnel
  coefficient of sea water (Klein & Swift permittivity, evaluated in mpmath) and the two-ray sum.
* ``multipath_roughness`` — rough-sea specular factor: Miller-Brown-Vegh (default), Ament, and a
  smooth sea. Reference: the same exact geometry with the Miller-Brown-Vegh factor
  exp(-2 g^2) I0(2 g^2) in mpmath. Ament and smooth sea against it are model-choice differences.

Run alone: python benchmarks/_fidelity_propagation.py [--quick]
"""

from __future__ import annotations

import functools
import math

import _support

_support.require("_fidelity_propagation.py", "mpmath")

import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import mpmath as mp  # noqa: E402
import numpy as np  # noqa: E402

import diffsense  # noqa: E402,F401  (float64)
from _fidelity_support import Choice, Family, hlo_ops, main_alone, time_per_eval, worst  # noqa: E402
from diffsense.physics.propagation import (  # noqa: E402
    cloud_attenuation_db_per_km,
    gas_attenuation_approx_db_per_km,
    gas_attenuation_db_per_km,
    propagation_factor_db,
    rain_attenuation_db_per_km,
)
from diffsense.physics.propagation.gas import OXYGEN_LINES, WATER_VAPOUR_LINES  # noqa: E402

DPS = 30
C_M_S = 299792458
#: a row whose number is the user's (a given dB/km): its error is the user's, not the package's
USER_NOTE = "a given number: its error is the user's"
#: the figures behind the notes of the last ``run()``, by name (for the tests)
CHECKS: dict = {}


def _timing(quick):
    """Timing settings: repeats of the median, and the smallest batch a timed call holds."""
    return dict(repeats=3, min_batch=4096) if quick else dict(repeats=7, min_batch=32768)


def _tiled(args, min_batch):
    """The grid arguments repeated until a call holds at least ``min_batch`` elements, so that the time
    per evaluation is not the dispatch overhead of a small grid."""
    n = int(np.size(np.asarray(args[0])))
    reps = max(1, -(-min_batch // n))
    return tuple(jnp.tile(jnp.asarray(a), reps) for a in args), n * reps


def _choice(name, fn, args, *, exact=None, ref=None, relative=False, mask=None, repeats=5, note="", per_element=1,
            min_batch=4096):
    """Time, size and compare one choice; returns the Choice and its values on the grid. ``fn`` is
    called once on the grid repeated to ``min_batch`` elements (one compilation serves the values, the
    timing and the HLO count); ``per_element``: evaluations per grid element (2 when ``fn`` returns both
    polarizations, stacked)."""
    jf = jax.jit(fn)
    n = int(np.size(np.asarray(args[0])))
    targs, big = _tiled(args, min_batch)
    vals = np.asarray(jf(*targs)).reshape(per_element, big)[:, :n].ravel()
    secs = time_per_eval(jf, *targs, batch=big * per_element, repeats=repeats)
    ops = hlo_ops(fn, *targs)
    sel = (lambda a: np.asarray(a)[mask]) if mask is not None else np.asarray
    e_exact = 0.0 if exact is None else worst(sel(vals), sel(exact), relative)
    e_ref = float("nan") if ref is None else worst(sel(vals), sel(ref), relative)
    return Choice(name, secs, ops, e_exact, e_ref, note), vals


def _given_choice(args, **kw):
    """The 'specified' row: the given dB/km passes through (time of the pass-through, error n/a)."""
    fn = lambda alpha: alpha * 1.0  # noqa: E731  (as the chain's given-attenuation parts)
    c, _ = _choice("specified", fn, args, note=USER_NOTE, **kw)
    c.error_vs_exact = float("nan")
    return c


# ---------------------------------------------------------------------------------------------
# Gaseous attenuation: P.676-12 Annex 1 in mpmath
# ---------------------------------------------------------------------------------------------

# published: ITU-R SG3 validation examples for P.676-12 (CG-3M3J-13-ValEx-Rev5, sheet "P676-12
# SpAtt"): f (GHz), gamma_o, gamma_w (dB/km) at a dry-air pressure of 1013.25 hPa, 288.15 K, 7.5 g/m^3
P676_12_VALEX = [(1, 0.005388658, 5.09e-05), (10, 0.008224417, 0.005974125), (22, 0.013130223, 0.174207033),
                 (60, 14.6234748, 0.154841841), (118, 1.134866202, 0.605921953), (183, 0.012733909, 27.66500831),
                 (250, 0.018753887, 3.077989748)]


def _mpf(x):
    """The float x as an mpmath number (its shortest decimal, i.e. the digits as typed)."""
    return mp.mpf(repr(float(x)))


def _mp_rows(table):
    return [[_mpf(x) for x in row] for row in table]


def mp_gas_db_per_km(freqs_ghz, p_total_hpa, temperature_k, rho_g_m3):
    """[(gamma_o, gamma_w)] in dB/km at each frequency (GHz) of one atmosphere: ITU-R P.676-12 Annex 1
    eqs. (1)-(9) evaluated in mpmath (line strengths and widths once per atmosphere)."""
    m = mp.mpf
    with mp.workdps(DPS):
        t, rho = _mpf(temperature_k), _mpf(rho_g_m3)
        theta = 300 / t
        e = rho * t / m("216.7")
        p = _mpf(p_total_hpa) - e
        oxygen = []
        for fi, a1, a2, a3, a4, a5, a6 in _mp_rows(OXYGEN_LINES):  # eqs. (3), (6a), (7)
            s = a1 * m("1e-7") * p * theta**3 * mp.exp(a2 * (1 - theta))
            df = a3 * m("1e-4") * (p * theta ** (m("0.8") - a4) + m("1.1") * e * theta)
            df = mp.sqrt(df**2 + m("2.25e-6"))
            oxygen.append((fi, s, df, (a5 + a6 * theta) * m("1e-4") * (p + e) * theta ** m("0.8")))
        water = []
        for fi, b1, b2, b3, b4, b5, b6 in _mp_rows(WATER_VAPOUR_LINES):  # eqs. (3), (6b)
            s = b1 * m("0.1") * e * theta ** m("3.5") * mp.exp(b2 * (1 - theta))
            df = b3 * m("1e-4") * (p * theta**b4 + b5 * e * theta**b6)
            water.append((fi, s, m("0.535") * df + mp.sqrt(m("0.217") * df**2 + m("2.1316e-12") * fi**2 / theta), 0))
        d = m("5.6e-4") * (p + e) * theta ** m("0.8")  # eq. (9)
        nitrogen = m("1.4e-12") * p * theta ** m("1.5")
        out = []
        for fg in freqs_ghz:
            f = _mpf(fg)

            def line_sum(lines):  # eqs. (2), (5)
                return sum(s * f / fi * ((df - dl * (fi - f)) / ((fi - f) ** 2 + df**2)
                                         + (df - dl * (fi + f)) / ((fi + f) ** 2 + df**2)) for fi, s, df, dl in lines)

            n_d = f * p * theta**2 * (m("6.14e-5") / (d * (1 + (f / d) ** 2)) + nitrogen / (1 + m("1.9e-5") * f ** m("1.5")))
            k = m("0.1820") * f  # eq. (1)
            out.append((k * (line_sum(oxygen) + n_d), k * line_sum(water)))
        return out


GAS_STATES = [(1013.25, 288.15, 7.5), (800.0, 273.15, 5.0), (1013.25, 303.15, 20.0), (1013.25, 288.15, 0.0)]


def gas_family(quick: bool) -> Family:
    freqs = np.geomspace(1.0, 350.0, 24) if quick else np.arange(1.0, 350.0 + 1e-9, 0.5)
    states = GAS_STATES[:2] if quick else GAS_STATES
    f, p, t, rho = (np.array(v, dtype=float) for v in zip(*[(fg, *s) for s in states for fg in freqs]))
    ref = np.array([float(o + w) for st in states for o, w in mp_gas_db_per_km(freqs, *st)])
    args = tuple(jnp.asarray(a) for a in (f * 1e9, p, t, rho))
    kw = _timing(quick)
    exact, ex_vals = _choice("itu_p676", gas_attenuation_db_per_km, args, ref=ref,
                             **kw)
    rel_ref = worst(ex_vals, ref, relative=True)
    valex = _valex_check()
    CHECKS.update(gas_exact_relative=rel_ref, gas_valex_package=valex[0], gas_valex_mpmath=valex[1])
    exact.note = (f"Annex 1 line by line (44 O2 + 35 H2O lines); relative {rel_ref:.1e} against the mpmath line sum; ITU-R SG3 validation examples "
                  f"(P.676-12, 7 frequencies 1-250 GHz): {valex[0]:.1e} relative (package), {valex[1]:.1e} (mpmath)")
    approx, ap_vals = _choice("itu_p676_approx", gas_attenuation_approx_db_per_km, args,
                              exact=ex_vals, ref=ref, **kw)
    below40 = f <= 40.0
    CHECKS.update(gas_approx_worst_relative=worst(ap_vals, ref, relative=True),
                  gas_approx_mean_relative=float(np.mean(np.abs(ap_vals / ref - 1))),
                  gas_approx_worst_below_40ghz=worst(ap_vals[below40], ref[below40]))
    approx.note = (f"P.676-10 Annex 2 closed forms; relative: worst {worst(ap_vals, ref, relative=True):.3f}, mean "
                   f"{float(np.mean(np.abs(ap_vals / ref - 1))):.3f} (the Recommendation: about 0.15 on average); "
                   f"1-40 GHz: worst {worst(ap_vals[below40], ref[below40]):.3g} dB/km")
    given = _given_choice((jnp.asarray(ex_vals),), **kw)
    state_text = "; ".join(f"{s[0]:g} hPa, {s[1]:g} K, {s[2]:g} g/m^3" for s in states)
    return Family(
        key="gas_attenuation",
        title="Gaseous attenuation (one-way specific attenuation)",
        domain=(f"{len(freqs)} frequencies 1-350 GHz ({'log-spaced' if quick else 'every 0.5 GHz'}, the closed forms' "
                f"range) at each of {len(states)} atmospheres (total pressure, temperature, water vapour): {state_text}"),
        error_unit="dB/km",
        reference=("ITU-R P.676-12 (08/2019) Annex 1 eqs. (1)-(9) evaluated in mpmath at 30 digits from the "
                   "Recommendation's Tables 1 and 2 (the line sum, not a call of the package); the package's line "
                   "sum also checked against the ITU-R SG3 validation examples for P.676-12 (CG-3M3J-13-ValEx-Rev5)"),
        exact="itu_p676",
        default="itu_p676",
        why_default=("the Recommendation's general method, valid 1-1000 GHz and at any pressure, temperature and "
                     "humidity; the closed forms of P.676-10 Annex 2 cover 1-350 GHz and differ from it by up to "
                     "12 % at the standard atmosphere"),
        choices=[exact, approx, given],
        fast=None,
        fast_bound=(f"bound 0.01 dB/km of one-way specific attenuation (0.02 dB of two-way loss per km of range): "
                    f"the closed forms miss it (worst {approx.error_vs_reference:.2g} dB/km), so fast keeps the line sum"),
    )


def _valex_check():
    """Worst relative deviation from the P.676-12 validation examples: (package, mpmath reference).
    The examples carry 7-10 digits except gamma_w at 1 GHz (3 digits): the sum is compared."""
    p_total = 1013.25 + 7.5 * 288.15 / 216.7
    freqs = np.array([row[0] for row in P676_12_VALEX], dtype=float)
    want = np.array([row[1] + row[2] for row in P676_12_VALEX])
    pkg = np.asarray(jax.jit(gas_attenuation_db_per_km)(jnp.asarray(freqs * 1e9), p_total, 288.15, 7.5))
    ref = np.array([float(o + w) for o, w in mp_gas_db_per_km(freqs, p_total, 288.15, 7.5)])
    return float(np.max(np.abs(pkg / want - 1))), float(np.max(np.abs(ref / want - 1)))


# ---------------------------------------------------------------------------------------------
# Rain: ITU-R P.838-3 in mpmath
# ---------------------------------------------------------------------------------------------

# Rec. ITU-R P.838-3 (03/2005), Tables 1-4, column by column: a_j, b_j, c_j (j = 1..4 or 1..5), m, c
P838_TABLES = {
    "k_H": ((-5.33980, -0.35351, -0.23789, -0.94158), (-0.10008, 1.26970, 0.86036, 0.64552),
            (1.13098, 0.45400, 0.15354, 0.16817), -0.18961, 0.71147),
    "k_V": ((-3.80595, -3.44965, -0.39902, 0.50167), (0.56934, -0.22911, 0.73042, 1.07319),
            (0.81061, 0.51059, 0.11899, 0.27195), -0.16398, 0.63297),
    "alpha_H": ((-0.14318, 0.29591, 0.32177, -5.37610, 16.1721), (1.82442, 0.77564, 0.63773, -0.96230, -3.29980),
                (-0.55187, 0.19822, 0.13164, 1.47828, 3.43990), 0.67849, -1.95537),
    "alpha_V": ((-0.07771, 0.56727, -0.20238, -48.2991, 48.5833), (2.33840, 0.95545, 1.14520, 0.791669, 0.791459),
                (-0.76284, 0.54039, 0.26809, 0.116226, 0.116479), -0.053739, 0.83433),
}
# published: ITU-R SG3 validation examples for P.838-3 (CG-3M3J-13-ValEx-Rev5.1; the distinct rows as
# extracted in the public ITU-Rpy test data): elevation (deg), f (GHz), R (mm/h), tilt (deg), k, alpha, gamma_R
P838_VALEX = [
    (31.07699124, 14.25, 26.48052, 0, 0.03975488, 1.12418043, 1.58130839),
    (40.232036, 14.25, 33.936232, 0, 0.04007624, 1.11804138, 2.06173213),
    (46.35969261, 14.25, 27.13586832, 0, 0.04030344, 1.11376017, 1.5920842),
    (31.07699124, 29, 26.48052, 0, 0.22106804, 0.95320005, 5.02180189),
    (40.232036, 29, 33.936232, 0, 0.22031404, 0.9504446, 6.27846024),
    (46.35969261, 29, 27.13586832, 0, 0.21978097, 0.9484851, 5.03135479),
    (22.27833468, 14.25, 50.639304, 0, 0.03949319, 1.12925336, 3.32139638),
    (52.67898486, 14.25, 78.2994993, 0, 0.04053522, 1.10944215, 5.11503463),
    (22.27833468, 29, 50.639304, 0, 0.22168203, 0.95543001, 9.42430244),
    (52.67898486, 29, 78.2994993, 0, 0.21923716, 0.9464763, 13.59290086),
    (48.24117054, 14.25, 63.62668149, 90, 0.04226474, 1.07871664, 3.72901264),
    (85.80459566, 14.25, 99.13558978, 90, 0.04133039, 1.09499629, 6.34064598),
    (20.14335809, 14.25, 42.91007183, 90, 0.04319835, 1.0631531, 2.35032323),
    (48.24117054, 29, 63.62668149, 90, 0.21517927, 0.93116621, 10.28699163),
    (85.80459566, 29, 99.13558978, 90, 0.21737148, 0.93950825, 16.3183686),
    (20.14335809, 29, 42.91007183, 90, 0.21298877, 0.92265917, 6.83364556),
]


@functools.lru_cache(maxsize=None)
def _mp_p838_fits(f_ghz):
    """(k_H, k_V, alpha_H, alpha_V) of ITU-R P.838-3 eqs. (2)-(3) in mpmath."""
    with mp.workdps(DPS):
        x = mp.log10(_mpf(f_ghz))

        def fit(name):
            a, b, c, m, cc = P838_TABLES[name]
            val = sum(_mpf(aj) * mp.exp(-((x - _mpf(bj)) / _mpf(cj)) ** 2) for aj, bj, cj in zip(a, b, c))
            return val + _mpf(m) * x + _mpf(cc)

        return 10 ** fit("k_H"), 10 ** fit("k_V"), fit("alpha_H"), fit("alpha_V")


def mp_rain(f_ghz, rain_mm_h, tilt_deg, elevation_deg):
    """(k, alpha, gamma_R) of ITU-R P.838-3 eqs. (1)-(5) in mpmath."""
    k_h, k_v, a_h, a_v = _mp_p838_fits(float(f_ghz))
    with mp.workdps(DPS):
        mix = mp.cos(mp.radians(_mpf(elevation_deg))) ** 2 * mp.cos(2 * mp.radians(_mpf(tilt_deg)))
        k = (k_h + k_v + (k_h - k_v) * mix) / 2
        alpha = (k_h * a_h + k_v * a_v + (k_h * a_h - k_v * a_v) * mix) / (2 * k)
        return k, alpha, k * _mpf(rain_mm_h) ** alpha


def _p838_valex():
    """Worst relative deviation of (package gamma_R; mpmath k, alpha, gamma_R) from the P.838-3 validation examples."""
    el, fg, r, tau, k, alpha, gam = (np.array(v, dtype=float) for v in zip(*P838_VALEX))
    got = np.asarray(jax.jit(rain_attenuation_db_per_km)(jnp.asarray(fg * 1e9), jnp.asarray(r), jnp.asarray(tau),
                                                         jnp.asarray(el)))
    ref = np.array([[float(x) for x in mp_rain(*row)] for row in zip(fg, r, tau, el)])
    return (float(np.max(np.abs(got / gam - 1))),
            float(np.max(np.abs(ref / np.stack([k, alpha, gam], axis=1) - 1))))


def rain_family(quick: bool) -> Family:
    freqs = np.geomspace(1.0, 1000.0, 16 if quick else 250)
    rates = (1.0, 25.0, 150.0) if quick else (0.5, 5.0, 25.0, 100.0, 300.0)
    tilts = (0.0, 45.0, 90.0)
    elevations = (0.0, 45.0) if quick else (0.0, 30.0, 60.0, 90.0)
    grid = [(fg, r, tau, el) for fg in freqs for r in rates for tau in tilts for el in elevations]
    f, r, tau, el = (np.array(v, dtype=float) for v in zip(*grid))
    ref = np.array([float(mp_rain(*g)[2]) for g in grid])
    args = tuple(jnp.asarray(a) for a in (f * 1e9, r, tau, el))
    kw = _timing(quick)
    fn = lambda f_hz, rate, tilt, elev: rain_attenuation_db_per_km(f_hz, rate, tilt, elev)  # noqa: E731
    itu, vals = _choice("itu_p838", fn, args, ref=ref, relative=True, **kw)
    pkg, mpv = _p838_valex()
    CHECKS.update(rain_valex_package=pkg, rain_valex_mpmath=mpv)
    itu.note = (f"ITU-R SG3 validation examples (16 rows, 14.25 and 29 GHz): gamma_R within {pkg:.1e} relative "
                f"(package), k, alpha, gamma_R within {mpv:.1e} (mpmath)")
    given = _given_choice((jnp.asarray(vals),), **kw)
    return Family(
        key="rain_attenuation",
        title="Rain attenuation (one-way specific attenuation)",
        domain=(f"{len(freqs)} log-spaced frequencies 1-1000 GHz x rain rates {', '.join(f'{x:g}' for x in rates)} mm/h x "
                f"polarization tilt 0 (H), 45 (circular), 90 (V) deg x path elevation "
                f"{', '.join(f'{x:g}' for x in elevations)} deg"),
        error_unit="relative",
        reference=("ITU-R P.838-3 (03/2005) eqs. (1)-(5) evaluated in mpmath at 30 digits with Tables 1-4 transcribed "
                   "a second time; spot values: the ITU-R SG3 validation examples for P.838-3 (CG-3M3J-13-ValEx-Rev5.1)"),
        exact="itu_p838",
        default="itu_p838",
        why_default="the Recommendation's regression, 1-1000 GHz, any rain rate, polarization and elevation",
        choices=[itu, given],
        fast=None,
        fast_bound="no other computed choice (a given dB/km is the user's number)",
    )


# ---------------------------------------------------------------------------------------------
# Cloud / fog: ITU-R P.840-7 in mpmath
# ---------------------------------------------------------------------------------------------

# published: ITU-R SG3 validation examples for P.840-8 (CG-3M3J-13-ValEx-Rev5.1): the same path's cloud
# attenuation at 29 and 14.25 GHz (K_l at 273.15 K), 1.77246907 dB and 0.45516982 dB
P840_VALEX_RATIO = 1.77246907 / 0.45516982


def mp_cloud_coefficient(f_ghz, temperature_k):
    """K_l ((dB/km)/(g/m^3)) of ITU-R P.840-7 eqs. (2)-(10) in mpmath."""
    with mp.workdps(DPS):
        f = _mpf(f_ghz)
        theta = 300 / _mpf(temperature_k)
        e0 = mp.mpf("77.66") + mp.mpf("103.3") * (theta - 1)
        e1 = mp.mpf("0.0671") * e0
        e2 = mp.mpf("3.52")
        fp = mp.mpf("20.20") - 146 * (theta - 1) + 316 * (theta - 1) ** 2
        fs = mp.mpf("39.8") * fp
        eps2 = f * (e0 - e1) / (fp * (1 + (f / fp) ** 2)) + f * (e1 - e2) / (fs * (1 + (f / fs) ** 2))
        eps1 = (e0 - e1) / (1 + (f / fp) ** 2) + (e1 - e2) / (1 + (f / fs) ** 2) + e2
        eta = (2 + eps1) / eps2
        return mp.mpf("0.819") * f / (eps2 * (1 + eta**2))


def cloud_family(quick: bool) -> Family:
    freqs = np.geomspace(1.0, 1000.0, 24 if quick else 400)
    temps = (253.15, 273.15, 303.15) if quick else (233.15, 253.15, 273.15, 288.15, 303.15, 323.15)
    grid = [(fg, t) for fg in freqs for t in temps]
    f, t = (np.array(v, dtype=float) for v in zip(*grid))
    m = np.full_like(f, 1.0)
    ref = np.array([float(mp_cloud_coefficient(*g)) for g in grid])
    args = tuple(jnp.asarray(a) for a in (f * 1e9, m, t))
    kw = _timing(quick)
    itu, _ = _choice("itu_p840", cloud_attenuation_db_per_km, args, ref=ref, relative=True, **kw)
    k29, k14 = np.asarray(jax.jit(cloud_attenuation_db_per_km)(jnp.array([29e9, 14.25e9]), 1.0, 273.15))
    ratio = float(k29 / k14)
    CHECKS.update(cloud_valex_ratio=ratio)
    itu.note = (f"ITU-R SG3 validation examples for P.840-8: K_l(29 GHz)/K_l(14.25 GHz) at 273.15 K "
                f"{ratio:.7f} against {P840_VALEX_RATIO:.7f} ({abs(ratio / P840_VALEX_RATIO - 1):.1e} relative)")
    return Family(
        key="cloud_attenuation",
        title="Cloud and fog attenuation (specific attenuation per g/m^3 of liquid water)",
        domain=(f"{len(freqs)} log-spaced frequencies 1-1000 GHz x liquid-water temperature "
                f"{', '.join(f'{x:g}' for x in temps)} K, M = 1 g/m^3"),
        error_unit="relative",
        reference=("ITU-R P.840-7 (12/2017) eqs. (2)-(10) (double-Debye permittivity of Liebe, Hufford & Manabe 1991, "
                   "Rayleigh absorption) evaluated in mpmath at 30 digits; spot value: the ratio of the ITU-R SG3 "
                   "validation examples for P.840-8 at 29 and 14.25 GHz"),
        exact="itu_p840",
        default="itu_p840",
        why_default="the package's only cloud/fog model (Rayleigh absorption, valid for droplets << wavelength)",
        choices=[itu],
        fast=None,
        fast_bound="a single choice",
    )


# ---------------------------------------------------------------------------------------------
# Sea multipath: the exact two-ray geometry over the 4/3 earth in mpmath
# ---------------------------------------------------------------------------------------------

EARTH_RADIUS_M = 6371000
#: WMO sea-state code, mid-band significant wave height H_1/3 (m); sigma_h = H_1/3 / 4
WMO_H13_M = {1: 0.05, 2: 0.3, 3: 0.875, 4: 1.875, 5: 3.25, 6: 5.0}


@functools.lru_cache(maxsize=None)
def mp_sea_permittivity(f_hz, t_c=15, salinity=35):
    """Sea-water eps' - j eps'' of Klein & Swift (1977), IEEE Trans. AP-25(1):104-111, eqs. (13)-(21), in mpmath."""
    with mp.workdps(DPS):
        return _klein_swift(mp.mpf, mp.mpf(t_c), mp.mpf(salinity), _mpf(f_hz))


def _klein_swift(m, t, s, f):
    eps_s = (m("87.134") - m("1.949e-1") * t - m("1.276e-2") * t**2 + m("2.491e-4") * t**3) * (
        1 + m("1.613e-5") * s * t - m("3.656e-3") * s + m("3.210e-5") * s**2 - m("4.232e-7") * s**3)
    two_pi_tau = (m("1.1109e-10") - m("3.824e-12") * t + m("6.938e-14") * t**2 - m("5.096e-16") * t**3) * (
        1 + m("2.282e-5") * s * t - m("7.638e-4") * s - m("7.760e-6") * s**2 + m("1.105e-8") * s**3)
    d = 25 - t
    sigma25 = s * (m("0.182521") - m("1.46192e-3") * s + m("2.09324e-5") * s**2 - m("1.28205e-7") * s**3)
    beta = (m("2.033e-2") + m("1.266e-4") * d + m("2.464e-6") * d**2
            - s * (m("1.849e-5") - m("2.551e-7") * d + m("2.551e-8") * d**2))
    sigma = sigma25 * mp.exp(-d * beta)
    eps0 = m("8.8541878128e-12")
    return m("4.9") + (eps_s - m("4.9")) / (1 + 1j * f * two_pi_tau) - 1j * sigma / (2 * mp.pi * f * eps0)


def mp_two_ray_geometry(range_m, h1_m, h2_m):
    """The specular point on the 4/3-earth sphere by root-finding: (path difference, sin psi, divergence)."""
    with mp.workdps(DPS):
        r, h1, h2 = (_mpf(x) for x in (range_m, h1_m, h2_m))
        ae = mp.mpf(4) / 3 * EARTH_RADIUS_M  # k = 4/3
        r1, r2 = ae + h1, ae + h2
        phi = 2 * mp.asin(mp.sqrt((r**2 - (h1 - h2) ** 2) / (4 * r1 * r2)))  # central angle between terminals

        def leg(h, rr, u):  # (height above the tangent plane at the surface point, distance to it)
            s2 = mp.sin(u / 2) ** 2
            return h - 2 * rr * s2, mp.sqrt(h**2 + 4 * ae * rr * s2)

        def mismatch(u):  # sin(grazing) seen from the antenna minus from the target, u = angle to the point
            a1, d1 = leg(h1, r1, u)
            a2, d2 = leg(h2, r2, phi - u)
            return a1 / d1 - a2 / d2

        lo = max(mp.mpf(0), phi - mp.acos(ae / r2))
        hi = min(phi, mp.acos(ae / r1))
        u = mp.findroot(mismatch, (lo, hi), solver="anderson")
        a1, d1 = leg(h1, r1, u)
        _, d2 = leg(h2, r2, phi - u)
        sin_psi = a1 / d1
        g1, g2, g = ae * u, ae * (phi - u), ae * phi
        divergence = 1 / mp.sqrt(1 + 2 * g1 * g2 / (ae * g * sin_psi))
        return d1 + d2 - r, sin_psi, divergence


def mp_two_way_factor_db(geometry, f_hz, polarization, sigma_h_m=0.0, roughness="miller_brown_vegh"):
    """40 log10 |1 + Gamma rho_s D exp(-j 2 pi delta / lambda)| from an exact geometry, in mpmath."""
    with mp.workdps(DPS):
        delta, sin_psi, divergence = geometry
        lam = C_M_S / _mpf(f_hz)
        eps = mp_sea_permittivity(f_hz)
        root = mp.sqrt(eps - (1 - sin_psi**2))
        gamma = ((sin_psi - root) / (sin_psi + root) if polarization == "horizontal"
                 else (eps * sin_psi - root) / (eps * sin_psi + root))
        x = 2 * (2 * mp.pi * _mpf(sigma_h_m) * sin_psi / lam) ** 2
        rho = mp.exp(-x) * (mp.besseli(0, x) if roughness == "miller_brown_vegh" else 1)
        f2 = abs(1 + gamma * rho * divergence * mp.exp(-2j * mp.pi * delta / lam)) ** 2
        return 20 * mp.log10(f2)


def _horizon_m(h1, h2):
    ae = 4.0 / 3.0 * EARTH_RADIUS_M
    return math.sqrt(2 * ae * h1 + h1**2) + math.sqrt(2 * ae * h2 + h2**2)


def _paths(h1s, h2s, n_ranges):
    """(R, h1, h2) from 300 m (or 3 |h2 - h1|) to 0.95 of the radar horizon, log-spaced."""
    return [(float(r), h1, h2) for h1 in h1s for h2 in h2s
            for r in np.geomspace(max(300.0, 3 * abs(h2 - h1)), 0.95 * _horizon_m(h1, h2), n_ranges)]


def _factor_fn(**kw):
    """Both polarizations of propagation_factor_db (static options ``kw``) on one batch."""
    def fn(r, h1, h2, f, sigma):
        return jnp.concatenate([propagation_factor_db(r, h1, h2, f, polarization=pol, rms_wave_height_m=sigma, **kw)
                                for pol in ("horizontal", "vertical")])
    return fn


#: where the two-way factor is this deep below free space (a null) its dB error is not meaningful
NULL_FLOOR_DB = -20.0


def multipath_earth_family(quick: bool) -> Family:
    h1s, h2s = ((5.0, 30.0), (3.0, 30.0, 300.0)) if quick else ((5.0, 15.0, 30.0), (3.0, 10.0, 30.0, 100.0, 300.0, 1000.0))
    freqs = (3e9, 10e9, 35e9) if quick else (1e9, 3e9, 10e9, 35e9, 94e9)
    paths = _paths(h1s, h2s, 8 if quick else 50)
    geoms = [mp_two_ray_geometry(*p) for p in paths]
    pts = [(p, g, f) for p, g in zip(paths, geoms) for f in freqs]
    ref = np.array([float(mp_two_way_factor_db(g, f, pol)) for pol in ("horizontal", "vertical") for _, g, f in pts])
    r, h1, h2, f = (np.array(v, dtype=float) for v in zip(*[(*p, f) for p, _, f in pts]))
    args = tuple(jnp.asarray(a) for a in (r, h1, h2, f, np.zeros_like(r)))
    mask = ref >= NULL_FLOOR_DB
    kw = _timing(quick)
    curved, cv = _choice("curved", _factor_fn(earth_model="curved"), args, ref=ref, mask=mask,
                         per_element=2, **kw)
    curved.note = (f"4/3 earth, Blake's cubic against the root-found specular point; all points: worst "
                   f"{worst(cv, ref):.2g} dB including nulls")
    flat, fv = _choice("flat", _factor_fn(earth_model="flat"), args, exact=cv, ref=ref, mask=mask,
                       per_element=2, **kw)
    short = np.concatenate([r, r]) <= 5e3
    flat.note = (f"flat earth: a model-choice error (no curvature, no divergence factor); ranges <= 5 km: worst "
                 f"{worst(fv[mask & short], ref[mask & short]):.2g} dB")
    return Family(
        key="multipath_earth",
        title="Sea multipath: earth geometry (two-way propagation factor 40 log10 F)",
        domain=(f"antenna heights {', '.join(f'{x:g}' for x in h1s)} m x target heights "
                f"{', '.join(f'{x:g}' for x in h2s)} m x {len(paths) // (len(h1s) * len(h2s))} slant ranges log-spaced "
                f"from 300 m (or 3 times the height difference) to 0.95 of the radar horizon x {', '.join(f'{x / 1e9:g}' for x in freqs)} GHz "
                f"x H and V polarization; smooth sea (Fresnel, Klein-Swift sea water at 15 degC, 35 psu), k = 4/3; "
                f"errors where the reference is above {NULL_FLOOR_DB:g} dB ({int(mask.sum())} of {mask.size} points)"),
        error_unit="dB",
        reference=("the exact two-ray geometry over the 4/3-earth sphere in mpmath at 30 digits: specular point by "
                   "root-finding on equal grazing angles, path difference and grazing angle from it, divergence factor "
                   "D = [1 + 2 G1 G2/(k a G sin psi)]^(-1/2) (Kerr 1951; Blake 1986 eq. 6.49), Fresnel coefficient of "
                   "Klein & Swift (1977) sea water evaluated in mpmath"),
        exact="curved",
        default="curved",
        why_default=("the radar chain's geometry, valid out to the radar horizon; over a flat earth the path difference "
                     "misses the earth's bulge, which moves the lobes and nulls once it is a fraction of a wavelength"),
        choices=[curved, flat],
        fast=None,
        fast_bound=f"bound 0.01 dB: the flat earth misses it (worst {flat.error_vs_reference:.2g} dB)",
    )


def multipath_roughness_family(quick: bool) -> Family:
    h1s, h2s = ((10.0, 30.0), (3.0, 30.0, 300.0)) if quick else ((5.0, 15.0, 30.0), (3.0, 10.0, 30.0, 100.0, 300.0, 1000.0))
    freqs = (3e9, 10e9) if quick else (1e9, 3e9, 10e9, 35e9)
    paths = _paths(h1s, h2s, 8 if quick else 30)
    geoms = [mp_two_ray_geometry(*p) for p in paths]
    states = (2, 4, 6) if quick else sorted(WMO_H13_M)
    pts = [(p, g, f, WMO_H13_M[s] / 4.0) for p, g in zip(paths, geoms) for f in freqs for s in states]
    ref = np.array([float(mp_two_way_factor_db(g, f, pol, sig)) for pol in ("horizontal", "vertical")
                    for _, g, f, sig in pts])
    r, h1, h2, f, sig = (np.array(v, dtype=float) for v in zip(*[(*p, f, s) for p, _, f, s in pts]))
    args = tuple(jnp.asarray(a) for a in (r, h1, h2, f, sig))
    mask = ref >= NULL_FLOOR_DB
    kw = _timing(quick)
    mbv, mv = _choice("miller_brown_vegh", _factor_fn(roughness_model="miller_brown_vegh"), args, ref=ref, mask=mask,
                      per_element=2, **kw)
    mbv.note = "exp(-2 g^2) I0(2 g^2) (Miller, Brown & Vegh 1984)"
    ament, _ = _choice("ament", _factor_fn(roughness_model="ament"), args, exact=mv, ref=ref, mask=mask,
                       per_element=2, **kw,
                       note="exp(-2 g^2) (Ament 1953): a model-choice difference, not a numerical error")
    smooth_fn = _factor_fn(roughness_model="miller_brown_vegh")
    smooth, _ = _choice("smooth sea", lambda r_, a, b, f_, s: smooth_fn(r_, a, b, f_, 0.0 * s), args, exact=mv, ref=ref,
                        mask=mask, per_element=2, **kw,
                        note="rho_s = 1 (sea state 0): a model-choice difference, not a numerical error")
    return Family(
        key="multipath_roughness",
        title="Sea multipath: rough-sea specular reflection (two-way propagation factor 40 log10 F)",
        domain=(f"WMO sea states {', '.join(str(x) for x in states)} (sigma_h = H_1/3 / 4 of the mid-band wave height) x antenna heights "
                f"{', '.join(f'{x:g}' for x in h1s)} m x target heights {', '.join(f'{x:g}' for x in h2s)} m x "
                f"{len(paths) // (len(h1s) * len(h2s))} slant ranges from 300 m to 0.95 of the radar horizon x "
                f"{', '.join(f'{x / 1e9:g}' for x in freqs)} GHz x H and V; 4/3 earth; errors where the reference is "
                f"above {NULL_FLOOR_DB:g} dB ({int(mask.sum())} of {mask.size} points)"),
        error_unit="dB",
        reference=("the exact 4/3-earth two-ray geometry and Fresnel coefficient of the multipath_earth family with the "
                   "Miller-Brown-Vegh factor exp(-2 g^2) I0(2 g^2), g = 2 pi sigma_h sin psi / lambda (Miller, Brown & "
                   "Vegh 1984, IEE Proc. 131H:114-116), all in mpmath at 30 digits"),
        exact="miller_brown_vegh",
        default="miller_brown_vegh",
        why_default=("the radar chain's roughness model: Ament's factor ignores the wave-height distribution's effect "
                     "(Miller, Brown & Vegh 1984) and underestimates the coherent reflection at large g"),
        choices=[mbv, ament, smooth],
        fast=None,
        fast_bound="no faster choice: the alternatives are other models (dB-level differences), not approximations",
    )


def run(quick: bool) -> list:
    """The propagation families (see the module docstring)."""
    return [gas_family(quick), rain_family(quick), cloud_family(quick), multipath_earth_family(quick),
            multipath_roughness_family(quick)]


if __name__ == "__main__":
    main_alone(run, __doc__)
