"""Scene parts as named sub-programs, and what a traced evaluation contains.

Computations belonging to one scene part are wrapped by :func:`scene_part`: each becomes a
named sub-program (``pjit`` with name ``part_<part>__<function>``) in the jaxpr, which lets
:func:`traced_parts` list exactly which parts a traced evaluation contains and
:func:`count_equations` measure its size. Chains call a part's functions only when the scene
holds the part, so an absent part is not in the program at all.
"""

from __future__ import annotations

import functools
from typing import Callable, Dict

import jax

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
    # imported here: jax.extend pulls in Pallas (0.13 s), which only this inspection needs
    import jax.extend.core as _jcore

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


