"""Deterministic sample solids with known geometry: boxes, solids of revolution, the pot, voxels.

Every sample is built from an indexed vertex table, so neighbouring facets
share bit-identical corners and the closed samples are exactly watertight.
`scripts/make_data.py` writes them to ``data/``.
"""
from __future__ import annotations

import numpy as np

from ..mesh.core import Mesh
from ..mesh.validation import signed_volume

__all__ = ["random_motion", "box", "revolve", "revolve_grid", "oriented", "torus", "sphere", "POT", "pot",
           "pot_profile", "pot_dimensions", "ring_prism", "cube_with_hole", "concat", "nested_shells",
           "overlapping_cubes", "figure_eight_prism", "voxels", "staircase"]


def random_motion(rng: np.random.Generator, shift: float = 0.0) -> np.ndarray:
    """A uniformly random rotation, and a random shift up to `shift` mm per axis, as a 4x4 matrix.

    For tests and benchmarks that put a sample in an arbitrary pose.

    Examples
    --------
    >>> m = random_motion(np.random.default_rng(0), shift=10)
    >>> bool(np.allclose(m[:3, :3] @ m[:3, :3].T, np.eye(3))), round(float(np.linalg.det(m[:3, :3])), 9)
    (True, 1.0)
    """
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] *= -1
    m = np.eye(4)
    m[:3, :3] = q
    if shift:
        m[:3, 3] = rng.uniform(-shift, shift, 3)
    return m


def oriented(vertices: np.ndarray, faces: np.ndarray) -> Mesh:
    """A closed mesh from a vertex table and faces, the faces reversed if that makes the volume positive.

    Examples
    --------
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> inward = np.array([[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]])
    >>> oriented(v, inward).triangles[0].tolist()
    [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    """
    mesh = Mesh.from_vertices_faces(vertices, faces)
    if signed_volume(mesh.triangles) < 0:
        mesh = Mesh.from_vertices_faces(vertices, faces[:, ::-1])
    return mesh


