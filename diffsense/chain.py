"""Sensor chains: named link budgets built from a static :class:`~diffsense.scene.Scene`.

A *chain* is one sensor family's complete evaluation: from named parameters (SI units, dB
explicit) to a :class:`Budget` of named dB terms (the book's link-budget tables) and a dict of
named outputs (SNR, SCR, Pd, detection range, resolutions...). Each family registers one
:class:`Chain` in :data:`CHAINS`; :func:`evaluate` is the single entry point.

Static versus traced: the scene (which parts exist, Swerling case, detector) is static; the
parameter values are traced, so ``evaluate`` is jit/vmap/grad-able in every numeric parameter.
Computations belonging to one scene part are wrapped by :func:`scene_part`: each becomes a
named sub-program (``pjit`` with name ``part_<part>__<function>``) in the jaxpr, which lets
:func:`traced_parts` list exactly which parts a traced evaluation contains.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Callable, ClassVar, Dict, FrozenSet, Iterable, Mapping, Optional, Tuple

import jax
import jax.extend.core as _jcore
import jax.numpy as jnp
import numpy as np

from ._checks import DomainError, check_range, is_concrete
from .scene import Scene, require_known_parts


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


# --- scene parts ---------------------------------------------------------------------------

_PART_OF_NAME: Dict[str, str] = {}


def scene_part(part: str) -> Callable:
    """Decorator: mark a function as computing (a term of) the scene part ``part``.

    The function is wrapped in ``jax.jit`` under the name ``part_<part>__<function>``, so it
    shows as one named sub-program in the jaxpr of any evaluation that calls it. Chains call
    part functions only when the scene holds the part.
    """

    def decorate(fn):
        name = f"part_{part}__{fn.__name__}"

        @functools.wraps(fn)
        def inner(*args, **kwargs):
            return fn(*args, **kwargs)

        inner.__name__ = name
        inner.__qualname__ = name
        _PART_OF_NAME[name] = part
        return jax.jit(inner)

    return decorate


def _sub_jaxprs(eqn):
    for value in eqn.params.values():
        candidates = value if isinstance(value, (tuple, list)) else (value,)
        for c in candidates:
            if isinstance(c, _jcore.ClosedJaxpr):
                yield c.jaxpr
            elif isinstance(c, _jcore.Jaxpr):
                yield c


def traced_parts(jaxpr) -> set:
    """Names of the scene parts whose sub-programs occur in ``jaxpr`` (searched recursively)."""
    found = set()
    stack = [getattr(jaxpr, "jaxpr", jaxpr)]
    while stack:
        jx = stack.pop()
        for eqn in jx.eqns:
            name = eqn.params.get("name")
            if isinstance(name, str) and name in _PART_OF_NAME:
                found.add(_PART_OF_NAME[name])
            stack.extend(_sub_jaxprs(eqn))
    return found


def count_equations(jaxpr) -> int:
    """Number of primitive equations in ``jaxpr`` including nested sub-programs."""
    total = 0
    stack = [getattr(jaxpr, "jaxpr", jaxpr)]
    while stack:
        jx = stack.pop()
        for eqn in jx.eqns:
            subs = list(_sub_jaxprs(eqn))
            if subs:
                stack.extend(subs)
            else:
                total += 1
    return total


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

    def parameters(self, scene: Scene) -> Dict[str, Param]:  # pragma: no cover - abstract
        raise NotImplementedError

    def outputs(self, scene: Scene) -> Dict[str, Output]:  # pragma: no cover - abstract
        raise NotImplementedError

    def compute(self, scene: Scene, p: Mapping[str, jnp.ndarray],
                wanted: Optional[FrozenSet[str]] = None) -> Evaluation:  # pragma: no cover - abstract
        raise NotImplementedError

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


CHAINS: Dict[str, Chain] = {}


def register(chain_cls):
    """Class decorator: register a chain under its ``kind``."""
    CHAINS[chain_cls.kind] = chain_cls()
    return chain_cls


_LOADED: list = []
_FAMILY_MODULES = ("radar", "lidar", "sonar", "radiometer", "infrared", "ultrasonic")


def _load_chains():
    """Import the family modules (once); importing a module registers its chain."""
    if _LOADED:
        return
    import importlib
    import importlib.util

    for name in _FAMILY_MODULES:
        if importlib.util.find_spec(f"{__package__}.{name}") is not None:
            importlib.import_module(f"{__package__}.{name}")
    _LOADED.append(True)


def sensor_kinds() -> list:
    """Names of the registered sensor chains."""
    _load_chains()
    return sorted(CHAINS)


def chain_for(scene: Scene) -> Chain:
    """The registered chain of ``scene.sensor`` (validated against the scene)."""
    _load_chains()
    if scene.sensor not in CHAINS:
        raise DomainError(f"unknown sensor kind {scene.sensor!r}; known kinds: {sorted(CHAINS)}")
    chain = CHAINS[scene.sensor]
    chain.validate_scene(scene)
    return chain


def complete_parameters(scene: Scene, params: Mapping[str, object]) -> Dict[str, jnp.ndarray]:
    """Fill defaults, reject unknown or missing names, check concrete values against domains."""
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
        if is_concrete(value):
            check_range(name, value, prm.lo, prm.hi, lo_open=prm.lo_open, hi_open=prm.hi_open,
                        where=f"{scene.sensor} chain")
        out[name] = jnp.asarray(value, dtype=float)
    if missing:
        raise DomainError(f"{scene.sensor} scene: missing required parameter(s) {missing}")
    return out


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


def collect(params: Iterable[Param]) -> Dict[str, Param]:
    """``{p.name: p}`` for a list of parameters (helper for chain definitions)."""
    return {p.name: p for p in params}
