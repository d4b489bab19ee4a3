"""A scan's vertex noise, measured from residuals to local surface fits, whatever the mesh's layout.

Each sampled vertex is predicted from its two rings of neighbours: a
quadric ``h = a + b x + c y + d x^2 + e x y + f y^2`` is fitted to the
neighbours in their own best plane (the vertex itself left out), and the
vertex's height over that plane is compared with the quadric's. On a smooth
surface the difference is the noise along the normal: its variance is
``sigma^2 (1 + l)``, ``l`` the leverage of the vertex in the fit (how far
the neighbours' quadric must extrapolate to it), so ``e / sqrt(1 + l)``
estimates sigma one vertex at a time, and their robust spread (1.4826 times
the median absolute value) the noise. Corners, rims and breaks, where no
quadric fits, fall in the tail the median ignores.

Unlike the umbrella operator (a vertex minus its neighbours' mean), which
needs edges of about one length, the fit takes the neighbours where they
are: a mesh of 180 steps round the axis (facets 4 mm by 0.3 mm, as
decimated and older laser scans are) reads the same noise as a scanner's
even mesh.

Vertices whose edges differ in length over 50 times (a CAD solid's facets
run from one profile corner to the next) are left out, and a mesh mostly of
them, or of fewer than 1,000 vertices, has no noise to measure.

The estimate's uncertainty (`NoiseEstimate.sd`) is its sampling error
(from the spread of the per-vertex estimates) plus the disagreement of the
two halves of the sample split by how well the quadric fits there (the
half of low leverage against the half of high leverage): a surface the
quadrics do not follow, or a mesh too coarse for its curvature, shows as a
disagreement.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["NoiseEstimate", "noise_estimate", "surface_noise"]

_SAMPLE = 20_000       # vertices whose residual is taken
_MIN_VERTICES = 1000   # fewer, and the mesh is too coarse to tell noise from its own corners and curvature
_MAX_RING = 48         # neighbours kept per vertex (the two rings of an even mesh hold 18)


@dataclass(frozen=True)
class NoiseEstimate:
    """The noise a scan's vertices carry, and how sure that is.

    Attributes
    ----------
    sigma : float
        Standard deviation (mm) of the vertices' noise along the surface's normal.
    sd : float
        Standard uncertainty (mm) of `sigma`: sampling error plus the disagreement of the
        low- and high-leverage halves of the sample.
    samples : int
        Vertices whose residual was taken (0: the mesh is too small or uneven to say; `sigma` is 0).

    Examples
    --------
    >>> NoiseEstimate(0.1, 0.004, 5000).uncertain
    False
    """

    sigma: float
    sd: float
    samples: int

    @property
    def uncertain(self) -> bool:
        """True when the estimate is over 30 % uncertain (and `sigma` over 0.02 mm: below that the
        smoothing it sizes does nothing a drawing shows), or no vertex could be fitted."""
        return self.samples == 0 or (self.sigma > 0.02 and self.sd > 0.3 * self.sigma)


def _rings(f: np.ndarray, nv: int, rows: np.ndarray):
    """The two rings of neighbours of vertices `rows`: an index table (rows, k) and its mask."""
    from scipy.sparse import csr_matrix
    a, b = f.reshape(-1), f[:, [1, 2, 0]].reshape(-1)
    A = csr_matrix((np.ones(2 * len(a)), (np.concatenate([a, b]), np.concatenate([b, a]))), shape=(nv, nv))
    A.sum_duplicates()
    A2 = (A[rows] @ A + A[rows]).tocsr()
    A2.sum_duplicates()
    counts = np.diff(A2.indptr)
    k = min(int(counts.max()) if len(counts) else 0, _MAX_RING)
    pos = np.arange(k)[None, :]
    mask = pos < counts[:, None]
    idx = np.where(mask, A2.indptr[:-1, None] + np.minimum(pos, np.maximum(counts[:, None] - 1, 0)), 0)
    nb = A2.indices[idx] if len(A2.indices) else np.zeros_like(idx)
    mask &= nb != rows[:, None]  # the vertex itself is predicted, not fitted
    return nb, mask


def noise_estimate(vertices: np.ndarray, faces: np.ndarray, *, sample: int = _SAMPLE, seed: int = 0) -> NoiseEstimate:
    """The noise of a welded mesh's vertices from leave-one-out quadric fits (module docstring).

    Parameters
    ----------
    vertices : (m, 3) ndarray
    faces : (n, 3) int ndarray
    sample : int
        Vertices whose residual is taken at most (a deterministic random subset).
    seed : int

    Returns
    -------
    NoiseEstimate

    See Also
    --------
    surface_noise : the same from a triangle array.

    Examples
    --------
    >>> from slicelab.samples import vessel_mesh
    >>> v, f = vessel_mesh("bowl", 0.5, steps=180)
    >>> noisy = v + np.random.default_rng(1).normal(0, 0.1, v.shape)
    >>> e = noise_estimate(noisy, f)
    >>> round(e.sigma, 2), e.uncertain, noise_estimate(v, f).sigma < 0.005
    (0.1, False, True)
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    nv = len(v)
    if nv < _MIN_VERTICES or not len(f):
        return NoiseEstimate(0.0, 0.0, 0)
    used = np.zeros(nv, bool)
    used[f.reshape(-1)] = True
    # A CAD solid's facets run from one profile corner to the next (a cup's wall, 80 mm by 0.5 mm):
    # its vertices, all on corners, are no noise. Vertices whose edges differ over 50 times are left
    # out (a scan's, even at 180 steps round, differ 10-15 times); a mesh mostly of them has none.
    a_, b_ = f.reshape(-1), f[:, [1, 2, 0]].reshape(-1)
    length = np.linalg.norm(v[a_] - v[b_], axis=1)
    hi = np.zeros(nv)
    lo = np.full(nv, np.inf)
    for ends in (a_, b_):  # both ends of each edge
        np.maximum.at(hi, ends, length)
        np.minimum.at(lo, ends, length)
    uneven = hi > 50 * np.maximum(lo, 1e-300)
    if (uneven & used).sum() > 0.5 * used.sum():
        return NoiseEstimate(0.0, 0.0, 0)
    used &= ~uneven
    rows = np.flatnonzero(used)
    if len(rows) < 50:
        return NoiseEstimate(0.0, 0.0, 0)
    if len(rows) > sample:
        rows = np.sort(np.random.default_rng(seed).choice(rows, size=sample, replace=False))
    nb, mask = _rings(f, nv, rows)
    enough = mask.sum(axis=1) >= 9
    rows, nb, mask = rows[enough], nb[enough], mask[enough]
    if len(rows) < 50:
        return NoiseEstimate(0.0, 0.0, 0)
    w = mask.astype(np.float64)
    P = v[nb]                                       # (s, k, 3)
    n_w = np.maximum(w.sum(axis=1), 1.0)
    centre = (P * w[..., None]).sum(axis=1) / n_w[:, None]
    Q = (P - centre[:, None]) * w[..., None]
    cov = np.einsum("ski,skj->sij", Q, Q)
    _, vec = np.linalg.eigh(cov)                    # columns: the plane's axes, then its normal
    e1, e2, nrm = vec[..., 2], vec[..., 1], vec[..., 0]
    rel = P - centre[:, None]
    x, y, h = (np.einsum("ski,si->sk", rel, e) for e in (e1, e2, nrm))
    o = v[rows] - centre
    x0, y0, h0 = (np.einsum("si,si->s", o, e) for e in (e1, e2, nrm))
    # Each row's coordinates scaled to its own spread: a quadric over 8 mm by 0.6 mm stays well posed.
    sx = np.sqrt((w * x * x).sum(axis=1) / n_w) + 1e-12
    sy = np.sqrt((w * y * y).sum(axis=1) / n_w) + 1e-12
    X = np.stack([np.ones_like(x), x / sx[:, None], y / sy[:, None], (x / sx[:, None]) ** 2,
                  x * y / (sx * sy)[:, None], (y / sy[:, None]) ** 2], axis=-1) * w[..., None]
    G = np.einsum("ski,skj->sij", X, X) + 1e-9 * np.eye(6)
    x0s, y0s = x0 / sx, y0 / sy
    q0 = np.stack([np.ones_like(x0s), x0s, y0s, x0s ** 2, x0s * y0s, y0s ** 2], axis=-1)
    coef = np.linalg.solve(G, np.einsum("ski,sk->si", X, h * w)[..., None])[..., 0]
    lev = np.einsum("si,si->s", q0, np.linalg.solve(G, q0[..., None])[..., 0])
    ok = np.isfinite(lev) & (lev < 10.0)
    r = (h0 - np.einsum("si,si->s", q0, coef)) / np.sqrt(1.0 + np.maximum(lev, 0.0))
    r, lev = r[ok], lev[ok]
    if len(r) < 50:
        return NoiseEstimate(0.0, 0.0, 0)
    sigma = float(1.4826 * np.median(np.abs(r)))
    # Sampling error of a median-based scale (about 1.25 sigma / sqrt(n)), and the halves' disagreement.
    lo = lev <= np.median(lev)
    halves = [float(1.4826 * np.median(np.abs(r[part]))) for part in (lo, ~lo)]
    sd = math.hypot(1.25 * sigma / math.sqrt(len(r)), (halves[0] - halves[1]) / 2)
    return NoiseEstimate(sigma, sd, int(len(r)))


def surface_noise(triangles: np.ndarray) -> float:
    """Standard deviation (mm) of a scan's vertex noise, estimated from the surface itself.

    `noise_estimate`'s sigma, from the welded triangles; 0 for a mesh of
    fewer than 200 vertices (its corners are no noise).

    Examples
    --------
    >>> from slicelab.samples import scan
    >>> round(surface_noise(scan("beaker", spacing=2.0, noise=0.1)[0].triangles), 1)
    0.1
    >>> surface_noise(scan("beaker", spacing=2.0)[0].triangles) < 1e-3
    True
    """
    from ..geometry.topology import weld
    v, f = weld(triangles)
    return noise_estimate(v, f).sigma
