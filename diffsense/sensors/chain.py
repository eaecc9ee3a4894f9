"""The chain framework: named link budgets built from a static :class:`~diffsense.scene.Scene`.

A *chain* is one sensor family's complete evaluation: from named parameters (SI units, dB
explicit) to a :class:`Budget` of named dB terms (the book's link-budget tables) and a dict of
named outputs (SNR, SCR, Pd, detection range, resolutions...). Each sensor package defines one
:class:`Chain` subclass; :mod:`diffsense.scene` lists them in its registry and
:func:`diffsense.scene.evaluate` is the single entry point.

Static versus traced: the scene (which parts exist, Swerling case, detector) is static; the
parameter values are traced, so an evaluation is jit/vmap/grad-able in every numeric parameter.
Part computations are named sub-programs (:mod:`diffsense.sensors.parts`).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import ClassVar, Dict, FrozenSet, Iterable, Mapping, Optional, Tuple

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.sensors.structure import Scene, require_known_parts


@dataclass(frozen=True)
class Param:
    """One named numeric parameter of a chain.

    ``unit`` is a units-library string ("W", "m", "s", "Hz", "K", "dB", "m^2", "1" for
    dimensionless). ``default`` is used when the caller omits the parameter (``None``: the
    parameter is required). ``lo``/``hi`` bound the documented domain. ``part`` names the scene
    part the parameter belongs to (``None``: always present). ``integer`` marks counts that a
    solver relaxes to real values.
    """

    name: str
    unit: str
    doc: str
    default: Optional[float] = None
    lo: Optional[float] = None
    hi: Optional[float] = None
    lo_open: bool = False
    hi_open: bool = False
    part: Optional[str] = None
    integer: bool = False


@dataclass(frozen=True)
class Output:
    """One named output of a chain, with its unit and meaning."""

    name: str
    unit: str
    doc: str


@jax.tree_util.register_pytree_node_class
class Budget:
    """Ordered, named link-budget terms in dB whose sum is ``total`` (e.g. SNR in dB).

    Each term is a signed contribution: gains positive, losses and noise negative, exactly as
    the book's link-budget tables read from top to bottom. The order is static structure.
    """

    def __init__(self, names: Tuple[str, ...], values: Tuple):
        self.names = tuple(names)
        self.values = tuple(values)

    def tree_flatten(self):
        return self.values, self.names

    @classmethod
    def tree_unflatten(cls, names, values):
        return cls(names, values)

    @property
    def total(self):
        """Sum of the terms (dB)."""
        return functools.reduce(jnp.add, self.values)

    def as_dict(self) -> Dict[str, jnp.ndarray]:
        """Terms as an ordered ``{name: dB}`` dict."""
        return dict(zip(self.names, self.values))

    def __getitem__(self, name):
        return self.values[self.names.index(name)]

    def __len__(self):
        return len(self.names)

    def __repr__(self) -> str:
        rows = []
        for name, value in zip(self.names, self.values):
            try:
                rows.append(f"  {name:<40s} {float(np.asarray(value)):+10.2f} dB")
            except TypeError:
                rows.append(f"  {name:<40s} {value}")
        return "Budget(\n" + "\n".join(rows) + "\n)"


class BudgetBuilder:
    """Collects ``(name, dB)`` terms in order; ``build()`` returns a :class:`Budget`."""

    def __init__(self):
        self._names = []
        self._values = []

    def add(self, name: str, value_db):
        """Append a signed term (dB) and return its value."""
        if name in self._names:
            raise ValueError(f"budget term {name!r} added twice")
        self._names.append(name)
        self._values.append(jnp.asarray(value_db, dtype=float))
        return self._values[-1]

    def build(self) -> Budget:
        return Budget(tuple(self._names), tuple(self._values))


@jax.tree_util.register_pytree_node_class
class Evaluation:
    """Result of :func:`evaluate`: a :class:`Budget` (or ``None``) and a dict of named outputs."""

    def __init__(self, budget: Optional[Budget], values: Dict[str, jnp.ndarray]):
        self.budget = budget
        self.values = dict(values)

    def tree_flatten(self):
        keys = tuple(self.values)
        return (self.budget, tuple(self.values[k] for k in keys)), keys

    @classmethod
    def tree_unflatten(cls, keys, children):
        budget, vals = children
        return cls(budget, dict(zip(keys, vals)))

    def __getitem__(self, name):
        return self.values[name]

    def __repr__(self) -> str:
        lines = [repr(self.budget)] if self.budget is not None else []
        for k, v in self.values.items():
            try:
                lines.append(f"{k} = {float(np.asarray(v)):.6g}")
            except TypeError:
                lines.append(f"{k} = {v}")
        return "\n".join(lines)


# --- chains ----------------------------------------------------------------------------------


class Chain:
    """Base class of a sensor family's chain.

    Subclasses set ``kind``, ``parts`` ({part: description}), ``options``
    ({option: (default, allowed values)}) and implement :meth:`parameters`, :meth:`outputs` and
    :meth:`compute` (which receives a dict of float64 arrays with defaults filled in and may call
    ``scene.has(part)`` to decide, at trace time, which parts to build).

    ``compute(scene, p, wanted=None)`` takes the static keyword ``wanted``: ``None`` asks for
    every output of :meth:`outputs`; a frozenset of output names asks for those only. The chain
    then returns at least those names (it may return more), with the values of the full
    evaluation, and leaves out of the trace the expensive computations (root finds, detection
    series, exact detectability solves) that no wanted output depends on, so that a caller who
    differentiates a few outputs does not trace, differentiate and lower the rest. Like the
    scene, ``wanted`` is static structure: decide with :func:`needs` at trace time.
    """

    kind: ClassVar[str] = ""
    description: ClassVar[str] = ""
    parts: ClassVar[Mapping[str, str]] = {}
    options: ClassVar[Mapping[str, Tuple[object, tuple]]] = {}
    #: the chain's scenes may be drawn on a range-height coverage chart (:meth:`coverage_chart_reason`)
    draws_coverage: ClassVar[bool] = False

    def parameters(self, scene: Scene) -> Dict[str, Param]:  # pragma: no cover - abstract
        raise NotImplementedError

    def outputs(self, scene: Scene) -> Dict[str, Output]:  # pragma: no cover - abstract
        raise NotImplementedError

    def compute(self, scene: Scene, p: Mapping[str, jnp.ndarray],
                wanted: Optional[FrozenSet[str]] = None) -> Evaluation:  # pragma: no cover - abstract
        raise NotImplementedError

    def check_values(self, scene: Scene, p: Mapping[str, float]) -> None:
        """Raise :class:`DomainError` for plain-number parameter values ``p`` that the chain
        rejects together and can tell without being evaluated (NumPy only: a spec's corners are
        checked this way before any program is compiled); none by default."""

    def coverage_chart_reason(self, scene: Scene) -> Optional[str]:
        """``None`` when a range-height coverage chart over the refracting 4/3 earth (Blake 1986)
        describes ``scene`` — a beam looking along the earth's surface through the atmosphere, whose
        margin the chain gives against range — else why it does not (a sentence for the report).
        Chains that can be drawn so override it; the report asks the chain, never the sensor name."""
        return (f"a Blake range-height chart describes a radar beam over the refracting atmosphere; it does not "
                f"apply to the {self.kind} chain")

    # shared helpers
    def option(self, scene: Scene, name: str):
        default, _ = self.options[name]
        return scene.option(name, default)

    def validate_scene(self, scene: Scene) -> None:
        require_known_parts(scene, self.parts)
        for key, value in scene.options:
            if key not in self.options:
                raise DomainError(
                    f"{self.kind} scene: unknown option {key!r}; known options: {sorted(self.options)}"
                )
            allowed = self.options[key][1]
            if allowed and value not in allowed:
                raise DomainError(
                    f"{self.kind} scene: option {key!r} must be one of {list(allowed)}; got {value!r}"
                )


def needs(wanted: Optional[FrozenSet[str]], *names: str) -> bool:
    """True when a chain must compute something that the outputs ``names`` depend on: ``wanted``
    is ``None`` (every output) or holds one of ``names`` (see :class:`Chain`)."""
    return wanted is None or any(n in wanted for n in names)


def collect(params: Iterable[Param]) -> Dict[str, Param]:
    """``{p.name: p}`` for a list of parameters (helper for chain definitions)."""
    return {p.name: p for p in params}
