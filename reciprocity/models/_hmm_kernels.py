"""The numba kernels of the hidden Markov plume model (:mod:`reciprocity.models.hmm`).

They live apart so that importing the model (as listing the strategies does) loads no
numba; :mod:`~reciprocity.models.hmm` imports this module where a kernel first runs, and
``cache=True`` keeps the compiled code on disk between processes (issue 24: start-up).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["row_combination", "stencil"]

@njit(cache=True)
def stencil(x, sx, sy, w00, wx, wy, wxy, scale, tiny, out):  # pragma: no cover (compiled)
    """``out[r, j, i] = scale (w00 x[r, j, i] + wx x[r, j, i - sx] + wy x[r, j - sy, i]
    + wxy x[r, j - sy, i - sx])``, terms from outside the ``n × m`` grid left out (odour
    shifted out of it is lost to C0); sums below `tiny`
    (:data:`~reciprocity.models.hmm.TINY`) become 0."""
    R, n, m = x.shape
    for r in range(R):
        for j in range(n):
            jy = j - sy
            in_y = 0 <= jy < n
            for i in range(m):
                ix = i - sx
                s = w00 * x[r, j, i]
                if 0 <= ix < m:
                    s += wx * x[r, j, ix]
                    if in_y:
                        s += wxy * x[r, jy, ix]
                if in_y:
                    s += wy * x[r, jy, i]
                # flush what is below any meaningful probability to zero: subnormal
                # numbers would slow every later product tenfold
                out[r, j, i] = scale * s if s > tiny else 0.0


@njit(cache=True)
def row_combination(weights, rows):  # pragma: no cover (compiled)
    """``Σ_i weights_i rows[i, :]`` (a row vector times a matrix, e.g. α = π Ψ of
    eq. (12)), single-threaded and skipping zero weights."""
    out = np.zeros(rows.shape[1])
    for i in range(rows.shape[0]):
        w = weights[i]
        if w != 0.0:
            for j in range(rows.shape[1]):
                out[j] += w * rows[i, j]
    return out
