"""Scenes and the registry of sensor kinds: the entry point of every evaluation.

A :class:`Scene` (defined in :mod:`diffsense.sensors.structure`) is static structure: the sensor
kind, the parts the world holds and static options. :data:`CHAINS` maps each sensor kind to its
chain — an explicit list of the sensor packages, no plug-in loading — and :func:`evaluate` turns a
scene and named parameters (SI units, dB explicit) into an
:class:`~diffsense.sensors.chain.Evaluation`: a link budget of named dB terms and named outputs.
Numbers never live in the scene; they are the traced parameters, so ``evaluate`` is
jit/vmap/grad-able in every one of them while an absent part is not in the program at all.

>>> from diffsense.scene import Scene, evaluate
>>> ev = evaluate(Scene("radar", [], {"antenna": "specified", "matched_filter": "matched"}),
...               range_m=10e3, peak_power_w=1e3, pulse_width_s=1e-6, freq_hz=10e9,
...               bandwidth_hz=1e6, gain_db=30.0, beamwidth_az_deg=3.0, beamwidth_el_deg=3.0,
...               noise_figure_db=3.0, prf_hz=1e3, n_pulses=1, pd=0.9, pfa=1e-6)
>>> round(float(ev["snr_db"]), 2)
7.54

which is the radar equation Pt G² λ² σ / ((4π)³ R⁴ k T0 β F) with σ = 1 m² (the default):

>>> import math
>>> lam = 299792458.0 / 10e9
>>> round(10 * math.log10(1e3 * 1e3**2 * lam**2 / ((4 * math.pi)**3 * 1e4**4 * 1.380649e-23 * 290.0 * 1e6 * 10**0.3)), 2)
7.54
"""

from __future__ import annotations

import functools
from typing import Callable, Dict, Mapping, Optional

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range, is_concrete
from diffsense.sensors.chain import Chain, Evaluation, Output, Param
from diffsense.sensors.fmcw import FmcwChain
from diffsense.sensors.infrared import InfraredChain
from diffsense.sensors.lidar import LidarChain
from diffsense.sensors.radar import RadarChain
from diffsense.sensors.radiometer import RadiometerChain
from diffsense.sensors.sonar import SonarChain
from diffsense.sensors.structure import Scene
from diffsense.sensors.ultrasonic import UltrasonicChain

__all__ = ["Scene", "CHAINS", "sensor_kinds", "chain_for", "complete_parameters", "check_values", "evaluate", "evaluator", "describe", "describe_kind",
           "parameter_table", "output_table", "number_text", "domain_text", "describe_command",
           "unknown_name_hint"]

CHAINS: Dict[str, Chain] = {chain.kind: chain for chain in (
    RadarChain(), LidarChain(), SonarChain(), RadiometerChain(), InfraredChain(), UltrasonicChain(), FmcwChain())}
"""Sensor kind -> its chain: every sensor diffsense models."""


def sensor_kinds() -> list:
    """Names of the sensor kinds, sorted."""
    return sorted(CHAINS)


def chain_for(scene: Scene) -> Chain:
    """The chain of ``scene.sensor``, validated against the scene."""
    if scene.sensor not in CHAINS:
        raise DomainError(f"unknown sensor kind {scene.sensor!r}; known kinds: {sorted(CHAINS)}")
    chain = CHAINS[scene.sensor]
    chain.validate_scene(scene)
    return chain


def complete_parameters(scene: Scene, params: Mapping[str, object]) -> Dict[str, jnp.ndarray]:
    """Fill defaults, reject unknown or missing names, check concrete values against domains."""
    return {name: jnp.asarray(value, dtype=float) for name, value in _filled(scene, params, checked=True).items()}


def _filled(scene: Scene, params: Mapping[str, object], *, checked: bool) -> Dict[str, object]:
    """``params`` with the defaults of the missing names, as given (no conversion); unknown or
    missing names raise :class:`DomainError`, and with ``checked`` so does a concrete value
    outside its parameter's domain."""
    chain = chain_for(scene)
    spec = chain.parameters(scene)
    unknown = sorted(set(params) - set(spec))
    if unknown:
        raise DomainError(
            f"{scene.sensor} scene {sorted(scene.parts)}: unknown parameter(s) {unknown}; "
            f"known: {sorted(spec)}"
        )
    out = {}
    missing = []
    for name, prm in spec.items():
        if name in params:
            value = params[name]
        elif prm.default is not None:
            value = prm.default
        else:
            missing.append(name)
            continue
        if checked and is_concrete(value):
            check_range(name, value, prm.lo, prm.hi, lo_open=prm.lo_open, hi_open=prm.hi_open,
                        where=f"{scene.sensor} chain")
        out[name] = value
    if missing:
        raise DomainError(f"{scene.sensor} scene: missing required parameter(s) {missing}")
    return out


