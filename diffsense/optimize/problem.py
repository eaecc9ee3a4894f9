"""The constrained design problem and its scaled coordinates.

A :class:`Problem` states

    minimise  f(x, θ)
    subject to g(x, θ) ≤ 0        (vector, m entries; may be absent)
               h(x, θ) = 0        (vector, p entries; may be absent)
               lower ≤ x ≤ upper  (elementwise, ±inf allowed)

over x ∈ Rⁿ, where θ is any pytree of fixed parameters (requirement limits, ranges, ...) that
the solution is later differentiated against (:mod:`diffsense.optimize.sensitivity`).

Variable scaling
----------------
Sensor variables span many decades at once (a pulse width of 1e-9 s next to a peak power of
1e6 W), so the solvers never work in x. Each variable gets a positive typical magnitude
``scale`` sᵢ (units of xᵢ) and is mapped to a dimensionless coordinate zᵢ:

    linear:  zᵢ = xᵢ / sᵢ            xᵢ = sᵢ zᵢ
    log:     zᵢ = ln(xᵢ / sᵢ)        xᵢ = sᵢ exp(zᵢ)     (needs lowerᵢ > 0)

The log map suits positive quantities whose useful range spans decades (powers, bandwidths,
apertures): a unit step in z is then a relative change of e in x. Bounds map monotonically,
so the box stays a box in z and projecting z onto it projects x onto [lower, upper].

Default scales: a log variable with both bounds finite gets the geometric mean √(lo·hi) (its
z-box is then symmetric about 0), otherwise its finite lower bound; a linear variable gets
max(|lo|, |hi|) over its finite bounds (1 when that is 0 or no bound is finite). Give
``scale`` explicitly when the bounds say little about the typical size.

Integer variables (``integer``) are solved as continuous relaxations and rounded by
:mod:`diffsense.optimize.integer`; the continuous solvers ignore the flag.
"""

from __future__ import annotations

from typing import Any, Callable, Optional, Sequence

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range, is_concrete


def _as_vector(value, n: int, name: str, dtype=float) -> np.ndarray:
    a = np.asarray(value, dtype=dtype)
    if a.ndim == 0:
        a = np.full((n,), a, dtype=dtype)
    if a.shape != (n,):
        raise DomainError(f"Problem: '{name}' must be a scalar or have shape ({n},); got shape {a.shape}")
    return a


def default_scales(lower, upper, log_scale) -> np.ndarray:
    """The default typical magnitude of each variable (module docstring): the geometric mean
    of finite bounds (else the lower bound) for a log variable, the largest finite bound's
    magnitude (1 when that is 0 or none is finite) otherwise."""
    lo, hi = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    logm = np.broadcast_to(np.asarray(log_scale, dtype=bool), lo.shape)
    s = np.ones(lo.shape)
    both = np.isfinite(lo) & np.isfinite(hi)
    for i in range(lo.size):
        if logm[i]:
            s[i] = np.sqrt(lo[i] * hi[i]) if both[i] else lo[i]
        else:
            mags = [abs(v) for v in (lo[i], hi[i]) if np.isfinite(v)]
            m = max(mags) if mags else 0.0
            s[i] = m if m > 0 else 1.0
    return s


#: the array fields of a :class:`Problem` (pytree children) and its static fields (auxiliary data:
#: functions and tuples, compared by equality when JAX caches a trace)
_ARRAYS = ("lower", "upper", "scale", "log_scale")
_STATIC = ("objective", "inequality", "equality", "integer_indices", "names", "combined", "sizes")


