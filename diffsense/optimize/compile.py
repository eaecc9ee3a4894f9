"""Compiling the solvers: XLA option presets, jit with them, and compiling in the background.

The solvers are loop-heavy programs (nested ``lax.while_loop``s around a model evaluation),
and XLA's compile time dominates a first solve. Two XLA:CPU options change that a lot
(measured on the design problems during development): disabling the fusion emitters cuts
compile time by ~40 % at equal run time ("optimized", the default); optimisation level 0
cuts it ~3x more at ~1.5x run time ("fast", for tests and one-off solves).
"""

from __future__ import annotations

import concurrent.futures

import jax

from diffsense.numerics.checks import check_choice

_COMPILE_PRESETS = {
    "optimized": {"xla_cpu_use_fusion_emitters": False},
    "fast": {"xla_cpu_use_fusion_emitters": False, "xla_backend_optimization_level": 0},
    "default": {},
}
_ACCEPTED: dict = {}


def compiler_options(preset: str = "optimized") -> dict:
    """XLA compiler options of a preset ("optimized", "fast" or "default"), or {} when the
    installed jaxlib rejects them (checked once on a trivial program)."""
    check_choice("preset", preset, tuple(_COMPILE_PRESETS), where="compiler_options")
    if preset not in _ACCEPTED:
        opts = _COMPILE_PRESETS[preset]
        try:
            jax.jit(lambda a: a + 1.0).lower(1.0).compile(compiler_options=opts) if opts else None
            _ACCEPTED[preset] = dict(opts)
        except Exception:  # an older/newer XLA without these flags: compile with defaults
            _ACCEPTED[preset] = {}
    return dict(_ACCEPTED[preset])


def preset_options(preset: str = "optimized") -> dict:
    """The XLA options a preset asks for, unchecked (what a program compiled with the preset
    was compiled with when :func:`compiler_options` accepted them)."""
    check_choice("preset", preset, tuple(_COMPILE_PRESETS), where="preset_options")
    return dict(_COMPILE_PRESETS[preset])


def jit_with_options(fn, preset: str = "optimized", **jit_kwargs):
    """``jax.jit(fn, **jit_kwargs)`` with the XLA options of ``preset`` (see
    :func:`compiler_options`); plain ``jax.jit`` on JAX versions without ``compiler_options``."""
    opts = compiler_options(preset)
    if opts:
        try:
            return jax.jit(fn, compiler_options=opts, **jit_kwargs)
        except TypeError:
            pass
    return jax.jit(fn, **jit_kwargs)


def call_compiling_alongside(jitted, args, alongside):
    """``jitted(*args)``, its XLA compilation run in a background thread while this thread
    calls ``alongside()`` (e.g. tracing and compiling another program): XLA compiles without
    holding Python's global interpreter lock, so the two share the machine's cores. The
    program is the one a plain call would compile; later calls reuse it."""
    lowered = jitted.lower(*args)
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        compiling = pool.submit(lowered.compile)
        alongside()
        executable = compiling.result()
    return executable(*args)


__all__ = ["compiler_options", "preset_options", "jit_with_options", "call_compiling_alongside"]
