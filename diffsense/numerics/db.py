"""Decibels: the one home of the conversions between power ratios and dB.

Every conversion goes through the natural logarithm and exponential, ``10 log10 x = (10/ln 10)
ln x`` and ``10^(x/10) = exp(x ln 10 / 10)``: the exponential is several times cheaper than a
general power on CPU, and the gradient of ``ln`` is finite for every x > 0. The rounding of the
product x ln(10)/10 gives a relative error up to about |x ln(10)/10|·1.1e-16 (at most 3.3e-15
over −90…130 dB against mpmath), the order of the error of rounding x/10 before a power.

>>> round(float(db10(2.0)), 6), round(float(db20(2.0)), 6)
(3.0103, 6.0206)
>>> round(float(from_db10(30.0)), 9), round(float(from_db20(6.0206)), 4)
(1000.0, 2.0)
>>> round(float(power_sum_db(10.0, 10.0)), 6)    # two equal powers add 3.01 dB
13.0103
"""

from __future__ import annotations

import jax.numpy as jnp

__all__ = ["DB_PER_NEPER", "db10", "db20", "from_db10", "from_db20", "power_sum_db", "increment_db"]

#: 10 / ln 10 = 4.3429: dB per neper of a power ratio (10 log10 x = DB_PER_NEPER · ln x).
#: Both constants are written to 36 digits so that they are the correctly rounded doubles
#: (``10 / math.log(10)`` and ``math.log(10) / 10`` are each one unit in the last place off).
DB_PER_NEPER = 4.34294481903251827651128918916605082
_NEPER_PER_DB = 0.230258509299404568401799145468436421  # ln 10 / 10


def _float(x):
    return jnp.asarray(x, dtype=jnp.result_type(float, x))


def db10(x):
    """10 log10 x (dB of a power ratio x > 0)."""
    return DB_PER_NEPER * jnp.log(_float(x))


def db20(x):
    """20 log10 x (dB of an amplitude ratio x > 0)."""
    return 2.0 * DB_PER_NEPER * jnp.log(_float(x))


def from_db10(x_db):
    """10^(x/10): the power ratio of x dB."""
    return jnp.exp(_NEPER_PER_DB * _float(x_db))


def from_db20(x_db):
    """10^(x/20): the amplitude ratio of x dB."""
    return jnp.exp(0.5 * _NEPER_PER_DB * _float(x_db))


def power_sum_db(a_db, b_db):
    """10 log10(10^(a/10) + 10^(b/10)): two powers given in dB added, stable for any magnitudes."""
    return jnp.logaddexp(_NEPER_PER_DB * _float(a_db), _NEPER_PER_DB * _float(b_db)) / _NEPER_PER_DB


def increment_db(x_db):
    """10 log10(1 + 10^(x/10)): the rise of a level when a second one x dB above it is added.

    >>> float(increment_db(0.0))     # an equal level doubles the power: 10 log10 2
    3.0103
    >>> float(increment_db(-10.0))   # a level 10 dB below: 10 log10 1.1
    0.4139
    """
    return jnp.logaddexp(0.0, _NEPER_PER_DB * _float(x_db)) / _NEPER_PER_DB