def compute(scene: Scene, params: Mapping[str, jnp.ndarray], wanted=None) -> Evaluation:
    """The chain of ``scene`` at the complete parameter dict ``params`` with outputs ``wanted``
    (None: every output), as a jitted call: inside a traced program the chain's Python code is
    traced once per (scene, wanted, parameter shapes) and reused by every other call site and
    program of the process (JAX keeps the traced sub-program), which shortens the tracing of
    programs that evaluate a chain in several places. No domain check runs here: the values are
    traced. Use :func:`evaluate` for a checked evaluation of concrete values."""
    return _compute(dict(params), scene=scene, wanted=None if wanted is None else frozenset(wanted))


@functools.partial(jax.jit, static_argnames=("scene", "wanted"))
def _compute(params, scene, wanted):
    return chain_for(scene).compute(scene, params, wanted=wanted)


def evaluate(scene: Scene, params: Optional[Mapping[str, object]] = None, **kwargs) -> Evaluation:
    """Evaluate the chain of ``scene`` at the named parameters (keyword or mapping).

    Returns an :class:`Evaluation` with the link budget and the named outputs. Pure and
    jit/vmap/grad-able in the parameter values; ``scene`` is static.
    """
    merged = dict(params or {})
    merged.update(kwargs)
    chain = chain_for(scene)
    p = complete_parameters(scene, merged)
    return chain.compute(scene, p)


def check_values(scene: Scene, params: Mapping[str, float]) -> None:
    """Raise :class:`~diffsense.errors.DomainError` when plain-number ``params`` hold values the
    chain of ``scene`` rejects together and can tell without evaluating (no JAX program). Each
    value's own domain is not checked here (a spec's loader checks every value alone); the values
    reach the chain as NumPy float64 numbers, so no JAX operation runs."""
    values = _filled(scene, dict(params), checked=False)
    chain_for(scene).check_values(scene, {name: np.asarray(v, dtype=float) for name, v in values.items()})


@functools.lru_cache(maxsize=256)
def evaluator(scene: Scene) -> Callable:
    """A jitted ``params -> Evaluation`` for ``scene`` (cached per scene).

    ``params`` must hold every parameter (see :func:`complete_parameters`).
    """
    chain = chain_for(scene)
    return jax.jit(lambda p: chain.compute(scene, p))


def parameter_table(scene: Scene) -> Dict[str, Param]:
    """The parameters a scene takes (name -> :class:`Param`)."""
    return chain_for(scene).parameters(scene)


def output_table(scene: Scene) -> Dict[str, Output]:
    """The outputs a scene produces (name -> :class:`Output`)."""
    return chain_for(scene).outputs(scene)




def number_text(value) -> str:
    """The shortest decimal text that reads back as the same float (no NumPy repr, no rounding
    that would make a printed bound lie).

    >>> number_text(1.0 - 1e-12), number_text(1e-300), number_text(2.0), number_text(0.1)
    ('0.999999999999', '1e-300', '2', '0.1')
    """
    x = float(value)
    if x != x or x in (float("inf"), float("-inf")):
        return str(x)
    for digits in range(6, 18):
        text = f"{x:.{digits}g}"
        if float(text) == x:
            return text
    return repr(x)


def domain_text(p: Param) -> str:
    """The documented domain of parameter ``p`` as an interval, its ends printed exactly.

    >>> domain_text(Param("pd", "1", "", lo=0.0, hi=1.0 - 1e-12, lo_open=True))
    '(0, 0.999999999999]'
    """
    lo = "-inf" if p.lo is None else number_text(p.lo)
    hi = "inf" if p.hi is None else number_text(p.hi)
    left = "(" if p.lo is None or p.lo_open else "["
    right = ")" if p.hi is None or p.hi_open else "]"
    return f"{left}{lo}, {hi}{right}"


