"""``[options] fidelity = "exact" | "fast"``: the model choices a spec's chains use.

``"exact"`` (the default) keeps every option as the spec (or the chain's default) sets it. ``"fast"``
takes, for every option the spec leaves at its default, the fastest choice whose worst error on
the run-time-against-error atlas (``python benchmarks/bench_fidelity.py``, ``docs/speed_accuracy.md``)
stays within the bound :data:`FAST_OPTIONS` states for it — so a user exploring thousands of designs
goes fast, and ``optimize`` re-evaluates the answer with the exact choices and reports the difference
(:func:`exact_spec`). An option the spec sets explicitly is never changed.

A fast choice takes the same parameters as the exact one (the spec's ``[fixed]`` values mean the
same under both), which :func:`fast_options` relies on and the tests check.
"""

from __future__ import annotations

import dataclasses
from typing import Dict, Mapping, Tuple

from diffsense.design.spec.common import echo
from diffsense.errors import DomainError, SpecError
from diffsense.scene import CHAINS, Scene

FIDELITY_VALUES = ("exact", "fast")

#: sensor -> option -> (fast value, the atlas family and bound that admit it): the fastest choice
#: of the family within 0.01 dB (0.01 dB/km) of the reference over its domain on the atlas
#: (docs/speed_accuracy.md). Only detectability has one: the Chebyshev interpolant of the exact
#: requirement (within 1.2e-4 dB of the exact solver); no other family's faster choice meets it.
FAST_OPTIONS: Dict[str, Dict[str, Tuple[str, str]]] = {
    "radar": {"detectability": ("chebyshev", "detectability: 0.01 dB against the mpmath reference")},
}


def read_fidelity(file, options: Mapping) -> str:
    """The spec's ``options.fidelity`` ("exact" when absent); raise :class:`SpecError` otherwise."""
    value = options.get("fidelity", "exact")
    if not (isinstance(value, str) and value in FIDELITY_VALUES):
        raise SpecError(file, "options.fidelity", f"must be one of {', '.join(map(echo, FIDELITY_VALUES))} "
                        f"(default {echo('exact')}); got {echo(value)}")
    return value


def fast_options(sensor: str, options: Mapping) -> Tuple[dict, Dict[str, str]]:
    """``(options with the fast choices, {option: fast value})`` for the options ``options`` does
    not set (:data:`FAST_OPTIONS`). A fast choice the chain refuses beside the spec's other
    options (the Chebyshev detectability with M-of-N integration, say) is not taken: the spec
    keeps the exact choice there."""
    out = dict(options)
    switched = {}
    for name, (value, _) in FAST_OPTIONS.get(sensor, {}).items():
        if name not in options and name in CHAINS[sensor].options and _accepted(sensor, dict(out, **{name: value})):
            out[name] = value
            switched[name] = value
    return out, switched


def _accepted(sensor: str, options: Mapping) -> bool:
    """Whether the chain of ``sensor`` accepts these options together (no parts)."""
    try:
        CHAINS[sensor].validate_scene(Scene(sensor, [], dict(options)))
    except (DomainError, SpecError, ValueError):
        return False
    return True


def exact_spec(spec):
    """``spec`` with every option :func:`fast_options` switched put back to the chain's default:
    the spec the exact re-evaluation of a ``fidelity = "fast"`` answer uses."""
    if not spec.fidelity_switched:
        return spec
    defaults = CHAINS[spec.sensor].options
    scenes = {}
    for case, scene in spec.scenes.items():
        opts = dict(scene.options)
        for name in spec.fidelity_switched:
            opts[name] = defaults[name][0]
        scenes[case] = Scene(scene.sensor, list(scene.parts), opts)
    return dataclasses.replace(spec, scenes=scenes, fidelity="exact", fidelity_switched={})


__all__ = ["FIDELITY_VALUES", "FAST_OPTIONS", "read_fidelity", "fast_options", "exact_spec"]
