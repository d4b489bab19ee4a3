"""Sherds and fragments of the vessel forms, broken as real material breaks, with their truth.

A sherd is a block of the wall (`broken_sherd`): its inner and outer faces
are the vessel's own surfaces, its lip (a rim sherd's top) the form's lip
(`slicelab.samples.lip_parts`), and its other faces breaks. How a break
runs is chosen by `breaks`:

* ``"irregular"``: the lower and upper breaks waver up to 4 mm along the
  wall (waves 40 mm to 5 mm long), the side breaks up to 3 degrees about the
  axis; each crosses the wall obliquely (up to half a wall thickness from
  one face to the other) and its face carries a relief (the fracture's
  grain: `rough` mm RMS, about 1.5 mm across);
* ``"level"``: the lower break runs at nearly constant height (within
  0.25 mm), as along a coil joint or a carination, obliquely across the
  wall, with the relief; the side breaks as above;
* ``"straight"``: the project's first sherds: side breaks in meridian
  planes, lower and upper breaks wavering 3 mm, smooth faces.

The block is a lattice (along the wall, about the axis, across the wall)
whose interior is a Coons patch of its four edges, so the lip, the walls
and the breaks meet in shared vertices and the sherd is closed; a break
crosses the wall about square to it (to the inner wall's nearest point). The same
block makes the low-poly thick fragments of archives and web downloads
(`lowpoly_sherd`) and the fragments of a reassembled vessel
(`assembled_vessel`).
"""
from __future__ import annotations

import math

import numpy as np

from .vessels import lip_parts

__all__ = ["SHERDS", "BREAKS", "broken_sherd", "sherd_mesh", "lowpoly_sherd", "assembled_vessel"]

#: Kinds of sherd: with the rim, from the body, with the base corner.
SHERDS = ("rim", "body", "base")
#: How the breaks run (see the module's docstring).
BREAKS = ("irregular", "level", "straight")
_GRAIN = 1.5     # mm: how wide the relief's bumps are


def _arc(chain: np.ndarray) -> np.ndarray:
    step = np.diff(chain, axis=0)
    return np.concatenate([[0.0], np.cumsum(np.hypot(step[:, 0], step[:, 1]))])


def _at(chain: np.ndarray, s: np.ndarray, t) -> np.ndarray:
    """Points of `chain` at arc length `t` (`s` its cumulative arc length), shape of `t` plus (2,)."""
    t = np.asarray(t, dtype=np.float64)
    return np.stack([np.interp(t, s, chain[:, 0]), np.interp(t, s, chain[:, 1])], axis=-1)


def _block_faces(idx: np.ndarray) -> np.ndarray:
    """Triangles of the six sides of a lattice block, wound the same way round (outward in index space)."""
    faces = []
    for ax in range(3):  # six sides
        for high in (False, True):
            side = np.take(idx, -1 if high else 0, axis=ax)
            if ax == 1:  # the other two axes in cyclic order (ax + 1, ax + 2)
                side = side.T
            q00, q10, q11, q01 = side[:-1, :-1], side[1:, :-1], side[1:, 1:], side[:-1, 1:]
            tri = np.stack([np.stack([q00, q10, q11], -1), np.stack([q00, q11, q01], -1)], -2).reshape(-1, 3)
            faces.append(tri if high else tri[:, ::-1])
    return np.concatenate(faces)


def _wave(rng, lo: float, hi: float, amp: float, longest: float = 40.0, shortest: float = 5.0):
    """A smooth random line over [lo, hi] (mm) whose largest excursion there is `amp`: eight waves
    from `longest` to `shortest` mm long, amplitudes falling as 1 / k."""
    k = np.arange(1, 9)
    lam = longest * (shortest / longest) ** ((k - 1) / 7)
    a = rng.uniform(0.5, 1.0, 8) / k
    ph = rng.uniform(0, 2 * np.pi, 8)
    ref = np.linspace(lo, hi, 2001)
    peak = float(np.abs(np.sin(2 * np.pi * ref[:, None] / lam + ph) @ a).max()) or 1.0

    def f(x):
        x = np.asarray(x, dtype=np.float64)
        return amp * (np.sin(2 * np.pi * x[..., None] / lam + ph) @ a) / peak
    return f


