"""Fitting the Chebyshev interpolant of the exact required SNR (:mod:`diffsense.detection.chebyshev_snr`).

``python -m diffsense.detection.chebyshev_fit --write`` evaluates the exact solver
(:func:`diffsense.detection.required_snr_db`, within 1e-9 dB of mpmath) at the tensor grid of
Chebyshev points of the first kind of :data:`~diffsense.detection.chebyshev_snr.POINTS` in the
coordinates of :func:`~diffsense.detection.chebyshev_snr.coordinates`, turns the values into the
interpolant's coefficients by the discrete cosine transform along each axis (Trefethen,
*Approximation Theory and Approximation Practice*, SIAM 2013, ch. 3), and stores them for the five
Swerling cases in ``data/chebyshev_snr.npz`` (written atomically). A test re-fits and compares.
"""

from __future__ import annotations

import io
import os
import sys
import tempfile
from pathlib import Path

import jax
import numpy as np

from diffsense.detection.chebyshev_snr import DATA, POINTS, box, inputs_at

__all__ = ["chebyshev_points", "fit_coefficients", "write_coefficients"]


def chebyshev_points(size: int) -> np.ndarray:
    """The Chebyshev points of the first kind, cos(π (j + 1/2) / size), j = 0 ... size - 1."""
    return np.cos(np.pi * (np.arange(size) + 0.5) / size)


def _transform(size: int) -> np.ndarray:
    """The matrix taking values at :func:`chebyshev_points` to the interpolant's coefficients."""
    k = np.arange(size)[:, None]
    j = np.arange(size)[None, :]
    m = (2.0 / size) * np.cos(np.pi * k * (j + 0.5) / size)
    m[0] /= 2.0
    return m


def fit_coefficients(swerling: int, points=POINTS) -> np.ndarray:
    """The coefficients of the interpolant of the exact requirement for ``swerling`` with
    ``points`` Chebyshev points per axis."""
    from diffsense.detection.required_snr import _required_snr

    pd, pfa, n = inputs_at(np.meshgrid(*(chebyshev_points(k) for k in points), indexing="ij"))
    solve = jax.jit(lambda p, f, m: _required_snr(p, f, m, swerling))
    values = np.concatenate([np.asarray(solve(*(v.ravel()[i:i + 4096] for v in (pd, pfa, n))))
                             for i in range(0, pd.size, 4096)]).reshape(pd.shape)
    if not np.all(np.isfinite(values)):
        raise ArithmeticError(f"the exact requirement is not finite on the grid (Swerling {swerling})")
    ma, mb, mc = (_transform(k) for k in points)
    return np.einsum("ai,bj,ck,ijk->abc", ma, mb, mc, values)


def write_coefficients(path: Path = DATA) -> None:
    """Fit every Swerling case and store the coefficients at ``path`` (a temporary file beside it
    renamed into place)."""
    buffer = io.BytesIO()
    np.savez(buffer, points=np.asarray(POINTS), box=np.asarray(box()),
             **{f"swerling{sw}": fit_coefficients(sw) for sw in (0, 1, 2, 3, 4)})
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    with os.fdopen(fd, "wb") as fh:
        fh.write(buffer.getvalue())
    os.chmod(tmp, 0o644)
    os.replace(tmp, path)


if __name__ == "__main__":
    if sys.argv[1:] != ["--write"]:
        sys.exit("usage: python -m diffsense.detection.chebyshev_fit --write")
    write_coefficients()
    print(f"wrote {os.path.relpath(DATA)}")