@jax.tree_util.register_pytree_node_class
class Problem:
    """A bound- and inequality/equality-constrained minimisation problem (see module doc).

    Arguments
    ---------
    objective: ``f(x, theta) -> scalar`` (any units; a cost, an error variance, ...).
    lower, upper: bounds on x in the units of each variable, shape (n,) or scalar; ±inf allowed;
        lower ≤ upper (equal bounds fix a variable).
    inequality: optional ``g(x, theta) -> (m,)``, feasible where every entry is ≤ 0.
    equality: optional ``h(x, theta) -> (p,)``, feasible where every entry is 0.
    scale: typical magnitude of each variable, in its units (> 0); default from the bounds.
    log_scale: bool or (n,) bools; True solves that variable in ln(x/scale) (requires lower > 0).
    integer: bool or (n,) bools marking integer variables (used by ``integer_neighbours`` and
        ``solve_mixed_integer``).
    names: optional variable names, used in reports.
    combined: optional ``fgh(x, theta) -> (f, g, h)`` computing all three at once (one
        evaluation of a model that both read); the solvers call it where they need all three.
    sizes: optional ``(m, p)``, the numbers of inequalities and equalities, when known without
        tracing the functions (a large model's trace is expensive).

    The functions must be pure JAX functions, finite with finite gradients inside the bounds.
    """

    __slots__ = _ARRAYS + _STATIC

    objective: Callable
    inequality: Optional[Callable]
    equality: Optional[Callable]
    lower: jax.Array
    upper: jax.Array
    scale: jax.Array
    log_scale: jax.Array
    integer_indices: tuple
    names: Optional[tuple]
    combined: Optional[Callable]
    sizes: Optional[tuple]

    def __init__(
        self,
        objective: Callable,
        lower,
        upper,
        *,
        inequality: Optional[Callable] = None,
        equality: Optional[Callable] = None,
        scale=None,
        log_scale=False,
        integer=False,
        names: Optional[Sequence[str]] = None,
        combined: Optional[Callable] = None,
        sizes: Optional[tuple] = None,
    ):
        lo = np.atleast_1d(np.asarray(lower, dtype=float))
        hi = np.atleast_1d(np.asarray(upper, dtype=float))
        n = max(lo.size, hi.size)
        lo = _as_vector(lo if lo.size > 1 else lo.reshape(()), n, "lower")
        hi = _as_vector(hi if hi.size > 1 else hi.reshape(()), n, "upper")
        if np.any(np.isnan(lo)) or np.any(np.isnan(hi)):
            raise DomainError("Problem: bounds must not be NaN")
        if np.any(lo > hi):
            i = int(np.argmax(lo > hi))
            raise DomainError(f"Problem: lower[{i}] = {lo[i]!r} exceeds upper[{i}] = {hi[i]!r}")
        if np.any(lo == np.inf) or np.any(hi == -np.inf):
            raise DomainError("Problem: lower may not be +inf and upper may not be -inf")
        logm = _as_vector(log_scale, n, "log_scale", dtype=bool)
        if np.any(logm & ~(lo > 0)):
            i = int(np.argmax(logm & ~(lo > 0)))
            raise DomainError(f"Problem: log-scaled variable {i} needs lower > 0; got lower = {lo[i]!r}")
        if scale is None:
            s = default_scales(lo, hi, logm)
        else:
            s = _as_vector(scale, n, "scale")
            check_range("scale", s, 0.0, None, lo_open=True, where="Problem")
            if not np.all(np.isfinite(s)):
                raise DomainError("Problem: 'scale' must be finite")
        intm = _as_vector(integer, n, "integer", dtype=bool)
        if names is not None:
            names = tuple(str(v) for v in names)
            if len(names) != n:
                raise DomainError(f"Problem: {len(names)} names for {n} variables")
        # NumPy arrays: building a problem stages nothing on a device (traced code reads them as
        # constants; with_bounds puts traced arrays in their place)
        self._set(lower=np.asarray(lo, dtype=float), upper=np.asarray(hi, dtype=float),
                  scale=np.asarray(s, dtype=float), log_scale=np.asarray(logm, dtype=bool),
                  objective=objective, inequality=inequality, equality=equality,
                  integer_indices=tuple(int(i) for i in np.flatnonzero(intm)), names=names, combined=combined,
                  sizes=None if sizes is None else (int(sizes[0]), int(sizes[1])))

    # ------------------------------------------------------------------ pytree
    def _set(self, **fields) -> None:
        for key, value in fields.items():
            object.__setattr__(self, key, value)

    def __setattr__(self, key, value):
        raise AttributeError(f"Problem is immutable: use with_bounds or replace, not '{key} = ...'")

    def tree_flatten(self):
        return tuple(getattr(self, k) for k in _ARRAYS), tuple(getattr(self, k) for k in _STATIC)

    @classmethod
    def tree_unflatten(cls, static, arrays) -> "Problem":
        problem = object.__new__(cls)
        problem._set(**dict(zip(_ARRAYS, arrays)), **dict(zip(_STATIC, static)))
        return problem

    def replace(self, **fields) -> "Problem":
        """A copy with the given fields replaced (no checks: arrays may be traced)."""
        unknown = set(fields) - set(_ARRAYS + _STATIC)
        if unknown:
            raise TypeError(f"Problem.replace: no field {sorted(unknown)[0]!r}")
        arrays, static = self.tree_flatten()
        copy = type(self).tree_unflatten(static, arrays)
        copy._set(**fields)
        return copy

    def __repr__(self) -> str:
        return f"Problem(n={self.n}, names={self.names})"

    # ------------------------------------------------------------------ sizes
    @property
    def n(self) -> int:
        """Number of variables."""
        return int(self.lower.shape[-1])

    def constraint_sizes(self, theta=None) -> tuple[int, int]:
        """(m, p): numbers of inequality and equality constraints (static, from shapes)."""
        if self.sizes is not None:
            return self.sizes
        x = jax.ShapeDtypeStruct((self.n,), jnp.result_type(float))
        m = 0 if self.inequality is None else int(np.prod(jax.eval_shape(self.inequality, x, theta).shape))
        p = 0 if self.equality is None else int(np.prod(jax.eval_shape(self.equality, x, theta).shape))
        return m, p

    # ------------------------------------------------------- function values
    def f(self, x, theta=None):
        """Objective value f(x, θ) as a scalar array."""
        return jnp.reshape(jnp.asarray(self.objective(x, theta), dtype=x.dtype), ())

    def g(self, x, theta=None):
        """Inequality values g(x, θ), shape (m,) (empty when there are none)."""
        if self.inequality is None:
            return jnp.zeros((0,), dtype=x.dtype)
        return jnp.reshape(jnp.asarray(self.inequality(x, theta), dtype=x.dtype), (-1,))

    def h(self, x, theta=None):
        """Equality values h(x, θ), shape (p,) (empty when there are none)."""
        if self.equality is None:
            return jnp.zeros((0,), dtype=x.dtype)
        return jnp.reshape(jnp.asarray(self.equality(x, theta), dtype=x.dtype), (-1,))

    def fgh(self, x, theta=None):
        """(f, g, h) at x: through ``combined`` when the problem has it (one evaluation)."""
        if self.combined is None:
            return self.f(x, theta), self.g(x, theta), self.h(x, theta)
        f, g, h = self.combined(x, theta)
        return (jnp.reshape(jnp.asarray(f, dtype=x.dtype), ()), jnp.reshape(jnp.asarray(g, dtype=x.dtype), (-1,)),
                jnp.reshape(jnp.asarray(h, dtype=x.dtype), (-1,)))

    # ------------------------------------------------------ scaled coordinates
    def from_scaled(self, z):
        """x(z): sᵢ zᵢ for linear variables, sᵢ exp(zᵢ) for log variables."""
        zl = jnp.where(self.log_scale, z, 0.0)  # keeps exp finite in the unused branch
        return jnp.where(self.log_scale, self.scale * jnp.exp(zl), self.scale * z)

    def to_scaled(self, x):
        """z(x), the inverse of :meth:`from_scaled` (x must be > 0 for log variables)."""
        xl = jnp.where(self.log_scale, x, self.scale)
        return jnp.where(self.log_scale, jnp.log(xl / self.scale), x / self.scale)

    def to_scaled_host(self, x) -> np.ndarray:
        """:meth:`to_scaled` in NumPy (host arrays in and out, no JAX dispatch; a log variable's
        x ≤ 0 or an infinite bound maps to ±inf or NaN without a warning)."""
        s, log = np.asarray(self.scale, float), np.asarray(self.log_scale, bool)
        x = np.asarray(x, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(log, np.log(np.where(log, x, s) / s), x / s)

    def from_scaled_host(self, z) -> np.ndarray:
        """:meth:`from_scaled` in NumPy (host arrays in and out, no JAX dispatch)."""
        s, log = np.asarray(self.scale, float), np.asarray(self.log_scale, bool)
        z = np.asarray(z, dtype=float)
        return np.where(log, s * np.exp(np.where(log, z, 0.0)), s * z)

    def scaled_bounds(self):
        """(zlo, zhi), the bounds in scaled coordinates (±inf kept)."""
        lo_l = jnp.where(self.log_scale, self.lower, self.scale)
        hi_l = jnp.where(self.log_scale, self.upper, self.scale)
        zlo = jnp.where(self.log_scale, jnp.log(lo_l / self.scale), self.lower / self.scale)
        zhi = jnp.where(self.log_scale, jnp.log(hi_l / self.scale), self.upper / self.scale)
        return zlo, zhi

    def clip(self, x):
        """x projected onto [lower, upper]."""
        return jnp.clip(x, self.lower, self.upper)

    def with_bounds(self, lower, upper, scale=None) -> "Problem":
        """The same problem with other bounds (and, given, other variable scales); arrays may be
        traced, e.g. under vmap."""
        if scale is None:
            return self.replace(lower=jnp.asarray(lower, float), upper=jnp.asarray(upper, float))
        return self.replace(lower=jnp.asarray(lower, float), upper=jnp.asarray(upper, float),
                            scale=jnp.asarray(scale, float))


def check_start(problem: Problem, x0, where: str = "solve") -> None:
    """Domain check of a concrete starting point: shape (..., n) and finite."""
    if not is_concrete(x0):
        return
    a = np.asarray(x0, dtype=float)
    if a.shape[-1:] != (problem.n,):
        raise DomainError(f"{where}: x0 must have trailing shape ({problem.n},); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise DomainError(f"{where}: x0 must be finite")


Theta = Any