def _relief(rng, rms: float):
    """A random relief of `rms` mm RMS over a break's face, bumps about `_GRAIN` mm across: a sum of
    48 plane waves 1 to 4 grains long in random directions, as a function of (x, y) in mm."""
    m = 48
    lam = _GRAIN * rng.uniform(1.0, 4.0, m)
    ang = rng.uniform(0, np.pi, m)
    kx, ky = 2 * np.pi * np.cos(ang) / lam, 2 * np.pi * np.sin(ang) / lam
    ph = rng.uniform(0, 2 * np.pi, m)
    a = rms * math.sqrt(2.0 / m)

    def f(x, y):
        x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
        return a * np.cos(x[..., None] * kx + y[..., None] * ky + ph).sum(axis=-1)
    return f


def _break_line(rng, kind: str, s0: float, r: float, width: float, t: float, rough: float):
    """A lower or upper break: outer-wall arc position (mm) as a function of (angle, share across the wall)."""
    if kind == "straight":
        w = _wave(rng, 0.0, width * r, 3.0)
        return lambda phi, c: s0 + w(phi * r)
    amp, longest = (4.0, 40.0) if kind == "irregular" else (0.25, 60.0)
    w = _wave(rng, 0.0, width * r, amp, longest, 5.0 if kind == "irregular" else 15.0)
    slant = rng.uniform(-0.5, 0.5) * t if kind == "irregular" else rng.choice([-1, 1]) * rng.uniform(0.3, 1.0) * t
    bump = _relief(rng, rough)
    return lambda phi, c: s0 + w(phi * r) + slant * (c - 0.5) + bump(phi * r, c * t)


def _ring_line(rng, s0: float, r: float, t: float, rough: float):
    """A break all round the vessel (between two rows of a reassembled vessel's pieces): like an
    irregular `_break_line`, but periodic in the angle (whole numbers of waves round the turn)."""
    turn = 2 * np.pi * r
    m = np.unique(np.maximum(1, np.round(turn / (40.0 * (5.0 / 40.0) ** (np.arange(8) / 7))))).astype(float)
    a = rng.uniform(0.5, 1.0, len(m)) / np.arange(1, len(m) + 1)
    ph = rng.uniform(0, 2 * np.pi, len(m))
    ref = np.linspace(0, 2 * np.pi, 4001)
    peak = float(np.abs(np.sin(ref[:, None] * m + ph) @ a).max()) or 1.0
    slant = rng.uniform(-0.5, 0.5) * t
    q = np.maximum(1, np.round(turn / (_GRAIN * rng.uniform(1.0, 4.0, 48))))
    ky = 2 * np.pi / (_GRAIN * rng.uniform(1.0, 4.0, 48)) * rng.choice([-1, 1], 48)
    ps = rng.uniform(0, 2 * np.pi, 48)

    def f(phi, c):
        phi, c = np.asarray(phi, dtype=np.float64), np.asarray(c, dtype=np.float64)
        bump = rough * math.sqrt(2 / 48) * np.cos(phi[..., None] * q + (c * t)[..., None] * ky + ps).sum(axis=-1)
        return s0 + 4.0 * (np.sin(phi[..., None] * m + ph) @ a) / peak + slant * (c - 0.5) + bump
    return f


def _side_break(rng, kind: str, phi0: float, length: float, r: float, t: float, rough: float):
    """A side break: angle (radians) as a function of (share along the wall, share across it)."""
    if kind == "straight":
        return lambda a, c: phi0 + 0.0 * (a + c)
    w = _wave(rng, 0.0, length, math.radians(3.0))
    slant = rng.uniform(-0.5, 0.5) * t / r
    bump = _relief(rng, rough)
    return lambda a, c: phi0 + w(a * length) + slant * (c - 0.5) + bump(a * length, c * t) / r