def describe_command(scene: Scene) -> str:
    """The ``diffsense describe`` command line that lists what ``scene`` takes and gives.

    >>> describe_command(Scene("radar", ["rain", "dust"], {"swerling": 1}))
    'diffsense describe radar --parts dust,rain --option swerling=1'
    """
    text = f"diffsense describe {scene.sensor}"
    if scene.parts:
        text += " --parts " + ",".join(sorted(scene.parts))
    for key, value in scene.options:
        text += f" --option {key}={value}"
    return text


def unknown_name_hint(scene: Scene, name: str) -> str:
    """Why ``name`` is not a parameter of ``scene``, when the chain knows better than a spelling
    match: it is an output (computed, not set), a budget term set by a static option, or a
    parameter of a part the scene does not hold. ``""`` when none applies.

    >>> unknown_name_hint(Scene("radar"), "matched_filter_loss_db")
    "'matched_filter_loss_db' is set by the static option matched_filter (here 'two_tuned', the default; one of 'matched', 'rectangular', 'gaussian', 'single_tuned', 'two_tuned', 'three_tuned', 'four_tuned', 'five_tuned'): choose the option under [options], not the value"
    >>> unknown_name_hint(Scene("radar"), "rain_rate_mm_h")
    "'rain_rate_mm_h' belongs to the part 'rain', which this scene does not hold (add it to parts)"
    """
    chain = chain_for(scene)
    if name in chain.outputs(scene):
        return f"'{name}' is an output of the {scene.sensor} chain (computed from the parameters); it cannot be set"
    for option, (default, allowed) in chain.options.items():
        if name == option or name.startswith(option + "_"):
            current = scene.option(option, default)
            how = "the default" if (option, current) not in scene.options else "set in the scene"
            values = ", ".join(repr(v) for v in allowed)
            return (f"'{name}' is set by the static option {option} (here {current!r}, {how}; one of "
                    f"{values}): choose the option under [options], not the value")
    for part in chain.parts:
        if part in scene.parts:
            continue
        try:
            table = chain.parameters(Scene(scene.sensor, sorted(scene.parts | {part}), dict(scene.options)))
        except DomainError:
            continue
        if name in table:
            return f"'{name}' belongs to the part '{part}', which this scene does not hold (add it to parts)"
    return ""


def describe_kind(scene: Scene) -> dict:
    """What a scene's sensor kind offers whatever its parts: the kind, its description, every
    part it knows (with whether the scene holds it) and every static option (default, allowed
    values, the value the scene sets) — the first keys of :func:`describe`, available for a scene
    that holds too few parts to have parameters and outputs.

    >>> sorted(describe_kind(Scene("sonar"))["parts"])[:2]
    ['bottom_reverberation', 'receiver_noise']
    """
    chain = CHAINS[scene.sensor]
    return {
        "sensor": scene.sensor,
        "description": chain.description,
        "parts": {name: {"description": text, "in_scene": scene.has(name)} for name, text in chain.parts.items()},
        "options": {name: {"default": default, "values": list(allowed), "value": scene.option(name, default)}
                    for name, (default, allowed) in chain.options.items()},
    }


def describe(scene: Scene) -> dict:
    """What a scene takes and gives, as plain data: its sensor kind, every part the kind knows
    (with whether the scene holds it), every static option (default, allowed values, the value the
    scene sets), the parameters it takes (unit, default, domain, part, meaning) and the outputs it
    produces (unit, meaning). Used by ``diffsense describe`` and by error messages.

    >>> d = describe(Scene("radar", ["rain"]))
    >>> d["options"]["matched_filter"]["default"], d["parts"]["rain"]["in_scene"]
    ('two_tuned', True)
    >>> d["parameters"]["rain_rate_mm_h"]["unit"], d["parameters"]["rain_rate_mm_h"]["part"]
    ('mm/h', 'rain')
    """
    chain = chain_for(scene)
    params = chain.parameters(scene)
    outputs = chain.outputs(scene)

    return {
        **describe_kind(scene),
        "parameters": {name: {"unit": p.unit, "default": p.default, "domain": domain_text(p), "part": p.part,
                              "integer": p.integer, "doc": p.doc} for name, p in params.items()},
        "outputs": {name: {"unit": o.unit, "doc": o.doc} for name, o in outputs.items()},
    }