def box(lo=(0, 0, 0), hi=(1, 1, 1), *, inward: bool = False) -> Mesh:
    """An axis-aligned box of 12 facets, normals outward (or inward for a cavity).

    Examples
    --------
    >>> from slicelab import check
    >>> round(check(box((0, 0, 0), (2, 3, 4))).volume, 9)
    24.0
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    corner = np.array([[(i >> 0) & 1, (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], float)
    v = lo + corner * (hi - lo)
    f = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
    return Mesh.from_vertices_faces(v, f[:, ::-1] if inward else f)


def revolve(profile, n_theta: int) -> Mesh:
    """Revolve an (r, z) profile about the z axis.

    Parameters
    ----------
    profile : (k, 2) array_like
        Either a closed loop with every r > 0 (a torus-like solid), or an open
        polyline whose first and last points lie on the axis (r = 0), which
        become poles.
    n_theta : int
        Facets around the axis.

    Returns
    -------
    Mesh
        Watertight, normals outward.

    Examples
    --------
    >>> from slicelab import check
    >>> r = check(revolve([[0, 0], [1, 0], [1, 1], [0, 1]], 64))
    >>> r.watertight, round(float(r.volume / (32 * np.sin(2 * np.pi / 64))), 9)
    (True, 1.0)
    """
    return oriented(*revolve_grid(profile, n_theta))


def revolve_grid(profile, n_theta: int):
    """The vertex table and faces of `revolve` (before orienting): for noise added to shared vertices.

    Returns
    -------
    vertices : (m, 3) ndarray
    faces : (n, 3) int ndarray
        Consistently wound; `oriented` turns them outward.

    See Also
    --------
    revolve, oriented

    Examples
    --------
    >>> v, f = revolve_grid([[0, 0], [1, 0], [1, 1], [0, 1]], 8)
    >>> v.shape, f.shape
    ((18, 3), (32, 3))
    """
    p = np.asarray(profile, dtype=np.float64)
    theta = 2 * np.pi * np.arange(n_theta) / n_theta
    c, s = np.cos(theta), np.sin(theta)
    j = np.arange(n_theta)
    j1 = (j + 1) % n_theta
    closed = not (p[0, 0] == 0 and p[-1, 0] == 0)
    ring_pts = p if closed else p[1:-1]
    m = len(ring_pts)
    ring = np.stack([ring_pts[:, None, 0] * c, ring_pts[:, None, 0] * s,
                     np.broadcast_to(ring_pts[:, None, 1], (m, n_theta))], axis=-1).reshape(-1, 3)
    rid = np.arange(m * n_theta).reshape(m, n_theta)
    a = np.arange(m if closed else m - 1)
    b = (a + 1) % m
    A, A1, B, B1 = rid[a][:, j], rid[a][:, j1], rid[b][:, j], rid[b][:, j1]  # (pairs, n_theta) each
    # Per pair of profile points, the quads' first triangles, then their second ones.
    faces = [np.stack([np.stack([A, A1, B1], -1), np.stack([A, B1, B], -1)], 1).reshape(-1, 3)]
    vertices = ring
    if not closed:
        p0, p1 = len(ring), len(ring) + 1
        vertices = np.vstack([ring, [[0, 0, p[0, 1]], [0, 0, p[-1, 1]]]])
        faces += [np.stack([np.full(n_theta, p0), rid[0, j1], rid[0, j]], 1),
                  np.stack([rid[-1, j], rid[-1, j1], np.full(n_theta, p1)], 1)]
    return vertices, np.concatenate(faces)


def torus(major: float = 30.0, minor: float = 10.0, n_major: int = 96, n_minor: int = 48) -> Mesh:
    """A torus about the z axis, centred at the origin.

    Examples
    --------
    >>> len(torus(n_major=8, n_minor=4))
    64
    """
    phi = 2 * np.pi * np.arange(n_minor) / n_minor
    return revolve(np.stack([major + minor * np.cos(phi), minor * np.sin(phi)], 1), n_major)


def sphere(radius: float = 20.0, n_lat: int = 48, n_lon: int = 96) -> Mesh:
    """A UV sphere centred at the origin with poles on the z axis.

    Examples
    --------
    >>> len(sphere(n_lat=4, n_lon=8))
    48
    """
    phi = np.linspace(-np.pi / 2, np.pi / 2, n_lat + 1)
    prof = np.stack([radius * np.cos(phi), radius * np.sin(phi)], 1)
    prof[0, 0] = prof[-1, 0] = 0.0
    return revolve(prof, n_lon)


# The synthetic vessel: outer wall r_o(z) = R0 + A sin(pi z / L), a horizontal wall
# thickness T, a flat base of thickness B, open at the rim z = H.
POT = {"height": 120.0, "R0": 30.0, "A": 32.0, "L": 150.0, "wall": 4.0, "base": 6.0}


def _r_outer(z):
    return POT["R0"] + POT["A"] * np.sin(np.pi * np.asarray(z) / POT["L"])


def pot_profile(n_wall: int = 60) -> np.ndarray:
    """The pot's closed half-section as an axis-to-axis (r, z) polyline.

    Examples
    --------
    >>> pot_profile(10)[[0, -1]].tolist()
    [[0.0, 0.0], [0.0, 6.0]]
    """
    H, T, B = POT["height"], POT["wall"], POT["base"]
    zo = np.linspace(0.0, H, n_wall + 1)
    zi = np.linspace(H, B, n_wall + 1)
    outer = np.stack([_r_outer(zo), zo], 1)
    inner = np.stack([_r_outer(zi) - T, zi], 1)
    return np.vstack([[[0.0, 0.0]], outer, inner, [[0.0, B]]])


def pot(n_wall: int = 60, n_theta: int = 72) -> Mesh:
    """A closed vessel of revolution with a wall thickness, open at the top rim.

    Its true dimensions are in `pot_dimensions`.

    Examples
    --------
    >>> m = pot(10, 16)
    >>> m.bounds[:, 2].tolist()
    [0.0, 120.0]
    """
    return revolve(pot_profile(n_wall), n_theta)


def pot_dimensions() -> dict:
    """True dimensions of the continuous pot that `pot` discretises (mm, mm^3).

    Examples
    --------
    >>> round(pot_dimensions()["max_diameter"], 6)
    124.0
    """
    from scipy.integrate import quad
    H, T, B = POT["height"], POT["wall"], POT["base"]
    outer = quad(lambda z: np.pi * _r_outer(z) ** 2, 0, H, epsabs=0, epsrel=1e-13)[0]
    capacity = quad(lambda z: np.pi * (_r_outer(z) - T) ** 2, B, H, epsabs=0, epsrel=1e-13)[0]
    z_max = min(POT["L"] / 2, H)
    return {
        "height": H,
        "rim_diameter": float(2 * _r_outer(H)),
        "max_diameter": float(2 * _r_outer(z_max)),
        "max_diameter_height": float(z_max),
        "base_diameter": float(2 * _r_outer(0.0)),
        "wall_thickness_horizontal": T,
        "base_thickness": B,
        "capacity": capacity,
        "clay_volume": outer - capacity,
    }


def ring_prism(outer_xy, inner_xy, z0: float, z1: float) -> Mesh:
    """Extrude the region between two star-shaped rings of equal size.

    Point k of the outer ring faces point k of the inner ring (same angle from
    the centre), both counter-clockwise, so the caps are strips of quads.

    Examples
    --------
    >>> from slicelab import check
    >>> sq = np.array([[2, 0], [2, 2], [0, 2], [-2, 2], [-2, 0], [-2, -2], [0, -2], [2, -2]], float)
    >>> round(check(ring_prism(sq, sq / 2, 0, 1)).volume, 9)
    12.0
    """
    o = np.asarray(outer_xy, float)
    i = np.asarray(inner_xy, float)
    n = len(o)
    v = np.vstack([np.c_[o, np.full(n, z0)], np.c_[o, np.full(n, z1)],
                   np.c_[i, np.full(n, z0)], np.c_[i, np.full(n, z1)]])
    k = np.arange(n)
    k1 = (k + 1) % n
    ob, ot, ib, it = k, n + k, 2 * n + k, 3 * n + k
    ob1, ot1, ib1, it1 = k1, n + k1, 2 * n + k1, 3 * n + k1
    f = np.concatenate([
        np.stack([ob, ob1, ot1], 1), np.stack([ob, ot1, ot], 1),      # outer wall
        np.stack([ib, it1, ib1], 1), np.stack([ib, it, it1], 1),      # hole wall
        np.stack([ot, ot1, it1], 1), np.stack([ot, it1, it], 1),      # top
        np.stack([ob, ib1, ob1], 1), np.stack([ob, ib, ib1], 1),      # bottom
    ])
    return Mesh.from_vertices_faces(v, f)


def cube_with_hole(size: float = 20.0, radius: float = 5.0, n: int = 64) -> Mesh:
    """A cube with a round through-hole along z, corner at the origin.

    Examples
    --------
    >>> from slicelab import check
    >>> r = check(cube_with_hole(n=8))
    >>> r.watertight, r.n_shells
    (True, 1)
    """
    if n % 8:
        raise ValueError("n must be a multiple of 8 so the square's corners are vertices")
    t = 2 * np.pi * np.arange(n) / n
    c, s = np.cos(t), np.sin(t)
    h = size / 2
    sq = np.stack([c, s], 1) / np.maximum(np.abs(c), np.abs(s))[:, None] * h
    sq = np.round(sq / h) * h * (np.abs(np.abs(sq) - h) < 1e-9) + sq * (np.abs(np.abs(sq) - h) >= 1e-9)
    circle = radius * np.stack([c, s], 1)
    return ring_prism(sq + h, circle + h, 0.0, size)


def concat(*meshes: Mesh) -> Mesh:
    """Join meshes into one triangle soup (shells stay separate)."""
    return Mesh(np.concatenate([m.triangles for m in meshes]))


def nested_shells() -> Mesh:
    """A hollow box with a closed cavity, and an island cube inside the cavity.

    Three shells; a horizontal section through the middle is outer square,
    square hole, and square island inside the hole.

    Examples
    --------
    >>> from slicelab import check
    >>> round(check(nested_shells()).volume, 9)
    51176.0
    """
    return concat(box((0, 0, 0), (40, 40, 40)), box((8, 8, 8), (32, 32, 32), inward=True),
                  box((15, 15, 15), (25, 25, 25)))


def overlapping_cubes() -> Mesh:
    """Two cubes whose volumes overlap, as CAD exports sometimes produce.

    Examples
    --------
    >>> from slicelab import check
    >>> check(overlapping_cubes()).n_shells
    2
    """
    return concat(box((0, 0, 0), (20, 20, 20)), box((10, 10, 5), (30, 30, 25)))


def figure_eight_prism(height: float = 10.0) -> Mesh:
    """A prism over a ring that crosses itself (a figure eight): one closed shell that passes
    through itself, as a careless boolean or a self-intersecting scan leaves.

    The ring runs (0, 0) -> (0, 8) -> (30, 0) -> (30, 12): two of its edges
    cross at (12, 4.8), and its signed area is 60 mm2 (a lobe of 96 mm2 wound
    counter-clockwise, one of 36 mm2 clockwise). The top and bottom are fans
    of triangles, so every edge is shared by two facets: the mesh checks as
    watertight, with a signed volume of 60 x height.

    Examples
    --------
    >>> from slicelab import check
    >>> r = check(figure_eight_prism())
    >>> r.watertight, r.n_shells
    (True, 1)
    """
    ring = np.array([[0.0, 0.0], [0.0, 8.0], [30.0, 0.0], [30.0, 12.0]])
    n = len(ring)
    v = np.concatenate([np.column_stack([ring, np.zeros(n)]), np.column_stack([ring, np.full(n, height)])])
    k = np.arange(n)
    nxt = (k + 1) % n
    sides = np.concatenate([np.stack([k, nxt, nxt + n], 1), np.stack([k, nxt + n, k + n], 1)])
    top = np.stack([np.full(n - 2, n), k[1:-1] + n, k[2:] + n], 1)
    bottom = np.stack([np.zeros(n - 2, np.int64), k[2:], k[1:-1]], 1)
    faces = np.concatenate([sides, top, bottom])
    return Mesh.from_vertices_faces(v, faces)


def voxels(occupancy, pitch=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0)) -> Mesh:
    """The boundary of a union of grid cells, as a watertight mesh.

    Cells that touch only along an edge or at a corner make non-manifold
    edges; avoid them for a clean solid.

    Examples
    --------
    >>> from slicelab import check
    >>> occ = np.ones((2, 1, 1), bool)
    >>> r = check(voxels(occ)); r.watertight, round(r.volume, 9)
    (True, 2.0)
    """
    occ = np.pad(np.asarray(occupancy, bool), 1)
    nx, ny, nz = occ.shape
    pitch = np.asarray(pitch, float)
    origin = np.asarray(origin, float)
    faces = []

    def vid(i, j, k):
        return (i * (ny + 1) + j) * (nz + 1) + k

    for axis in range(3):
        a = occ
        b = np.roll(occ, -1, axis=axis)
        for sign, cells in ((1, a & ~b), (-1, ~a & b)):
            i, j, k = np.nonzero(cells)
            # The face lies on the far side of cell (i, j, k) along `axis`.
            base = [i, j, k]
            base[axis] = base[axis] + 1
            u, w = [(1, 2), (2, 0), (0, 1)][axis]
            corners = []
            for du, dw in ((0, 0), (1, 0), (1, 1), (0, 1)):
                idx = list(base)
                idx[u] = idx[u] + du
                idx[w] = idx[w] + dw
                corners.append(vid(*idx))
            q = np.stack(corners, 1)
            if sign < 0:
                q = q[:, ::-1]
            faces += [q[:, [0, 1, 2]], q[:, [0, 2, 3]]]
    f = np.concatenate(faces)
    used, f = np.unique(f, return_inverse=True)
    f = f.reshape(-1, 3)
    i, rest = np.divmod(used, (ny + 1) * (nz + 1))
    j, k = np.divmod(rest, nz + 1)
    v = (np.stack([i, j, k], 1) - 1) * pitch + origin  # index 1 is the first cell after the padding
    return Mesh.from_vertices_faces(v, f)


def staircase(steps: int = 8, tread: float = 2.0, width: float = 10.0, layer: float = 0.2,
              layers_per_step: int = 2) -> Mesh:
    """A staircase whose treads lie exactly on the layer planes ``k * layer``.

    Slicing it at its tread heights puts vertices, edges and whole faces in
    the plane.

    Examples
    --------
    >>> from slicelab import check
    >>> r = check(staircase(4)); r.watertight, round(r.volume, 6)
    (True, 80.0)
    """
    occ = np.zeros((steps, 1, steps * layers_per_step), bool)
    for s in range(steps):
        occ[s, 0, : (s + 1) * layers_per_step] = True
    return voxels(occ, pitch=(tread, width, layer))