def _block(walls, cap, n, phi_lo, phi_hi, s_lo, s_hi, *, jitter: float = 0.0, rng=None):
    """A closed lattice block of the wall.

    `walls` are the outer and inner walls (from the axis up); `cap` the lip from the inner wall's top to
    the outer's (the block's top) or None (an upper break `s_hi`); `n` = (along, about, across) the
    lattice's steps; `phi_lo`, `phi_hi` (a, c) the side breaks; `s_lo`, `s_hi` (phi, c) the lower and
    upper breaks in mm along the outer wall (the inner's by the same share). Interior lattice points of
    each face are moved by up to `jitter` of a step (a decimated mesh's uneven facets)."""
    (outer, inner) = walls
    so, si = _arc(outer), _arc(inner)
    Lo, Li = so[-1], si[-1]
    across_map = _across_map(outer, inner)
    na, nb, nc = n
    shape = (na + 1, nb + 1, nc + 1)
    border = np.zeros(shape, bool)
    border[[0, -1]] = True
    border[:, [0, -1]] = True
    border[:, :, [0, -1]] = True
    idx = np.full(shape, -1, np.int64)
    i, j, k = np.nonzero(border)
    idx[i, j, k] = np.arange(len(i))
    a, b, c = i / na, j / nb, k / nc
    if jitter:
        for g, q, m in ((a, i, na), (b, j, nb), (c, k, nc)):  # uneven steps inside each edge
            inside = (q > 0) & (q < m)
            g[inside] += rng.uniform(-jitter, jitter, int(inside.sum())) / m
    lo, hi = phi_lo(a, c), phi_hi(a, c)
    phi = lo + b * (hi - lo)

    def inner_at(s):  # the inner wall's arc position across from outer arc position s
        return np.interp(s, so, across_map)

    def across(s, cc):  # the straight line across the wall at outer arc position s (per point)
        return (1 - cc)[:, None] * _at(inner, si, inner_at(s)) + cc[:, None] * _at(outer, so, np.clip(s, 0, Lo))

    zero, one = np.zeros_like(c), np.ones_like(c)
    s_lo_i, s_lo_o, s_lo_c = s_lo(phi, zero), s_lo(phi, one), s_lo(phi, c)
    if cap is None:
        s_hi_i, s_hi_o = s_hi(phi, zero), s_hi(phi, one)
        top = across(s_hi(phi, c), c)
    else:
        s_hi_i = s_hi_o = np.full_like(c, Lo)
        sc = _arc(cap)
        top = _at(cap, sc, c * sc[-1])
    lo_i = inner_at(s_lo_i)
    inner_a = _at(inner, si, lo_i + a * ((inner_at(s_hi_i) if cap is None else Li) - lo_i))
    outer_a = _at(outer, so, np.clip(s_lo_o + a * (s_hi_o - s_lo_o), 0, Lo))
    bottom = across(s_lo_c, c)
    i0, o0 = across(s_lo_i, zero), across(s_lo_o, one)
    i1, o1 = (across(s_hi_i, zero), across(s_hi_o, one)) if cap is None else (cap[0] + 0 * top, cap[-1] + 0 * top)
    A, C = a[:, None], c[:, None]
    rz = (1 - C) * inner_a + C * outer_a + (1 - A) * bottom + A * top \
        - ((1 - A) * (1 - C) * i0 + (1 - A) * C * o0 + A * (1 - C) * i1 + A * C * o1)
    vertices = np.column_stack([rz[:, 0] * np.cos(phi), rz[:, 0] * np.sin(phi), rz[:, 1]])
    faces = _block_faces(idx)
    from ..mesh.validation import signed_volume
    if signed_volume(vertices[faces]) < 0:
        faces = faces[:, ::-1]
    return vertices, faces


def _across_map(outer: np.ndarray, inner: np.ndarray) -> np.ndarray:
    """For each point of the outer wall, the arc position of the inner wall's nearest point: a break
    crosses the wall about square to it. Made non-decreasing (a corner's fan of nearest points)."""
    from scipy.spatial import cKDTree
    si = _arc(inner)
    _, k = cKDTree(inner).query(outer)
    return np.maximum.accumulate(si[k])


