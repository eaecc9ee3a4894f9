"""Scenes: the static structure of one evaluation.

A :class:`Scene` names the sensor family, the parts the world holds (rain, fog, dust, sea
clutter, multipath, a jammer, the sun in the field of view...) and static options (Swerling
case, detector law, waveform kind). It is hashable and is passed to JAX as *static* structure:
the traced program is built from the parts that exist, so an absent part costs nothing at all —
it is not computed as a zero, it does not appear in the jaxpr.

Numbers (ranges, powers, rain rates) never live in the scene; they are the traced parameters
of :func:`diffsense.scene.evaluate`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping

from diffsense.errors import DomainError


def _freeze_options(options) -> tuple[tuple[str, Any], ...]:
    if options is None:
        return ()
    if isinstance(options, Mapping):
        items = options.items()
    else:
        items = options
    out = []
    for key, value in items:
        if isinstance(value, list):
            value = tuple(value)
        out.append((str(key), value))
    return tuple(sorted(out))


@dataclass(frozen=True)
class Scene:
    """Static structure of an evaluation.

    ``sensor``: the sensor family, a key of :data:`diffsense.scene.CHAINS` ("radar", "lidar",
    "sonar", "radiometer", "infrared", "ultrasonic").
    ``parts``: names of the scene parts that exist (each chain documents the parts it knows).
    ``options``: static choices, e.g. ``{"swerling": 1, "detector": "square_law"}``.
    """

    sensor: str
    parts: frozenset = field(default_factory=frozenset)
    options: tuple = ()

    def __init__(self, sensor: str, parts: Iterable[str] = (), options=None):
        object.__setattr__(self, "sensor", str(sensor))
        object.__setattr__(self, "parts", frozenset(str(p) for p in parts))
        object.__setattr__(self, "options", _freeze_options(options))

    def has(self, part: str) -> bool:
        """True when the scene holds ``part``."""
        return part in self.parts

    def option(self, name: str, default=None):
        """The static option ``name`` (or ``default`` when the scene does not set it)."""
        for key, value in self.options:
            if key == name:
                return value
        return default

    def with_parts(self, *parts: str) -> "Scene":
        """A copy of the scene with ``parts`` added."""
        return Scene(self.sensor, self.parts | set(parts), self.options)

    def without_parts(self, *parts: str) -> "Scene":
        """A copy of the scene with ``parts`` removed."""
        return Scene(self.sensor, self.parts - set(parts), self.options)

    def with_options(self, **options) -> "Scene":
        """A copy of the scene with static ``options`` set or replaced."""
        merged = dict(self.options)
        merged.update(options)
        return Scene(self.sensor, self.parts, merged)

    def __repr__(self) -> str:
        parts = ", ".join(sorted(self.parts))
        opts = ", ".join(f"{k}={v!r}" for k, v in self.options)
        return f"Scene({self.sensor!r}, parts={{{parts}}}, options={{{opts}}})"


def require_known_parts(scene: Scene, known: Mapping[str, str]) -> None:
    """Raise :class:`DomainError` if the scene names a part the chain does not model."""
    unknown = sorted(scene.parts - set(known))
    if unknown:
        raise DomainError(
            f"{scene.sensor} scene: unknown part(s) {unknown}; known parts: {sorted(known)}"
        )
