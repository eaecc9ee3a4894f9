"""Free-space spreading and path loss.

* Friis free-space path loss L = (4 pi R / lambda)^2, in dB 20 log10(4 pi R / lambda).
* Isotropic spherical spreading 4 pi R^2 (one way, m^2); a monostatic radar sees it twice:
  (4 pi R^2)^2, i.e. 10 log10((4 pi)^2 R^4) dB re 1 m^4 — the 40 log10 R of the radar equation
  (Brooker §9.9.1 writes Pr = 87.14 - 40 log10 R).
* Uniform atmospheric loss over a two-way path: 2 alpha R (alpha one way, dB/km).
Sources: Friis (1946), Proc. IRE 34:254; Skolnik, *Radar Handbook* (3rd ed.), ch. 1.

In engineering units the Friis loss is the familiar 20 log10 d[km] + 20 log10 f[MHz] + 32.45 dB:

>>> float(free_space_path_loss_db(1e3, 1e9))      # 1 km at 1 GHz: 0 + 60 + 32.45
92.45
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import db10, db20
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S

__all__ = [
    "free_space_path_loss_db",
    "isotropic_spreading_loss_db",
    "two_way_spreading_loss_db",
    "atmospheric_two_way_loss_db",
]

_WHERE = "free-space propagation"


def free_space_path_loss_db(range_m, freq_hz):
    """Friis free-space path loss 20 log10(4 pi R f / c) (dB, one way, isotropic antennas).

    ``range_m`` R (m) > 0 (far field assumed); ``freq_hz`` f (Hz) > 0. Exact (c = 299792458 m/s).

    >>> import math
    >>> float(free_space_path_loss_db(10e3, 10e9)), 20 * math.log10(4 * math.pi * 10e3 * 10e9 / 299792458.0)
    (132.4478, 132.4478)
    """
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=_WHERE)
    check_range("freq_hz", freq_hz, 0.0, None, lo_open=True, where=_WHERE)
    r = jnp.asarray(range_m, dtype=float)
    f = jnp.asarray(freq_hz, dtype=float)
    return db20(4.0 * jnp.pi * r * f / SPEED_OF_LIGHT_M_S)


def isotropic_spreading_loss_db(range_m):
    """One-way isotropic spreading 10 log10(4 pi R^2) (dB re 1 m^2); ``range_m`` R (m) > 0.

    >>> import math
    >>> float(isotropic_spreading_loss_db(1e3)), 10 * math.log10(4 * math.pi) + 60.0
    (70.9921, 70.9921)
    """
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=_WHERE)
    r = jnp.asarray(range_m, dtype=float)
    return db10(4.0 * jnp.pi * r**2)


def two_way_spreading_loss_db(range_m):
    """Two-way (radar) spreading 10 log10((4 pi R^2)^2) = 40 log10 R + 21.98 dB (dB re 1 m^4).

    ``range_m`` R (m) > 0. Exact. Source: radar equation, e.g. Brooker §9.9.1.

    >>> import math
    >>> float(two_way_spreading_loss_db(1.0)), 20 * math.log10(4 * math.pi)   # the 21.98 dB
    (21.9842, 21.9842)
    """
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=_WHERE)
    r = jnp.asarray(range_m, dtype=float)
    return db20(4.0 * jnp.pi * r**2)


def atmospheric_two_way_loss_db(range_m, one_way_db_per_km):
    """Two-way loss over a uniform path: 2 alpha R (dB), R in m, alpha one way in dB/km.

    ``range_m`` R (m) >= 0; ``one_way_db_per_km`` alpha >= 0. Exact for a homogeneous path.
    Source: Brooker §9.9.1 (0.003 dB/km one way, L-band surveillance radar example).

    >>> float(atmospheric_two_way_loss_db(100e3, 0.003))   # 2 x 0.003 dB/km x 100 km
    0.6
    """
    check_range("range_m", range_m, 0.0, None, where=_WHERE)
    check_range("one_way_db_per_km", one_way_db_per_km, 0.0, None, where=_WHERE)
    return 2.0 * jnp.asarray(one_way_db_per_km, dtype=float) * jnp.asarray(range_m, dtype=float) / 1e3
