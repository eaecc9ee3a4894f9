"""Fidelity families of the solver's numerical knobs (for ``bench_fidelity.py``): what each setting
costs per solve or check and what it leaves as error.

1. **Interval search grid** (``over_points``): the worst value of a requirement over an interval
   found by the search (:mod:`diffsense.design.intervals`: a grid of 17, 33 or 129 points, its
   lowest local minima polished by values alone) and by the dense re-check (10,001 points, the
   worse of its grid's value and the search's), at fixed designs, against the true worst value:
   a scan of 100,001 points (20,001 with ``quick``) polished by bounded Brent minimisation
   (``scipy.optimize.minimize_scalar``) of the requirement's output evaluated by the chain
   (``diffsense.scene.compute``). Two specs: the multipath null of
   ``tests/design/interval_specs/multipath_null.toml`` (non-monotone: target heights that put
   2 to 11 local minima in the interval) and ``designs/ore_pass.toml`` (monotone in range).
2. **Chance-constraint sample size** (``[uncertain] samples``): the design the solver returns
   with the smoothed quantile on 256 … 16,384 scrambled Sobol points, and the probability it
   actually achieves, in closed form (a margin linear in three inputs: lognormal RCS and normal
   noise figure make it normal, a uniform gas attenuation adds a uniform term; the expectation of
   Φ over the uniform term integrates in closed form).
3. **Continuation points** of a trade front (``[trade] points``): ``benchmarks/bench_trade.py``'s
   power–aperture problem (exact front P·d⁴ = K) traced by ``trace_front`` with 5 … 40 points;
   hypervolume against the exact front's, in closed form.
4. **Solver tolerance** (``SolverOptions(tol, feas_tol)``, the augmented Lagrangian and the SQP;
   the tolerances of ``bench_design.py``'s sweep): objective error against closed-form optima.

Times are per solve or per check (one warm call of the compiled program, the median of a few),
not per grid point; each note says which. Programs are compiled with the package's "optimized"
XLA preset (:mod:`diffsense.optimize.compile`; ``quick``: its "fast" preset), several at once in
background threads, before anything is timed (:func:`run_staged`).

Run alone: python benchmarks/_fidelity_solver.py [--quick] (needs scipy, in the ``bench`` extras).
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import functools
import math
import time
from statistics import NormalDist
from pathlib import Path
from typing import Callable, Dict, List, NamedTuple, Optional, Sequence, Tuple

import _support
import jax
import jax.numpy as jnp
import numpy as np

from _fidelity_support import _OP, PRESET, QUICK_PRESET, Choice, Family, main_alone, worst

ROOT = _support.ROOT
MULTIPATH = ROOT / "tests" / "design" / "interval_specs" / "multipath_null.toml"
ORE_PASS = ROOT / "designs" / "ore_pass.toml"
SIDESCAN = ROOT / "designs" / "sidescan_sonar.toml"
FIRE_CONTROL = ROOT / "designs" / "fire_control.toml"
#: bound of the fast choice for worst values in dB
DB_BOUND = 0.01


# --- compiling and timing --------------------------------------------------------------------


def run_staged(makers: Sequence[Callable], quick: bool) -> List[Family]:
    """Run family generators in two stages. Each ``maker(quick)`` is a generator that yields the
    programs it needs, a list of ``(fn, example args)``, and is sent back ``(compiled, HLO
    operations)`` for each, then returns its :class:`Family`. First every family's programs are
    traced and lowered here, one after another, while two background threads compile them (XLA
    compiles without Python's lock); then, with nothing compiling, each family runs and is timed.
    The XLA options are the :data:`PRESET`'s (``quick``: :data:`QUICK_PRESET`'s)."""
    from diffsense.optimize.compile import jit_with_options

    preset = QUICK_PRESET if quick else PRESET
    gens = [maker(quick) for maker in makers]
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        staged = []
        for g in gens:
            # a function already jitted (with its own options) is lowered as it is
            staged.append([pool.submit((fn if hasattr(fn, "lower") else jit_with_options(fn, preset))
                                       .lower(*args).compile) for fn, args in next(g)])
        programs = [[(f.result(), len(_OP.findall(f.result().as_text()))) for f in futures] for futures in staged]
    out = []
    for g, compiled in zip(gens, programs):
        try:
            g.send(compiled)
        except StopIteration as stop:
            out.append(stop.value)
        else:
            raise RuntimeError("a family generator yielded twice")
    return out


def timed(fn: Callable, args: tuple, repeats: int):
    """``(fn(*args), seconds)``: the result of a first call (which warms the program), then the
    median wall time of ``repeats`` further calls."""
    out = jax.block_until_ready(fn(*args))
    ts = []
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(fn(*args))
        ts.append(time.perf_counter() - t)
    return out, float(np.median(ts))


def choice_named(choices: List[Choice], name: str) -> Choice:
    return next(c for c in choices if c.name == name)


def _tree(a):
    return jax.tree_util.tree_map(jnp.asarray, a)


# --- 1. interval search grid -----------------------------------------------------------------


def _with_counts(spec, n: int):
    """``spec`` with every interval requirement searched on ``n`` grid points."""
    reqs = [dataclasses.replace(r, over_points=n) if r.over else r for r in spec.requirements]
    return dataclasses.replace(spec, requirements=reqs)


def _chunked(fn, points: np.ndarray, chunk: int) -> np.ndarray:
    """``fn`` (compiled for ``chunk`` points) over ``points``, the last chunk padded."""
    out = []
    for s in range(0, points.size, chunk):
        part = points[s:s + chunk]
        pad = np.concatenate([part, np.full(chunk - part.size, part[-1])])
        out.append(np.asarray(fn(jnp.asarray(pad)))[: part.size])
    return np.concatenate(out, axis=0)


def true_worst(curve: Callable, lower: float, upper: float, log: bool, sense: str, scan: int, chunk: int):
    """``(worst value, its number of local extrema in the scan)`` of a requirement's output over
    [lower, upper] — its minimum for ``at_least``, maximum for ``at_most`` — by a scan of ``scan``
    points (uniform in p, or in ln p when ``log``) whose five worst local extrema (ends included)
    are each polished by bounded Brent minimisation (``scipy.optimize.minimize_scalar``, method
    "bounded", to 1e-9 of the interval) inside the bracket of their scan neighbours; at a smooth
    extremum that leaves the value exact to round-off (its error is second order in the 1e-9).
    ``curve``: the output at a chunk of ``chunk`` parameter values (a plateau counts as one
    extremum)."""
    from scipy.optimize import minimize_scalar

    sgn = 1.0 if sense == "at_least" else -1.0
    p = np.geomspace(lower, upper, scan) if log else np.linspace(lower, upper, scan)
    v = sgn * _chunked(curve, p, chunk)
    best = float(np.min(v))
    local = np.flatnonzero((v <= np.r_[np.inf, v[:-1]]) & (v <= np.r_[v[1:], np.inf]))
    runs = v[np.r_[True, np.diff(v) != 0]]  # a plateau counts once
    n_local = int(np.count_nonzero((runs < np.r_[np.inf, runs[:-1]]) & (runs < np.r_[runs[1:], np.inf])))
    tol = 1e-9 * (upper - lower)

    def f(x):
        return sgn * float(np.asarray(curve(jnp.full(chunk, x)))[0])

    for i in local[np.argsort(v[local])][:5]:
        a, b = p[max(i - 1, 0)], p[min(i + 1, p.size - 1)]
        res = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": tol, "maxiter": 500})
        best = min(best, float(res.fun))
    return sgn * best, n_local


class Source(NamedTuple):
    """Designs of one spec for an interval family: ``designs`` maps a label to the inputs written
    over the spec's initial design ({input name: value}, "combo": a catalog combination);
    ``outputs``: the interval requirements kept, by output (None: all)."""

    path: Path
    designs: Dict[str, Dict[str, float]]
    outputs: Optional[Tuple[str, ...]] = None


def _interval_programs(source: Source, counts, default: int, chunk: int):
    """Models, input vectors and programs of one source: ``(models, m, vectors, curves, jobs)``;
    the jobs are each count's search, the dense re-check and each case's reference curve (the
    interval requirements' outputs from the chain itself, ``diffsense.scene.compute``)."""
    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec
    from diffsense.scene import compute

    base = load_spec(source.path)
    if source.outputs is not None:
        base = dataclasses.replace(base, requirements=[r for r in base.requirements
                                                       if r.over and f"{r.case}.{r.output}" in source.outputs])
    models = {n: DesignModel(_with_counts(base, n)) for n in counts}
    m = models[default]
    vectors = {}
    for label, setting in source.designs.items():
        combo = int(setting.get("combo", 0))
        v = m.design_values(m.initial, combo)
        for name, value in setting.items():
            if name != "combo":
                v[m.layout.index(name)] = value
        vectors[label] = (v, _tree(m.inputs(combo, values=v)))
    v0, in0 = next(iter(vectors.values()))
    jobs = [(lambda v, inp, mm=mm: mm.intervals.search(mm.parameters(v), inp), (jnp.asarray(v0), in0))
            for mm in models.values()]
    jobs.append((lambda v, inp: m.intervals.dense(m.parameters(v), inp), (jnp.asarray(v0), in0)))
    reqs = [m.spec.requirements[j] for j in m.intervals.indices]
    curves = {}
    for case in sorted({r.case for r in reqs}):
        outs = [r.output for r in reqs if r.case == case]
        (name,) = {r.over[0].parameter for r in reqs if r.case == case}

        def fn(v, p, case=case, outs=outs, name=name):
            params = m.parameters(v)[case]

            def at(q):
                ev = compute(m.spec.scenes[case], dict(params, **{name: q}), frozenset(outs))
                return jnp.stack([ev.values[o] for o in outs])
            return jax.vmap(at)(p)
        curves[case] = outs
        jobs.append((fn, (jnp.asarray(v0), jnp.zeros(chunk))))
    return models, m, vectors, curves, jobs


def interval_family(key: str, title: str, sources: Sequence[Source], domain: str, why_default: str, quick: bool,
                    counts=(17, 33, 129), default: int = 129):
    """One interval-search family (a generator, :func:`run_staged`): the interval requirements of
    each source searched with each grid of ``counts`` at every design of the source, against the
    dense re-check and the true worst value (:func:`true_worst`). ``domain``: its words,
    ``{minima}`` replaced by the range of local minima counted."""
    chunk = 1024
    built = [_interval_programs(src, counts, default, chunk) for src in sources]
    compiled = yield [job for b in built for job in b[4]]
    repeats = 3 if quick else 15
    scan = 20_001 if quick else 100_001
    found = {n: {} for n in counts}  # n -> (source, design, j) -> worst value
    times = {n: [] for n in counts}
    ops = {n: 0 for n in counts}
    exact, grid_only, ref, minima = {}, {}, {}, {}
    dense_times, dense_ops = [], 0
    start = 0
    for src, (models, m, vectors, curves, jobs) in zip(sources, built):
        mine = compiled[start:start + len(jobs)]
        start += len(jobs)
        searches = dict(zip(counts, mine[:len(counts)]))
        dense, d_ops = mine[len(counts)]
        dense_ops = max(dense_ops, d_ops)
        curve_fns = dict(zip(curves, [c for c, _ in mine[len(counts) + 1:]]))
        reqs = {j: m.spec.requirements[j] for j in m.intervals.indices}
        for label, (v, inp) in vectors.items():
            vj = jnp.asarray(v)
            for n, (fn, n_ops) in searches.items():
                out, t = timed(fn, (vj, inp), repeats)
                times[n].append(t)
                ops[n] = max(ops[n], n_ops)
                for j in reqs:
                    found[n][(src.path.stem, label, j)] = float(np.asarray(out[j][0])[0])
            out, t = timed(dense, (vj, inp), repeats)
            dense_times.append(t)
            for j, r in reqs.items():
                k = (src.path.stem, label, j)
                pts, vals = np.asarray(out[j][0]), np.asarray(out[j][1])
                exact[k] = m.intervals.check(j, pts, vals, found[default][k]).worst_value
                grid_only[k] = float(np.min(vals) if r.sense == "at_least" else np.max(vals))
                fn, col = curve_fns[r.case], curves[r.case].index(r.output)
                iv = r.over[0]
                ref[k], minima[k] = true_worst(lambda p, fn=fn, col=col: fn(vj, p)[:, col], iv.lower, iv.upper,
                                               bool(m.intervals.boxes[j].log[0]), r.sense, scan, chunk)
    keys = list(ref)
    exact_v = np.array([exact[k] for k in keys])
    ref_v = np.array([ref[k] for k in keys])
    choices = []
    for n in counts:
        got = np.array([found[n][k] for k in keys])
        miss = np.abs(got - ref_v)
        w = int(np.argmax(miss))
        note = "one warm search (every interval requirement of the spec) per design"
        if miss[w] > DB_BOUND:
            note += f"; worst at {keys[w][0]}, {keys[w][1]}"
        choices.append(Choice(f"{n} points + polish", float(np.median(times[n])), ops[n], worst(got, exact_v),
                              worst(got, ref_v), note))
    grid_v = np.array([grid_only[k] for k in keys])
    choices.append(Choice("dense re-check (10,001 points)", float(np.median(dense_times)), dense_ops, 0.0,
                          worst(exact_v, ref_v),
                          f"one warm call of the dense program per design; its grid alone errs by up to "
                          f"{worst(grid_v, ref_v):.2g} dB, the check reports the worse of it and the "
                          f"{default}-point search"))
    default_name = f"{default} points + polish"
    lo, hi = min(minima.values()), max(minima.values())
    return Family(
        key=key, title=title, domain=domain.format(minima=str(lo) if lo == hi else f"{lo} to {hi}"),
        error_unit="dB",
        reference=("true worst value of the requirement's output over the interval: a scan of "
                   f"{scan:,} points polished by bounded Brent minimisation (scipy.optimize.minimize_scalar, "
                   "1e-9 of the interval) of the chain's output (diffsense.scene.compute, the chain alone) at the "
                   "same design"),
        exact="dense re-check (10,001 points)", default=default_name, why_default=why_default, choices=choices,
        fast=_fastest_within(choices, DB_BOUND, default_name),
        fast_bound=(f"worst value within {DB_BOUND} dB of the true worst over the grid "
                    "(a solver setting, over_points in the spec: fidelity does not change it)"))


#: a choice counts as faster than the default when it takes less than this fraction of its time
#: (timings on a shared machine move by several per cent between calls)
FASTER = 0.9


def _fastest_within(choices: List[Choice], bound: float, default_name: str, meets=None):
    """The fastest choice whose error against the reference is within ``bound`` (and that
    ``meets(choice)``, when given) and that is faster than the default by :data:`FASTER`, else None."""
    default = next(c for c in choices if c.name == default_name)
    ok = [c for c in choices if c.error_vs_reference <= bound and (meets is None or meets(c))
          and c.seconds_per_eval < FASTER * default.seconds_per_eval]
    return min(ok, key=lambda c: c.seconds_per_eval).name if ok else None


def _combinations(path, quick: bool):
    """{label: {"combo": c}} for a spec's catalog combinations (the first and last with ``quick``)."""
    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec

    model = DesignModel(load_spec(path))
    n = len(model.combinations)
    combos = sorted({0, n - 1}) if quick else range(n)
    return {" / ".join(model.combinations[c].options.values()) or f"combination {c}": {"combo": c} for c in combos}


def interval_null(quick: bool):
    heights = (30.0, 60.0) if quick else (30.0, 60.0, 100.0, 200.0, 400.0)
    sources = [Source(MULTIPATH, {f"h2 = {h:g} m": {"target_height_m": h} for h in heights})]
    words = ("tests/design/interval_specs/multipath_null.toml (X band, radar 8 m above a calm sea, detection margin "
             f"over 10–20 km, 10 kW) at target heights {', '.join(f'{h:g}' for h in heights)} m")
    if not quick:
        sources.append(Source(FIRE_CONTROL, _combinations(FIRE_CONTROL, quick), ("sea_skimmer.detection_margin_db",)))
        words += ("; designs/fire_control.toml's sea skimmer (multipath and sea clutter, sea state 5, detection "
                  "margin over 50 m–5 km) at its initial design in each of its 3 bands")
    return (yield from interval_family(
        "solver_interval_null", "Interval search grid: non-monotone margin (multipath nulls)", sources,
        words + " ({minima} local minima of the margin in the interval)",
        "129 points resolve every multipath lobe of these intervals (target heights to 400 m), where 17 "
        "and 33 points miss the deepest null", quick))


def interval_monotone(quick: bool):
    designs = _combinations(ORE_PASS, quick)
    return (yield from interval_family(
        "solver_interval_monotone", "Interval search grid: monotone margin (ore pass)", [Source(ORE_PASS, designs)],
        "designs/ore_pass.toml at its initial design, both interval requirements (faded SNR margin and "
        f"signal-to-clutter margin over 10–300 m; {{minima}} local minimum each, at 300 m), {len(designs)} "
        "catalog combinations",
        "the package's default for an interval; this spec sets over_points = 17 itself (its margins fall "
        "monotonically with range, and the dense re-check guards the choice)", quick))


# --- 2. chance-constraint sample size ---------------------------------------------------------

RANGE_KM = 320.0
SIGMA_RCS_DB = 3.0
SIGMA_NF_DB = 0.5
GAS = (0.0, 0.006)  # dB/km, uniform; its median 0.003 dB/km is the book 9.9.1 value


def chance_spec(samples: int, probability: float = 0.9) -> dict:
    """Book 9.9.1's L-band radar at 320 km (detectability given, gas attenuation specified) whose
    peak power is minimised subject to a detection margin ≥ 0 dB met with ``probability``, with
    three uncertain inputs: a lognormal RCS (3 dB), a normal noise figure (0.5 dB) and a uniform
    one-way gas attenuation on 0–0.006 dB/km."""
    fixed = {"freq_hz": "1.3034 GHz", "pulse_width_s": "2 us", "bandwidth_hz": "306.5 kHz", "prf_hz": "360 Hz",
             "n_pulses": 10, "aperture_efficiency": 0.7, "detectability_db": "8.2 dB",
             "range_m": f"{RANGE_KM} km", "antenna_diameter_m": "5.5 m"}
    uncertain = {"rcs_m2": {"lognormal": "1 m^2", "sigma_db": SIGMA_RCS_DB},
                 "noise_figure_db": {"normal": "4 dB", "sigma": f"{SIGMA_NF_DB} dB"},
                 "gas_attenuation_db_km": {"uniform": [f"{GAS[0]} dB/km", f"{GAS[1]} dB/km"]},
                 "samples": samples}
    return {"sensor": "radar", "parts": ["gas"],
            "options": {"antenna": "circular_aperture", "detectability": "given", "gas_model": "specified"},
            "fixed": fixed, "uncertain": uncertain,
            "variables": {"peak_power_w": {"lower": "100 kW", "upper": "50 MW", "initial": "5 MW"}},
            "requirements": [{"output": "detection_margin_db", "at_least": "0 dB", "probability": probability}],
            "objective": {"minimize": "peak_power_w"}}


def probability_met(nominal_margin_db: float) -> float:
    """P[m ≥ 0] for the margin m = m₀ + X − 2R(α − ᾱ) of :func:`chance_spec` (m₀ its value at the
    medians): X = 10 log10(σ/σ_med) − (NF − NF_med) is normal with S = √(s_σ² + s_NF²) (both in
    dB) and α uniform on [a, b], so with c = m₀ + kᾱ, k = 2R (km),

        P = (1/(b − a)) ∫_a^b Φ((c − kα)/S) dα = S/(k(b − a)) · [G(u_a) − G(u_b)],
        u = (c − kα)/S,  G(u) = uΦ(u) + φ(u)  (∫Φ = G).

    Exact for the untruncated distributions; the spec's truncation of the normal draws at ±6σ
    changes it by at most 2e-9."""
    n01 = NormalDist()
    s = math.hypot(SIGMA_RCS_DB, SIGMA_NF_DB)
    a, b = GAS
    k = 2.0 * RANGE_KM
    c = nominal_margin_db + k * 0.5 * (a + b)

    def g(u):
        return u * n01.cdf(u) + math.exp(-0.5 * u * u) / math.sqrt(2.0 * math.pi)

    return s / (k * (b - a)) * (g((c - k * a) / s) - g((c - k * b) / s))


@functools.lru_cache(maxsize=None)
def required_margin(p: float) -> float:
    """The nominal margin m₀ at which :func:`probability_met` equals ``p`` (bisection to 1e-12 dB;
    the probability increases with m₀)."""
    lo, hi = -50.0, 50.0
    while hi - lo > 1e-12:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if probability_met(mid) < p else (lo, mid)
    return 0.5 * (lo + hi)


def chance_samples(quick: bool):
    from diffsense.design.model import DesignModel
    from diffsense.design.problem import requirement_problem
    from diffsense.design.spec import parse_spec
    from diffsense.optimize import SolverOptions, solve
    from diffsense.scene import evaluate

    sizes = (256, 1024, 4096, 16384)
    probs = (0.9,) if quick else (0.75, 0.8, 0.85, 0.9)
    options = SolverOptions(polish=False)  # the design optimiser's
    models = {n: DesignModel(parse_spec(chance_spec(n))) for n in sizes}
    jobs, thetas = [], {}
    for n, model in models.items():
        problem = requirement_problem(model)
        # the objective's normalisation (diffsense.design.runner.objective_scale): the objective, the
        # peak power itself, at the initial design
        scale = float(model.initial[0])
        for p in probs:
            inp = model.inputs(0)._replace(alpha=np.array([1.0 - p]))
            thetas[(n, p)] = _tree(model.solve_inputs(inp, 0, model.limits, scale))
        jobs.append((lambda x0, th, problem=problem: solve(problem, x0, th, options),
                     (jnp.asarray(model.initial), thetas[(n, probs[0])])))
    m = models[sizes[0]]
    scene = m.spec.scenes["main"]
    jobs.append((lambda v: evaluate(scene, m.parameters(v)["main"]).values["detection_margin_db"],
                 (jnp.asarray(m.design_values(m.initial, 0)),)))
    compiled = yield jobs
    margin = compiled[-1][0]
    repeats = 1 if quick else 5
    achieved, powers, times, converged = {}, {}, {}, {}
    for (n, model), (fn, ops) in zip(models.items(), compiled):
        for p in probs:
            res, t = timed(fn, (jnp.asarray(model.initial), thetas[(n, p)]), repeats)
            x = np.asarray(res.x)
            achieved[(n, p)] = probability_met(float(margin(jnp.asarray(model.design_values(x, 0)))))
            powers[(n, p)] = float(x[0])
            times.setdefault(n, []).append(t)
            converged[(n, p)] = bool(res.converged)
    choices = []
    top = sizes[-1]
    for (n, (fn, ops)) in zip(sizes, compiled):
        got = np.array([achieved[(n, p)] for p in probs])
        best = np.array([achieved[(top, p)] for p in probs])
        db = max(abs(10 * math.log10(powers[(n, p)] / powers[(top, p)])) for p in probs)
        off = max(abs(float(margin(jnp.asarray(models[n].design_values(np.array([powers[(n, p)]]), 0))))
                      - required_margin(p)) for p in probs)
        note = (f"one warm solve (AL, the design optimiser's settings); power {db:.2g} dB from the {top:,}-sample "
                f"design's, nominal margin {off:.2g} dB from the exact one")
        if not all(converged[(n, p)] for p in probs):
            note += "; not converged at some p"
        choices.append(Choice(f"{n:,} samples", float(np.median(times[n])),
                              ops, worst(got, best), worst(got, np.array(probs)), note))
    default = "4,096 samples"
    bound = 2e-3
    n01 = NormalDist()
    wilson = {p: n01.inv_cdf(0.995) * math.sqrt(p * (1 - p) / 100_000) for p in probs}
    return Family(
        key="solver_chance_samples", title="Chance-constraint design sample size ([uncertain] samples)",
        domain=(f"a radar (book 9.9.1 numbers, 320 km, detectability given) designed for detection margin ≥ 0 dB "
                f"with probability p ∈ {{{', '.join(f'{p:g}' for p in probs)}}} over a lognormal RCS (3 dB), a "
                "normal noise figure (0.5 dB) and a uniform gas attenuation (0–0.006 dB/km); error: the probability "
                "the returned design achieves minus p"),
        error_unit="probability",
        reference=("closed form: the margin is m₀ + N(0, √(3² + 0.5²) dB) − 2R(α − ᾱ), α uniform, so "
                   "P = S/(2R(b − a))·[G(u_a) − G(u_b)], G(u) = uΦ(u) + φ(u) (∫Φ du; exact up to the ±6σ "
                   "truncation, ≤ 2e-9)"),
        exact="16,384 samples", default=default,
        why_default=(f"4,096 Sobol points hold the achieved probability within "
                     f"{choice_named(choices, default).error_vs_reference:.2g} of p here, inside what the "
                     "independent Monte Carlo check (100,000 draws) resolves (99 % Wilson half-width "
                     + ", ".join(f"{w:.1e} at p = {p:g}" for p, w in wilson.items()) + "), at a solve "
                     "cost of a fraction of a second"),
        choices=choices, fast=_fastest_within(choices, bound, default),
        fast_bound=(f"achieved probability within {bound:g} of the asked one over the grid, below the "
                    "check's resolution (a spec setting, [uncertain] samples: fidelity does not change it)"))


# --- 3. continuation points --------------------------------------------------------------------

P_BOX = (1e3, 1e7)
D_BOX = (1.0, 10.0)
HV_REFERENCE = 1.1  # per normalised objective, as bench_trade.py


def exact_hypervolume(K: float) -> float:
    """Hypervolume of the exact front P = K/d⁴, d ∈ [1, d_n], d_n = (K/P_min)^¼ (P from K down to
    P_min), in objectives normalised to the ideal–nadir box (P_min, 1)–(K, d_n), reference point
    (1.1, 1.1): 1.1² − ∫₀¹ f_P(f_d) df_d with

        ∫₀¹ f_P df_d = [K/3·(1 − d_n⁻³) − P_min(d_n − 1)] / ((K − P_min)(d_n − 1))."""
    p0 = P_BOX[0]
    dn = (K / p0) ** 0.25
    area = (K / 3.0 * (1.0 - dn ** -3) - p0 * (dn - 1.0)) / ((K - p0) * (dn - 1.0))
    return HV_REFERENCE ** 2 - area


def staircase_hypervolume(F: np.ndarray, K: float) -> float:
    """Hypervolume of the points ``F`` (N, 2) = (P, d) in the same normalisation: the union of the
    boxes [f_i, 1.1]², summed over the points sorted by the first objective."""
    p0 = P_BOX[0]
    dn = (K / p0) ** 0.25
    f = np.column_stack([(F[:, 0] - p0) / (K - p0), (F[:, 1] - 1.0) / (dn - 1.0)])
    f = f[np.all(f < HV_REFERENCE, axis=1)]
    f = f[np.lexsort((f[:, 1], f[:, 0]))]
    area, top = 0.0, HV_REFERENCE
    for a, b in f:
        if b < top:
            area += (HV_REFERENCE - a) * (top - b)
            top = b
    return area


def trade_points(quick: bool):
    from diffsense.optimize import Problem, SolverOptions
    from diffsense.optimize.continuation import Scalarization, pareto_mask, step_program, trace_front

    from bench_trade import K as K_BENCH

    problem = Problem(lambda x, th: 0.0 * x[0], [P_BOX[0], D_BOX[0]], [P_BOX[1], D_BOX[1]],
                      inequality=lambda x, th: jnp.array([1.0 - x[0] * x[1] ** 4 / th]), log_scale=True)

    def objectives(x, th):
        return x

    counts = (5, 10, 20, 30, 40)
    Ks = (K_BENCH,) if quick else (5e3, K_BENCH, 1e5)
    repeats = 3 if quick else 7
    # the one step program trace_front compiles and reuses for every count (two lanes: the anchors,
    # then the two walks), sized: lowered after the first call, JAX's cache hands back the executable
    step = step_program(problem, objectives, SolverOptions(polish=True), "auto")
    two = np.ones((2, 2))
    args = (two, (np.full(2, Ks[0]), Scalarization(two, two, two, two)), two, 10.0 * two, two)
    trace_front(problem, objectives, np.array([Ks[0]]), np.array([[1e5, 3.0]]), points=counts[0])  # compiles
    ((_, ops),) = yield [(step, args)]
    hv, dist, times, kept = {}, {}, {}, {}
    for n in counts:
        for K in Ks:
            def call(n=n, K=K):
                return trace_front(problem, objectives, np.array([K]), np.array([[1e5, 3.0]]), points=n)
            front, t = timed(call, (), repeats)
            ok = front.converged & front.feasible
            F = front.objectives[ok]
            F = F[pareto_mask(F)]
            hv[(n, K)] = staircase_hypervolume(F, K) / exact_hypervolume(K)
            dist[(n, K)] = float(np.max(np.abs(F[:, 0] * F[:, 1] ** 4 / K - 1.0)))
            kept[(n, K)] = len(F)
            times.setdefault(n, []).append(t)
    top = counts[-1]
    choices = []
    for n in counts:
        deficit = np.array([1.0 - hv[(n, K)] for K in Ks])
        vs_top = np.array([abs(hv[(n, K)] - hv[(top, K)]) for K in Ks])
        note = (f"one warm trace_front call (anchors and walks); {min(kept[(n, K)] for K in Ks)} points kept; "
                f"every point on P·d⁴ = K to {max(dist[(n, K)] for K in Ks):.1g}")
        choices.append(Choice(f"{n} points", float(np.median(times[n])), ops,
                              float(np.max(vs_top)), float(np.max(deficit)), note))
    bound = 0.05
    default = "30 points"
    return Family(
        key="solver_trade_points", title="Trade-front continuation points ([trade] points)",
        domain=(f"bench_trade.py's power–aperture problem: minimise (P, d) s.t. P·d⁴ ≥ K, 1e3 ≤ P ≤ 1e7 W, "
                f"1 ≤ d ≤ 10 m, K ∈ {{{', '.join(f'{K:g}' for K in Ks)}}}; error: the hypervolume the front's "
                "points leave out, relative to the exact front's (objectives normalised to the ideal–nadir box, "
                "reference point 1.1 each)"),
        error_unit="relative hypervolume",
        reference=("the exact front P = K/d⁴ in closed form: hypervolume "
                   "1.1² − [K/3·(1 − d_n⁻³) − P_min(d_n − 1)] / ((K − P_min)(d_n − 1)), "
                   "d_n = (K/P_min)^¼"),
        exact=f"{top} points", default=default,
        why_default=("30 points draw the front finely enough for the report's figure and its knee; one step "
                     "program serves every count (HLO ops: that program's), so more points cost only solves, "
                     "about N/2 calls of it"),
        choices=choices, fast=_fastest_within(choices, bound, default),
        fast_bound=(f"hypervolume within {bound:.0%} of the exact front's (every point lies on the front to solver "
                    "tolerance whatever the count; a spec setting, [trade] points: fidelity does not change it)"))


# --- 4. solver tolerance -----------------------------------------------------------------------

WEIGHTS = (1e-4, 1.0)  # minimise a·P + b·d (P in W, d in m) s.t. P·d⁴ ≥ K
K_TOL = 2e4


def power_aperture_optimum(K: float = K_TOL, a: float = WEIGHTS[0], b: float = WEIGHTS[1]) -> float:
    """min a·P + b·d s.t. P·d⁴ ≥ K: on the constraint P = K d⁻⁴, so d/dd (aK d⁻⁴ + b d) = 0 gives
    d* = (4aK/b)^⅕ and P* = K/d*⁴ (the air-surveillance check of the README: d⁵ = 4aK/b, aP = bd/4);
    f* = a·P* + b·d*."""
    d = (4.0 * a * K / b) ** 0.2
    return a * K / d ** 4 + b * d


def _sidescan_setup():
    """(model, problem, θ, closed-form optimal power): the sidescan spec at its monotone interval
    slots (the far end, 750 m, the worst point at every design) and its limits untightened; the
    closed form of ``tests/report/test_report.py`` (book eqs 12.42–12.48: the margin is
    const + 10 log10 P − 20 log10 θ_az, so the least power puts θ_az on its 1° bound and the
    margin at 750 m on 0 dB: P* = P0·10^(−m1/10), m1 = m(P0, θ0) + 20 log10(θ0/1°))."""
    from diffsense.design.model import DesignModel
    from diffsense.design.problem import requirement_problem
    from diffsense.design.programs import rows_of
    from diffsense.design.runner import objective_scale
    from diffsense.design.spec import load_spec
    from diffsense.scene import evaluate

    model = DesignModel(load_spec(SIDESCAN))
    _, designs = model.programs.design_inputs(model.initial[None, :], [0])
    theta = _tree(model.solve_inputs(rows_of(designs, 0), 0, model.limits, objective_scale(model)))
    names = list(model.variable_names)
    p0, theta0 = model.initial[names.index("electrical_power_w")], model.initial[names.index("beamwidth_az_deg")]
    theta_min = model.lower[names.index("beamwidth_az_deg")]
    params = model.parameters(model.design_values(model.initial, 0))["main"]
    m0 = float(evaluate(model.spec.scenes["main"], dict(params, range_m=750.0)).values["snr_margin_db"])
    m1 = m0 + 20.0 * math.log10(theta0 / theta_min)
    return model, requirement_problem(model), theta, p0 * 10 ** (-m1 / 10)


def _power_of_ten(t: float) -> str:
    """``1e-8`` for 1e-08."""
    return f"1e{round(math.log10(t))}"


def solver_tolerance(quick: bool):
    from diffsense.optimize import Problem, SolverOptions, solve

    from bench_design import TOLERANCES

    methods = ("al", "sqp")
    choices_opts = [(f"{'AL' if m == 'al' else 'SQP'}, tol {_power_of_ten(t)}",
                     SolverOptions(method=m, tol=t, feas_tol=t, polish=False)) for m in methods for t in TOLERANCES]
    pa = Problem(lambda x, th: WEIGHTS[0] * x[0] + WEIGHTS[1] * x[1], [P_BOX[0], D_BOX[0]], [P_BOX[1], D_BOX[1]],
                 inequality=lambda x, th: jnp.array([1.0 - x[0] * x[1] ** 4 / th]), log_scale=True)
    problems = [("power–aperture", pa, jnp.asarray([1e5, 3.0]), jnp.asarray(K_TOL), power_aperture_optimum(),
                 lambda x: x @ np.asarray(WEIGHTS))]
    if not quick:
        model, sp, theta, p_star = _sidescan_setup()
        names = list(model.variable_names)
        k = names.index("electrical_power_w")
        problems.append(("side-scan sonar", sp, jnp.asarray(model.initial), theta, p_star, lambda x, k=k: x[k]))
    jobs = [(lambda x0, th, prob=prob, o=o: solve(prob, x0, th, o), (x0, th))
            for _, prob, x0, th, _, _ in problems for _, o in choices_opts]
    compiled = yield jobs
    repeats = 5 if quick else 20
    err, viol, times, ops, conv = {}, {}, {}, {}, {}
    for i, (pname, _, x0, th, f_star, value) in enumerate(problems):
        for c, (name, _) in enumerate(choices_opts):
            fn, n_ops = compiled[i * len(choices_opts) + c]
            res, t = timed(fn, (x0, th), repeats)
            x = np.asarray(res.x)
            err[(name, pname)] = abs(float(value(x)) / f_star - 1.0)
            viol[(name, pname)] = float(res.kkt.feasibility)
            conv[(name, pname)] = bool(res.converged)
            times.setdefault(name, []).append(t)
            ops.setdefault(name, []).append(n_ops)
    exact, default = "SQP, tol 1e-10", "AL, tol 1e-8"
    pnames = [p[0] for p in problems]
    bound, violation_bound = 1e-6, 1e-7
    choices, meets = [], {}
    for name, _ in choices_opts:
        e = np.array([err[(name, p)] for p in pnames])
        e_exact = np.array([err[(exact, p)] for p in pnames])
        v = max(viol[(name, p)] for p in pnames)
        note = ("one warm solve per problem (time: their mean; " + ", ".join(
            f"{p} {t * 1e3:.2g} ms" for p, t in zip(pnames, times[name])) + f"); largest scaled violation {v:.1g}")
        if not all(conv[(name, p)] for p in pnames):
            note += "; not converged on " + ", ".join(p for p in pnames if not conv[(name, p)])
        meets[name] = float(np.max(e)) <= bound and v <= violation_bound
        choices.append(Choice(name, float(np.mean(times[name])), int(np.max(ops[name])),
                              float(np.max(np.abs(e - e_exact))), float(np.max(e)), note))
    return Family(
        key="solver_tolerance", title="Solver tolerance (SolverOptions tol = feas_tol, AL and SQP)",
        domain=("min 1e-4·P + d s.t. P·d⁴ ≥ 2e4 (1e3 ≤ P ≤ 1e7 W, 1 ≤ d ≤ 10 m, log-scaled; interior "
                "optimum)"
                + ("" if quick else "; designs/sidescan_sonar.toml, least electrical power (optimum on the "
                   "azimuth beam's bound)") + "; error: |f − f*|/f*"),
        error_unit="relative",
        reference=("closed-form optima: d* = (4aK/b)^⅕, f* = aK/d*⁴ + b·d*" + ("" if quick else (
            "; side-scan P* = P0·10^(−m1/10) with m1 the chain's margin at 750 m at the initial design moved to "
            "the 1° beam (book eqs 12.42–12.48, as tests/report/test_report.py)"))),
        exact=exact, default=default,
        why_default=("the design optimiser's setting (AL, tol = feas_tol = 1e-8, no Newton polish): its answers "
                     "are re-evaluated exactly with the requirements tightened by 1e-7, so the feasibility "
                     "tolerance must stay below that; bench_design.py and bench_optimizer.py sweep the same "
                     "tolerances on the ore-pass model and on Hock–Schittkowski problems"),
        choices=choices, fast=_fastest_within(choices, bound, default, lambda c: meets[c.name]),
        fast_bound=(f"objective within {bound:g} relative of the closed form and scaled violation ≤ "
                    f"{violation_bound:g} (the "
                    "optimiser's tightening) on every problem (a solver setting: fidelity does not change it)"))


# --- the module's interface ----------------------------------------------------------------------


def run(quick: bool) -> List[Family]:
    """The solver families (module docstring), on small grids with few repeats when ``quick``."""
    _support.require("bench_fidelity.py", "scipy")
    # staged in this order (the trade family compiles its own step program while the others' compile)
    null, monotone, chance, tolerance, trade = run_staged(
        [interval_null, interval_monotone, chance_samples, solver_tolerance, trade_points], quick)
    families = [null, monotone, chance, trade, tolerance]
    for f in families:
        f.model_option = False  # solver and spec settings: fidelity leaves them to the spec
    return families


if __name__ == "__main__":
    main_alone(run, __doc__)