def _thickness(outer, inner) -> float:
    so, si = _arc(outer), _arc(inner)
    u = np.linspace(0.2, 0.9, 9)
    return float(np.median(np.hypot(*(_at(outer, so, u * so[-1]) - _at(inner, si, u * si[-1])).T)))


def _crest(cap: np.ndarray) -> float:
    """Share of the lip's arc length where its crest's outer end lies (the rim's edge)."""
    top = cap[:, 1] >= cap[:, 1].max() - 1e-9
    s = _arc(cap)
    return float(s[np.flatnonzero(top)[np.argmax(cap[top, 0])]] / s[-1])


def broken_sherd(form: str = "pot", kind: str = "rim", span: float = 60.0, *, spacing: float = 0.3,
                 steps: int | None = None, seed: int = 0, start: float = 0.0, lip: str = "flat",
                 breaks: str = "irregular", wall: float | None = None, rough: float | None = None,
                 lattice=None, jitter: float = 0.0):
    """A sherd of a vessel form broken as `breaks` says, and what it keeps of the vessel.

    Parameters
    ----------
    form : str
        One of `slicelab.samples.FORMS` (the jug's body; no handle).
    kind : {"rim", "body", "base"}
        Rim sherd: the lip and the wall below it, down about 45 mm (at most
        45 % of the wall); body sherd: 40 mm (at most 40 %) of the middle of
        the wall; base sherd: the outer half of the underside, the base
        corner and up to 25 mm of wall.
    span : float
        Degrees about the axis (the side breaks waver about it).
    spacing : float
        About this far between vertices (mm).
    steps : int, optional
        Steps about the axis a whole turn would have (then the lattice steps about the axis
        are ``steps * span / 360``, whatever `spacing` is).
    seed : int
        The breaks' wavering, slant and relief.
    start : float
        Angle (degrees, from +x) of the first side break.
    lip : str
        The lip's shape (`slicelab.samples.LIPS`).
    breaks : {"irregular", "level", "straight"}
        How the breaks run (module docstring); "level" makes a rim or body sherd's lower break level.
    wall : float, optional
        The wall's thickness instead of the form's.
    rough : float, optional
        The relief of the break faces (mm RMS); default drawn between 0.05 and 0.3 mm (none for
        straight breaks).
    lattice : (int, int, int), optional
        Steps along the wall, about the axis and across it, instead of those `spacing` gives.
    jitter : float
        Inner lattice points moved by up to this share of a step (a decimated mesh's uneven facets).

    Returns
    -------
    vertices : (m, 3) ndarray
    faces : (n, 3) int ndarray
        Wound outward; the block is closed.
    info : dict
        ``span`` (degrees the sherd covers), ``rim_fraction`` (share of the rim circle its lip keeps at
        its crest's outer edge; 0 without), ``base_fraction`` (share of the footprint's edge kept; 0
        without), ``rough``, ``breaks``, ``lip``.

    See Also
    --------
    sherd_mesh : the mesh alone. slicelab.samples.scan : with noise, pose and the truth.

    Examples
    --------
    >>> from slicelab import Mesh, check
    >>> v, f, info = broken_sherd("pot", "rim", 60.0, spacing=2.0, lip="rounded")
    >>> check(Mesh.from_vertices_faces(v, f)).watertight, round(float(v[:, 2].max()), 1)
    (True, 120.0)
    >>> 50 < 360 * info["rim_fraction"] < 70, info["base_fraction"]
    (True, 0.0)
    """
    if kind not in SHERDS:
        raise ValueError(f"unknown sherd kind {kind!r}; choose one of {', '.join(SHERDS)}")
    if breaks not in BREAKS:
        raise ValueError(f"unknown breaks {breaks!r}; choose one of {', '.join(BREAKS)}")
    if not 0 < span < 360:
        raise ValueError(f"a sherd spans between 0 and 360 degrees, got {span}")
    outer, cap, inner, _ = lip_parts(form, lip, wall)
    so = _arc(outer)
    L = so[-1]
    foot = float(outer[outer[:, 1] <= 0.0, 0].max())
    wall_len = L - foot
    rng = np.random.default_rng(seed)
    t = _thickness(outer, inner)
    if rough is None:
        rough = 0.0 if breaks == "straight" else float(rng.uniform(0.05, 0.3))
    if kind == "rim":
        lo, hi = L - min(45.0, 0.45 * wall_len), None
    elif kind == "body":
        h = min(40.0, 0.4 * wall_len)
        lo, hi = foot + 0.45 * wall_len - h / 2, foot + 0.45 * wall_len + h / 2
    else:
        lo, hi = 0.5 * foot, foot + min(25.0, 0.3 * wall_len)
    top = L if hi is None else hi
    r_far = float(outer[(so >= lo) & (so <= top), 0].max())
    width = math.radians(span)
    phi0 = math.radians(start)
    side = "straight" if breaks == "straight" else "irregular"
    lower = _break_line(rng, breaks if kind != "base" else side, lo, r_far, width, t, rough)
    upper = None if hi is None else _break_line(rng, side, hi, r_far, width, t, rough)
    length = top - lo + 8.0
    left = _side_break(rng, side, phi0, length, r_far, t, rough)
    right = _side_break(rng, side, phi0 + width, length, r_far, t, rough)
    if lattice is None:
        across = max(t, float(_arc(cap)[-1]) if hi is None else t)
        lattice = (max(2, int(math.ceil((top - lo + 6.0) / spacing))),
                   max(2, int(round(steps * span / 360.0)) if steps else int(math.ceil(width * r_far / spacing))),
                   max(2, int(math.ceil(across / spacing))))
    v, f = _block((outer, inner), cap if hi is None else None, lattice, left, right,
                  lambda phi, c: lower(phi - phi0, c),
                  None if upper is None else (lambda phi, c: upper(phi - phi0, c)), jitter=jitter, rng=rng)
    ang = np.arctan2(v[:, 1], v[:, 0]) - phi0
    ang = (ang + np.pi / 2) % (2 * np.pi) - np.pi / 2  # the sherd's own angles, unwrapped about it
    rim = base = 0.0
    if hi is None:
        cc = np.array([_crest(cap)])
        rim = float((right(np.ones(1), cc) - left(np.ones(1), cc))[0]) / (2 * np.pi)
    if kind == "base":
        # The footprint's edge: where each side break meets the outer wall at the foot's arc position.
        a_l = np.clip((foot - lower(np.zeros(1), np.ones(1))) / (hi - lower(np.zeros(1), np.ones(1))), 0, 1)
        a_r = np.clip((foot - lower(np.full(1, width), np.ones(1))) / (hi - lower(np.full(1, width), np.ones(1))),
                      0, 1)
        base = float((right(a_r, np.ones(1)) - left(a_l, np.ones(1)))[0]) / (2 * np.pi)
    info = {"span": float(np.degrees(ang.max() - ang.min())), "rim_fraction": rim, "base_fraction": base,
            "rough": float(rough), "breaks": breaks, "lip": lip}
    return v, f, info


