"""Triangle kernels: edge cross products, unit normals from the winding, areas.

See Also
--------
slicelab.mesh.Mesh : the container whose normals come from `winding_normals`.
"""
from __future__ import annotations

import numpy as np

__all__ = ["edge_cross", "winding_normals", "triangle_areas"]

_BLOCK = 1 << 14


def edge_cross(t: np.ndarray) -> np.ndarray:
    """``(v1 - v0) x (v2 - v0)`` of each triangle, (n, 3): twice the area along the normal.

    Written out by component, which is several times faster than ``np.cross``
    on millions of rows.

    Examples
    --------
    >>> edge_cross(np.array([[[0, 0, 0], [2, 0, 0], [0, 3, 0]]], float)).tolist()
    [[0.0, 0.0, 6.0]]
    """
    ax, ay, az = (t[:, 1, k] - t[:, 0, k] for k in range(3))
    bx, by, bz = (t[:, 2, k] - t[:, 0, k] for k in range(3))
    out = np.empty((len(t), 3))
    np.subtract(ay * bz, az * by, out=out[:, 0])
    np.subtract(az * bx, ax * bz, out=out[:, 1])
    np.subtract(ax * by, ay * bx, out=out[:, 2])
    return out


def winding_normals(triangles: np.ndarray) -> np.ndarray:
    """Unit normals of triangles from their vertex order (right-hand rule).

    Parameters
    ----------
    triangles : (n, 3, 3) array_like
        Triangle corners in winding order (float32 corners are computed in
        float64 too).

    Returns
    -------
    (n, 3) ndarray
        ``(v1 - v0) x (v2 - v0)`` scaled to unit length; zero rows for
        degenerate (zero-area) triangles.

    Examples
    --------
    >>> winding_normals([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]])
    array([[0., 0., 1.]])
    """
    t = np.asarray(triangles)
    if t.dtype not in (np.float32, np.float64):
        t = t.astype(np.float64)
    t = t.reshape(-1, 3, 3)
    out = np.empty((len(t), 3))
    for s in range(0, len(t), _BLOCK):  # blocks of facets keep the temporaries in cache
        # Single-precision corners are widened block by block: the products are float64 either way.
        n = edge_cross(t[s:s + _BLOCK].astype(np.float64, copy=False))
        length = np.sqrt(np.einsum("ij,ij->i", n, n))
        # A facet of no area has no direction: its normal is zero rather than NaN.
        np.divide(n, length[:, None], out=n, where=length[:, None] > 0)
        n[length == 0] = 0.0
        out[s:s + _BLOCK] = n
    return out


def triangle_areas(triangles: np.ndarray) -> np.ndarray:
    """Area of each triangle, (n,), for 2-D or 3-D corners.

    Parameters
    ----------
    triangles : (n, 3, 2) or (n, 3, 3) ndarray

    Examples
    --------
    >>> triangle_areas(np.array([[[0, 0, 0], [2, 0, 0], [0, 3, 0]]], float)).tolist()
    [3.0]
    >>> triangle_areas(np.array([[[0, 0], [2, 0], [0, 3]]], float)).tolist()
    [3.0]
    """
    t = np.asarray(triangles, dtype=np.float64)
    if t.shape[-1] == 2:
        a, b = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
        return 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    c = edge_cross(t)
    return 0.5 * np.sqrt(np.einsum("ij,ij->i", c, c))
