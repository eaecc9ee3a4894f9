"""diffsense: a differentiable sensor-design optimizer.

The public face, one name per job::

    from diffsense import Scene, evaluate                 # a sensor chain at named parameters
    from diffsense import load_spec, DesignModel          # a requirement spec and its model
    from diffsense import optimize_design, build_report   # the optimum, and its report
    from diffsense import DomainError, SpecError, UnitError

The layers, data flowing one way: :mod:`diffsense.numerics` → :mod:`diffsense.physics` →
:mod:`diffsense.detection` → :mod:`diffsense.sensors` → :mod:`diffsense.scene` →
:mod:`diffsense.design` → :mod:`diffsense.report` → :mod:`diffsense.cli`, with the generic
solvers of :mod:`diffsense.optimize` used by the design layer.

Importing diffsense switches JAX to 64-bit floats (``jax_enable_x64``) so every result is
float64 without the user setting a flag. Set the environment variable ``DIFFSENSE_X64=0``
before import to keep JAX's 32-bit default; functions then follow the dtype of their inputs
(float32), with the accuracy documented in each module (see ``diffsense.detection``).

The names are imported on first use, so ``import diffsense.detection`` does not load the
sensors, the optimizer or matplotlib.
"""

import os as _os

if _os.environ.get("DIFFSENSE_X64", "1") != "0":
    import jax as _jax

    _jax.config.update("jax_enable_x64", True)

__version__ = "0.1.0"

__all__ = ["Scene", "evaluate", "load_spec", "DesignModel", "optimize_design", "build_report",
           "DomainError", "SpecError", "UnitError", "explore", "__version__"]


def __getattr__(name):
    # PEP 562: resolve the public names on first use (each branch is an ordinary import)
    if name in ("Scene", "evaluate"):
        from diffsense import scene as _m
    elif name == "load_spec":
        from diffsense.design import spec as _m
    elif name == "DesignModel":
        from diffsense.design import model as _m
    elif name == "optimize_design":
        from diffsense.design import optimizer as _m
    elif name == "explore":
        import diffsense.explore as _m
    elif name == "build_report":
        from diffsense import report as _m
    elif name in ("DomainError", "SpecError", "UnitError"):
        from diffsense import errors as _m
    else:
        raise AttributeError(f"module 'diffsense' has no attribute {name!r}")
    value = getattr(_m, name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