def sherd_mesh(form: str = "pot", kind: str = "rim", span: float = 60.0, *, spacing: float = 0.3,
               seed: int = 0, start: float = 0.0, **kwargs):
    """A sherd of a vessel form: a closed block of its wall (`broken_sherd`'s mesh).

    Returns
    -------
    vertices : (m, 3) ndarray
    faces : (n, 3) int ndarray
        Wound outward; the block is closed.

    See Also
    --------
    broken_sherd : the keywords, and what the sherd keeps.
    slicelab.samples.scan : with noise, pose and the truth.

    Examples
    --------
    >>> from slicelab import Mesh, check
    >>> v, f = sherd_mesh("pot", "rim", 60.0, spacing=2.0)
    >>> r = check(Mesh.from_vertices_faces(v, f)); r.watertight, round(float(v[:, 2].max()), 6)
    (True, 120.0)
    """
    v, f, _ = broken_sherd(form, kind, span, spacing=spacing, seed=seed, start=start, **kwargs)
    return v, f


def lowpoly_sherd(form: str = "pot", kind: str = "rim", *, seed: int = 0, span: float | None = None,
                  lip: str = "flat", wall: float | None = None):
    """A low-poly thick fragment, as archives and web downloads hold: 250-420 facets, uneven.

    The wall is 2.5 times the form's (8-12 mm), the lattice 7-9 steps along
    the wall and about the axis and one or two across it, its inner points
    moved by up to 0.3 of a step; the breaks are irregular and so make a
    large share of the surface.

    Returns
    -------
    vertices, faces, info
        As `broken_sherd`; ``info["wall"]`` is the wall's thickness.

    Examples
    --------
    >>> v, f, info = lowpoly_sherd("beaker", seed=2)
    >>> 250 <= len(f) <= 420
    True
    """
    rng = np.random.default_rng(seed + 7919)
    if wall is None:
        base_wall = {"pot": 4.0, "jug": 3.5, "beaker": 3.0, "bowl": 5.0, "plate": 4.5}[form]
        wall = min(12.0, max(8.0, 2.5 * base_wall))
    if span is None:
        span = float(rng.uniform(50.0, 90.0))
    na, nb = int(rng.integers(7, 10)), int(rng.integers(7, 10))
    nc = 2 if kind == "rim" and lip != "flat" else 1
    v, f, info = broken_sherd(form, kind, span, seed=seed, start=float(rng.uniform(0, 360)), lip=lip, wall=wall,
                              lattice=(na, nb, nc), jitter=0.3)
    info["wall"] = wall
    return v, f, info


