"""diffsense: a differentiable sensor-design optimizer.

Importing diffsense switches JAX to 64-bit floats (``jax_enable_x64``) so every result is
float64 without the user setting a flag. Set the environment variable ``DIFFSENSE_X64=0``
before import to keep JAX's 32-bit default; functions then follow the dtype of their inputs
(float32), with the accuracy documented in each module (see ``diffsense.detection``).
"""

import os as _os

import jax as _jax

if _os.environ.get("DIFFSENSE_X64", "1") != "0":
    _jax.config.update("jax_enable_x64", True)

__version__ = "0.1.0"
