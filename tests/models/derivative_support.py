"""Central differences for the derivative checks of the force models and laws."""

from __future__ import annotations

import numpy as np


def gradient_fd(fun, x, h):
    g = np.zeros_like(x)
    for idx in np.ndindex(*x.shape):
        xp, xm = x.copy(), x.copy()
        xp[idx] += h
        xm[idx] -= h
        g[idx] = (fun(xp) - fun(xm)) / (2 * h)
    return g


def jacobian_fd(fun, x, h):
    """d fun / dx as a (3n, 3n) matrix for fun: (n, 3) -> (n, 3), DOF = 3*node + axis."""
    cols = []
    for idx in np.ndindex(*x.shape):
        xp, xm = x.copy(), x.copy()
        xp[idx] += h
        xm[idx] -= h
        cols.append(((fun(xp) - fun(xm)) / (2 * h)).ravel())
    return np.array(cols).T


def rel_err(a, b):
    return np.abs(a - b).max() / np.abs(b).max()
