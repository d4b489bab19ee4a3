"""Placing a piece for printing: a flat face down, turned to fit, centred on the bed.

A piece cut from a large object has flat cut faces; printed standing on one
it needs no support under it and its glued face comes out smooth. The face
chosen is the largest planar face that lies on the piece's outer boundary in
one of the six axis directions (the cuts are axis-aligned), so a stair
joint's terraces, which lie at several levels, lose to a flat cut face.

See Also
--------
slicelab.partition : which places every piece it makes.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.triangles import edge_cross
from ..mesh.core import Mesh

__all__ = ["Placement", "place_for_printing", "flat_faces", "fit_rotation", "DIRECTIONS"]

#: Outward normals of the faces a piece may stand on, and their names.
DIRECTIONS = {"-z": (0, 0, -1), "+z": (0, 0, 1), "-x": (-1, 0, 0), "+x": (1, 0, 0), "-y": (0, -1, 0), "+y": (0, 1, 0)}

# Rotations taking each outward normal to -z (onto the bed); proper rotations (det +1).
_DOWN = {
    "-z": np.eye(3),
    "+z": np.diag([1.0, -1.0, -1.0]),                                  # half a turn about x
    "-x": np.array([[0.0, 0, -1], [0, 1, 0], [1, 0, 0]]),             # a quarter turn about y
    "+x": np.array([[0.0, 0, 1], [0, 1, 0], [-1, 0, 0]]),
    "-y": np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]]),             # a quarter turn about x
    "+y": np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]]),
}


@dataclass(frozen=True)
class Placement:
    """How a piece sits in the printer.

    Attributes
    ----------
    matrix : (4, 4) ndarray
        Rigid motion from the part's coordinates to the printer's (mm): the
        chosen face down on z = 0, turned about z, centred on the bed.
    down : str
        The piece's face that rests on the bed, by its outward normal in the
        part's coordinates ("-z", "+x", ...).
    turn : float
        Turn about z (degrees) after laying it down.
    flat_area : float
        Area of the planar face on the bed (mm^2); 0 when it rests on points or edges.
    size : tuple of float
        Bounding-box size (x, y, z) as placed (mm).
    """

    matrix: np.ndarray
    down: str
    turn: float
    flat_area: float
    size: tuple

    def to_dict(self) -> dict:
        """Plain-Python dictionary, ready for JSON."""
        return {"matrix": self.matrix.tolist(), "down": self.down, "turn": self.turn,
                "flat_area": self.flat_area, "size": list(self.size)}


def flat_faces(mesh: Mesh) -> dict[str, float]:
    """Area (mm^2) of the planar face on the outer boundary in each axis direction.

    A facet counts for a direction when its normal is that direction (within
    1e-9) and its corners lie on the piece's extreme plane along it.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> f = flat_faces(box((0, 0, 0), (2, 3, 4)))
    >>> f["-z"], f["+x"]
    (6.0, 12.0)
    """
    t = mesh.triangles
    out = {k: 0.0 for k in DIRECTIONS}
    if len(t) == 0:
        return out
    cross = edge_cross(t)
    double_area = np.sqrt(np.einsum("ij,ij->i", cross, cross))
    unit = np.divide(cross, double_area[:, None], out=np.zeros_like(cross), where=double_area[:, None] > 0)
    lo, hi = mesh.bounds
    tol = 1e-9 * max(float(np.abs(mesh.bounds).max()), 1.0)
    for name, d in DIRECTIONS.items():  # six directions
        axis = int(np.flatnonzero(d)[0])
        sign = d[axis]
        extreme = hi[axis] if sign > 0 else lo[axis]
        on = (unit[:, axis] * sign > 1 - 1e-9) & np.all(np.abs(t[:, :, axis] - extreme) <= tol, axis=1)
        out[name] = float(double_area[on].sum() / 2)
    return out


def fit_rotation(mesh: Mesh, build_volume, *, rotate: bool = True) -> float | None:
    """Turn about z (degrees) that makes the part fit the build volume, or None.

    Tries the part as it lies, then (with `rotate`) turned by 90 degrees, then
    every direction of an edge of its convex hull in plan (the smallest
    enclosing rectangles are aligned with one) and every half degree (a long
    part may only fit along the diagonal).

    Examples
    --------
    >>> from slicelab.samples import box
    >>> fit_rotation(box((0, 0, 0), (250, 100, 10)), (200, 300, 100))
    90.0
    >>> fit_rotation(box((0, 0, 0), (250, 100, 10)), (200, 200, 100)) is None
    True

    References
    ----------
    .. [1] H. Freeman, R. Shapira, "Determining the minimum-area encasing
       rectangle for an arbitrary closed curve", Communications of the ACM
       18(7), pp. 409-413, 1975 (a side of the smallest rectangle lies along
       an edge of the convex hull).
    """
    X, Y, Z = (float(v) for v in build_volume)
    lo, hi = mesh.bounds
    e = hi - lo
    tol = 1e-9 * max(float(np.abs(mesh.bounds).max()), 1.0)
    if e[2] > Z + tol:
        return None
    if e[0] <= X + tol and e[1] <= Y + tol:
        return 0.0
    if not rotate:
        return None
    if e[0] <= Y + tol and e[1] <= X + tol:
        return 90.0
    from scipy.spatial import ConvexHull
    xy = mesh.triangles.reshape(-1, 3)[:, :2]
    try:
        hull = xy[ConvexHull(xy).vertices]
    except Exception:  # flat or degenerate outline
        return None
    edges = np.roll(hull, -1, axis=0) - hull
    # Hull edge directions hold the smallest rectangles; a sweep finds the diagonal fits.
    ang = np.concatenate([np.arctan2(edges[:, 1], edges[:, 0]) % (np.pi / 2), np.radians(np.arange(0.5, 90, 0.5))])
    c, s = np.cos(ang), np.sin(ang)
    u = hull @ np.stack([c, s])           # extents along each edge direction
    v = hull @ np.stack([-s, c])
    wu, wv = np.ptp(u, axis=0), np.ptp(v, axis=0)
    ok = ((wu <= X + tol) & (wv <= Y + tol)) | ((wu <= Y + tol) & (wv <= X + tol))
    if not ok.any():
        return None
    k = int(np.flatnonzero(ok)[0])
    a = -np.degrees(ang[k])  # turn the edge onto x
    if not (wu[k] <= X + tol and wv[k] <= Y + tol):
        a += 90.0
    return float(a % 360.0)


def _turn_z(degrees: float) -> np.ndarray:
    a = np.radians(degrees)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def place_for_printing(mesh: Mesh, build_volume, *, rotate: bool = True) -> Placement | None:
    """Lay a piece on its largest flat boundary face, turn it to fit, centre it on the bed.

    Faces are tried from the largest; the first on which the piece fits the
    build volume (`fit_rotation`) wins. A piece with no flat face that fits
    stands as it lies in the part.

    Parameters
    ----------
    mesh : Mesh
    build_volume : (X, Y, Z)
        mm; the bed is ``[0, X] x [0, Y]`` and the piece is centred on it.
    rotate : bool, default True
        Allow turns about z.

    Returns
    -------
    Placement, or None when the piece fits the volume on none of its faces.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> p = place_for_printing(box((0, 0, 0), (40, 300, 150)), (200, 200, 400))
    >>> p.down, p.size  # too long to lie on its larger faces: stood on its end
    ('-y', (40.0, 150.0, 300.0))
    """
    X, Y, Z = (float(v) for v in build_volume)
    areas = flat_faces(mesh)
    # Largest face first; the part's own bottom wins ties (a part is usually modelled standing).
    order = sorted(DIRECTIONS, key=lambda k: (-round(areas[k], 9), list(DIRECTIONS).index(k)))
    candidates = [k for k in order if areas[k] > 0] or ["-z"]
    t = mesh.triangles.reshape(-1, 3)
    for down in candidates:  # six faces at most
        R = _DOWN[down]
        laid = Mesh((t @ R.T).reshape(-1, 3, 3))
        turn = fit_rotation(laid, (X, Y, Z), rotate=rotate)
        if turn is None:
            continue
        M3 = _turn_z(turn) @ R
        q = t @ M3.T
        lo, hi = q.min(axis=0), q.max(axis=0)
        shift = np.array([X / 2, Y / 2, 0.0]) - np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2]])
        M = np.eye(4)
        M[:3, :3] = M3
        M[:3, 3] = shift
        return Placement(M, down, float(turn), areas[down] if down in areas else 0.0,
                         tuple(float(v) for v in hi - lo))
    return None