def assembled_vessel(form: str = "pot", *, fragments: int = 44, missing: float = 0.2, gap: float = 1.5,
                     spacing: float = 1.0, seed: int = 0, lip: str = "flat"):
    """A vessel reassembled from fragments: separate closed shells, gaps between them, some missing.

    The wall from a little inside the base's edge up to the lip is broken
    into rows, and each row into pieces (irregular breaks, `gap` mm apart);
    the middle of the base is one more piece. A share `missing` of the
    pieces is left out (never every rim piece).

    Returns
    -------
    vertices : (m, 3) ndarray
    faces : (n, 3) int ndarray
    info : dict
        ``fragments`` (pieces kept), ``missing`` (pieces left out), ``rim_fraction`` (share of the
        rim circle the kept pieces' lips hold), ``base_fraction`` (of the footprint's edge),
        ``centre`` (the base's middle kept).

    Examples
    --------
    >>> from slicelab import Mesh, check
    >>> v, f, info = assembled_vessel("beaker", fragments=12, spacing=3.0)
    >>> check(Mesh.from_vertices_faces(v, f)).watertight, info["fragments"] + info["missing"]
    (True, 12)
    """
    from .solids import revolve_grid
    rng = np.random.default_rng(seed)
    outer, cap, inner, _ = lip_parts(form, lip)
    so, si = _arc(outer), _arc(inner)
    L = so[-1]
    foot = float(outer[outer[:, 1] <= 0.0, 0].max())
    t = _thickness(outer, inner)
    s_c = 0.45 * foot  # the base's middle piece
    ss = np.linspace(s_c, L, 400)
    rr = _at(outer, so, ss)[:, 0]
    area = float(2 * np.pi * np.sum(rr[:-1] * np.diff(ss)))
    side = math.sqrt(area / max(fragments - 1, 1))
    n_rows = max(2, int(round((L - s_c) / side)))
    edges = s_c + (L - s_c) * np.arange(n_rows + 1) / n_rows
    r_mid = np.interp((edges[:-1] + edges[1:]) / 2, ss, rr)
    per_row = np.maximum(3, np.round(2 * np.pi * r_mid / side * (fragments - 1) /
                                     max((2 * np.pi * r_mid / side).sum(), 1e-9))).astype(int)
    lines = [None] + [_ring_line(rng, edges[k], float(np.interp(edges[k], ss, rr)), t, 0.15)
                      for k in range(1, n_rows)] + [None]
    pieces = [(k, q) for k in range(n_rows) for q in range(per_row[k])]
    n_miss = int(round(missing * (len(pieces) + 1)))
    rim_pieces = [p for p in pieces if p[0] == n_rows - 1]
    choice = rng.permutation(len(pieces) + 1)[:n_miss]  # index len(pieces): the base's middle
    gone = {pieces[x] for x in choice if x < len(pieces)}
    if all(p in gone for p in rim_pieces):
        gone.discard(rim_pieces[0])
    centre = len(pieces) not in choice
    verts, faces, rim, base = [], [], 0.0, 0.0
    g = gap / 2
    for k in range(n_rows):  # a few rows of pieces
        n = per_row[k]
        r_row = float(r_mid[k])
        length = edges[k + 1] - edges[k] + 8.0
        offset = rng.uniform(0, 2 * np.pi)
        cuts = offset + 2 * np.pi * (np.arange(n) + rng.uniform(-0.2, 0.2, n)) / n
        sides = [_side_break(rng, "irregular", float(x), length, r_row, t, 0.15) for x in cuts]
        for q in range(n):  # the row's pieces
            left, right = sides[q], sides[(q + 1) % n]
            turn = 2 * np.pi if q == n - 1 else 0.0
            if (k, q) in gone:
                continue
            lo_line, hi_line = lines[k], lines[k + 1]
            s_lo = (lambda phi, c: s_c + g + 0.0 * phi) if lo_line is None else \
                (lambda phi, c, f=lo_line: f(phi, c) + g)
            s_hi = None if hi_line is None else (lambda phi, c, f=hi_line: f(phi, c) - g)
            top = edges[k + 1] if hi_line is not None else L
            r_far = float(_at(outer, so, np.linspace(edges[k], top, 50))[:, 0].max())
            width = float(cuts[(q + 1) % n] + turn - cuts[q])
            nb = max(2, int(math.ceil(width * r_far / spacing)))
            na = max(2, int(math.ceil((top - edges[k] + 6.0) / spacing)))
            nc = max(2, int(math.ceil((float(_arc(cap)[-1]) if s_hi is None else t) / spacing)))
            v, f = _block((outer, inner), cap if s_hi is None else None, (na, nb, nc),
                          lambda a, c, h=left: h(a, c) + g / r_row,
                          lambda a, c, h=right, w=turn: h(a, c) + w - g / r_row, s_lo, s_hi)
            faces.append(f + sum(len(x) for x in verts))
            verts.append(v)
            if s_hi is None:
                cc = np.array([_crest(cap)])
                rim += float((right(np.ones(1), cc) + turn - left(np.ones(1), cc))[0] - 2 * g / r_row) / (2 * np.pi)
            if edges[k] < foot < top:
                a_f = np.full(1, (foot - edges[k]) / (top - edges[k]))
                base += float((right(a_f, np.ones(1)) + turn - left(a_f, np.ones(1)))[0] - 2 * g / r_row) / (2 * np.pi)
    if centre:
        r_in = float(_at(inner, si, np.interp(s_c - g, so, _across_map(outer, inner)))[0])
        z_floor = float(inner[0, 1])
        disc = np.array([[0.0, 0.0], [s_c - g, 0.0], [r_in, z_floor], [0.0, z_floor]])
        v, f = revolve_grid(disc, max(16, int(math.ceil(2 * np.pi * s_c / spacing))))
        from ..mesh.validation import signed_volume
        if signed_volume(v[f]) < 0:
            f = f[:, ::-1]
        faces.append(f + sum(len(x) for x in verts))
        verts.append(v)
    info = {"fragments": len(verts), "missing": len(gone) + (not centre), "rim_fraction": rim,
            "base_fraction": base, "centre": bool(centre)}
    return np.vstack(verts), np.vstack(faces), info
