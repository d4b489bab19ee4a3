"""Vessel forms with their true dimensions: tall pot, beaker, bowl, plate, jug with a handle.

Each form is a pair of dense outlines in (r, z), r the distance from the
axis, z up, the base standing on z = 0:

* the exterior, from the base's centre (0, 0) along the underside, round the
  base corner and up the outer wall to the outer edge of the rim;
* the interior, from the inner edge of the rim down the inner wall and along
  the floor to the axis.

A land at the rim height joins them. The lip is square-cut (a flat land,
sharp corners), rounded, bevelled or everted (`LIPS`, `vessel_outlines`).
`vessel_mesh` revolves the closed profile at a chosen vertex spacing (a
scanner's density is about 0.3 mm) or a chosen number of steps round the axis,
`vessel_truth` measures the continuous outlines (the answer a measurement
must give), `handle_mesh` makes the jug's handle: an oval tube swept along a
D-shaped centre line whose ends are buried in the wall.

Definitions shared with `slicelab.artefacts.measure_halves`: the base
diameter is the footprint's (what touches the plane under the vessel); the
wall thickness is the perpendicular distance from the interior to the
exterior, averaged along the interior (arc length), leaving out the base
(the floor over the footprint) and a band one wall thickness deep
below the rim top; the capacity is the cavity filled to the rim; the rim
diameter is twice the radius at which the exterior wall, continued up past
the lip's rounding or bevel, meets the plane of the lip's crest (its highest
level): the outer edge of a square-cut lip, what a rim chart reads off the
outer face of the others.
"""
from __future__ import annotations

import math

import numpy as np

from .solids import POT

__all__ = ["FORMS", "LIPS", "vessel_outlines", "lip_parts", "vessel_profile", "vessel_mesh", "vessel_truth",
           "handle_mesh", "handle_truth", "sealed_vessel", "wall_thickness_samples", "FLOOR_COSINE"]

#: The vessel forms, tall to shallow; the jug is the pot-like body with a handle on its +x side.
FORMS = ("pot", "beaker", "bowl", "plate", "jug")
#: Lip shapes: square-cut (a flat land, sharp corners), rounded, bevelled (sloping down inwards), everted
#: (the top of the wall flares out, the lip rounded).
LIPS = ("flat", "rounded", "bevelled", "everted")

_STEP = 0.02  # mm between the points of the dense (true) outlines
#: The floor faces up: its outward normal is within 45 degrees of +z.
FLOOR_COSINE = math.cos(math.radians(45))
_JUG = {"height": 125.0, "R0": 30.0, "A": 24.0, "L": 135.0, "wall": 3.5, "base": 5.0,
        "handle": (55.0, 105.0, 34.0, 7.0, 3.5)}  # handle: z from, z to, reach, half width, half thickness


def _polyline(x: np.ndarray, z: np.ndarray) -> np.ndarray:
    return np.column_stack([x, z])


def _segment(a, b) -> np.ndarray:
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = max(2, int(math.ceil(float(np.hypot(*(b - a))) / _STEP)) + 1)
    t = np.linspace(0.0, 1.0, n)[:, None]
    return a + t * (b - a)


def _height_form(R0, A, L, H, wall, base, power=None):
    """Outlines of a form given by its outer radius as a function of height and a horizontal wall."""
    z = np.linspace(0.0, H, int(H / _STEP) + 1)
    r_o = R0 + A * ((z / H) ** power if power else np.sin(np.pi * z / L))
    outer = np.vstack([_segment((0.0, 0.0), (r_o[0], 0.0))[:-1], _polyline(r_o, z)])
    keep = z >= base
    zi = np.concatenate([[base], z[keep]]) if z[keep][0] > base else z[keep]
    ri = R0 + A * ((zi / H) ** power if power else np.sin(np.pi * zi / L)) - wall
    inner = _polyline(ri, zi)[::-1]
    return outer, np.vstack([inner, _segment(inner[-1], (0.0, base))[1:]])


def _offset_form(r_base, rim_r, H, a, wall, base):
    """Outlines of a shallow form: flat base to `r_base`, then z = H (a t + (1 - a) t^2) up to the rim,
    t = (r - r_base) / (rim_r - r_base); the interior is the exterior wall offset by `wall`
    (perpendicular), cut by the floor z = `base` and the rim z = `H`."""
    t = np.linspace(0.0, 1.0, int(1.5 * math.hypot(rim_r - r_base, H) / _STEP) + 1)
    r = r_base + (rim_r - r_base) * t
    z = H * (a * t + (1 - a) * t * t)
    outer = np.vstack([_segment((0.0, 0.0), (r_base, 0.0))[:-1], _polyline(r, z)])
    d = np.gradient(np.column_stack([r, z]), axis=0)
    d /= np.hypot(d[:, 0], d[:, 1])[:, None]
    inner = np.column_stack([r - wall * d[:, 1], z + wall * d[:, 0]])  # the left normal points inside
    inner = inner[(inner[:, 1] >= base) & (inner[:, 1] <= H)]
    # The ends exactly on the floor and on the rim level.
    lo = np.interp(base, inner[:, 1], inner[:, 0])
    hi = np.interp(H, inner[:, 1], inner[:, 0])
    inner = np.vstack([[lo, base], inner[(inner[:, 1] > base) & (inner[:, 1] < H)], [hi, H]])[::-1]
    return outer, np.vstack([inner, _segment(inner[-1], (0.0, base))[1:]])


def _form_outlines(form: str, wall: float | None = None):
    """The square-cut outlines of a form (the wall's horizontal or perpendicular thickness `wall` if given)."""
    if form in ("pot", "jug"):
        d = POT if form == "pot" else _JUG
        t = d["wall"] if wall is None else wall
        return _height_form(d["R0"], d["A"], d["L"], d["height"], t, max(d["base"], t))
    if form == "beaker":
        t = 3.0 if wall is None else wall
        return _height_form(33.0, 7.0, None, 100.0, t, max(5.0, t), power=1.5)
    if form == "bowl":
        t = 5.0 if wall is None else wall
        return _offset_form(28.0, 80.0, 48.0, 0.45, t, max(6.0, t))
    if form == "plate":
        t = 4.5 if wall is None else wall
        return _offset_form(70.0, 120.0, 20.0, 0.55, t, max(5.0, t))
    raise ValueError(f"unknown vessel form {form!r}; choose one of {', '.join(FORMS)}")


def _evert(outer: np.ndarray, inner: np.ndarray):
    """Both walls flared out over their top E = min(15, 0.3 H) mm: r grows by 0.35 E s^2, s = (z - H + E) / E."""
    H = float(outer[-1, 1])
    E = min(15.0, 0.3 * H)

    def flare(c):
        s = np.clip((c[:, 1] - (H - E)) / E, 0.0, None)
        return np.column_stack([c[:, 0] + 0.35 * E * s * s, c[:, 1]])

    return flare(outer), flare(inner)


def _left(chain: np.ndarray) -> np.ndarray:
    """Unit left normals of a polyline (the material's side of a counter-clockwise ring)."""
    d = np.gradient(chain, axis=0)
    d /= np.hypot(d[:, 0], d[:, 1])[:, None]
    return np.column_stack([-d[:, 1], d[:, 0]])


def _fillet(chain: np.ndarray, top: float, tangent: float, at_end: bool):
    """Round the corner between a wall `chain` and the level land z = `top` it meets at its first (or,
    `at_end`, its last) point: a circle tangent to both, touching the land `tangent` mm from the corner.

    Returns the chain with the arc in place of the corner (the arc's land point as its new end) and
    the index where the arc begins (`at_end`) or ends."""
    walk = chain[::-1] if at_end else chain  # from the corner along the wall
    corner = walk[0]
    near = walk[np.hypot(*(walk - corner).T) <= 3 * tangent]
    d = near[min(len(near) - 1, 5)] - corner
    d /= math.hypot(*d)
    land = np.array([-1.0, 0.0]) if at_end else np.array([1.0, 0.0])  # from the corner along the land
    theta = math.acos(float(np.clip(d @ land, -1.0, 1.0)))
    rho = tangent * math.tan(theta / 2)
    # The circle's centre lies rho inside the wall (its offset curve) and rho under the land.
    off = walk + rho * (_left(walk) * (-1 if at_end else 1))
    k = int(np.argmax(off[:, 1] <= top - rho))
    f = (off[k - 1, 1] - (top - rho)) / (off[k - 1, 1] - off[k, 1])
    centre = off[k - 1] + f * (off[k] - off[k - 1])
    touch = walk[k - 1] + f * (walk[k] - walk[k - 1])
    a0 = math.atan2(touch[1] - centre[1], touch[0] - centre[0])
    a1 = math.pi / 2
    if at_end:  # the exterior: counter-clockwise from the wall up to the land
        a0 = a0 if a0 <= a1 else a0 - 2 * math.pi
    else:       # the interior: counter-clockwise from the land down to the wall
        a0 = a0 if a0 >= a1 else a0 + 2 * math.pi
    n = max(3, int(math.ceil(rho * abs(a1 - a0) / _STEP)) + 1)
    t = np.linspace(a0, a1, n)
    arc = centre + rho * np.column_stack([np.cos(t), np.sin(t)])
    kept = walk[k:][::-1] if at_end else walk[k:]
    if at_end:
        return np.vstack([kept, arc]), len(kept) - 1
    return np.vstack([arc[::-1], kept]), n - 1


def _shaped(form: str, lip: str = "flat", wall: float | None = None):
    """Outlines with the lip shaped, the indices where the lip begins on each, and the rim's true radius."""
    if lip not in LIPS:
        raise ValueError(f"unknown lip {lip!r}; choose one of {', '.join(LIPS)}")
    outer, inner = _form_outlines(form, wall)
    if lip == "everted":
        outer, inner = _evert(outer, inner)
    rim_r = float(outer[-1, 0])
    H = float(outer[-1, 1])
    w = float(outer[-1, 0] - inner[0, 0])  # the land's width
    k_out, k_in = len(outer) - 1, 0
    if lip in ("rounded", "everted"):
        outer, k_out = _fillet(outer, H, 0.45 * w, True)
        inner, k_in = _fillet(inner, H, 0.45 * w, False)
    elif lip == "bevelled":
        # The top slopes down inwards from the outer edge to 0.6 wall thicknesses under it.
        t = float(np.hypot(*(outer - inner[0]).T).min())
        k = int(np.argmax(inner[:, 1] <= H - 0.6 * t))
        f = (inner[k - 1, 1] - (H - 0.6 * t)) / (inner[k - 1, 1] - inner[k, 1])
        start = inner[k - 1] + f * (inner[k] - inner[k - 1])
        inner = np.vstack([start, inner[k:] if f < 1 - 1e-9 else inner[k + 1:]])
    return outer, inner, k_out, k_in, rim_r


def vessel_outlines(form: str, lip: str = "flat", wall: float | None = None):
    """Dense exterior and interior outlines of a vessel form, in (r, z), 0.02 mm apart.

    Parameters
    ----------
    form : {"pot", "beaker", "bowl", "plate", "jug"}
        The pot is `slicelab.samples.pot`'s (120 mm tall, rim 97.6 mm, belly
        124 mm, base 60 mm, wall 4 mm horizontal); the beaker is 100 mm tall
        and nearly cylindrical; the bowl 48 mm tall with a 160 mm rim; the
        plate 20 mm tall with a 240 mm rim (its wall leaves the base at 12
        degrees); the jug is a 125 mm body with a narrow neck (its handle
        is `handle_mesh`).
    lip : {"flat", "rounded", "bevelled", "everted"}
        The lip's shape (`LIPS`): a flat land with sharp corners; both corners
        rounded (circles touching the land 0.45 of its width from each
        edge); the top sloping down inwards from the outer edge to 0.6 wall
        thicknesses under it; the top E = min(15, 0.3 H) mm of the wall flared
        out by up to 0.35 E (the lip then rounded). The crest stays at the
        form's height.
    wall : float, optional
        The wall's thickness instead of the form's (horizontal for the pot,
        jug and beaker, perpendicular for the bowl and plate); the base is
        at least as thick.

    Returns
    -------
    outer : (n, 2) ndarray
        From (0, 0) along the underside and up to the outer end of the lip's crest.
    inner : (m, 2) ndarray
        From the inner end of the crest (of the bevel, for a bevelled lip) down to the floor's centre.

    See Also
    --------
    vessel_profile, vessel_truth, lip_parts

    Examples
    --------
    >>> outer, inner = vessel_outlines("plate")
    >>> outer[-1].tolist(), inner[-1].tolist()
    ([120.0, 20.0], [0.0, 5.0])
    >>> outer, inner = vessel_outlines("beaker", "rounded")
    >>> round(float(outer[:, 1].max()), 9), bool(outer[-1, 0] < 40.0 - 1.0)
    (100.0, True)
    """
    outer, inner, _, _, _ = _shaped(form, lip, wall)
    return outer, inner


def lip_parts(form: str, lip: str = "flat", wall: float | None = None):
    """A form's outlines cut where the lip's shaping begins: the walls below it and the lip between.

    Returns
    -------
    outer_wall : (n, 2) ndarray
        From (0, 0) up the exterior to where the lip begins.
    cap : (k, 2) ndarray
        The lip, from the interior's end up over the crest down to the exterior's.
    inner_wall : (m, 2) ndarray
        From the floor's centre (0, base) up the interior to where the lip begins.
    rim_r : float
        The rim's true radius (see `vessel_truth`).

    Examples
    --------
    >>> ow, cap, iw, r = lip_parts("beaker", "rounded")
    >>> bool(np.allclose(cap[0], iw[-1]) and np.allclose(cap[-1], ow[-1])), round(float(cap[:, 1].max()), 6), r
    (True, 100.0, 40.0)
    """
    outer, inner, k_out, k_in, rim_r = _shaped(form, lip, wall)
    cap = np.vstack([inner[:k_in + 1][::-1], outer[k_out:][::-1]])
    return outer[:k_out + 1], cap, inner[k_in:][::-1], rim_r


def _resample(chain: np.ndarray, spacing: float) -> np.ndarray:
    """Points at most `spacing` apart along a polyline, its corners (turns over 5 degrees) kept."""
    d = np.diff(chain, axis=0)
    ang = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs((np.diff(ang) + np.pi) % (2 * np.pi) - np.pi)
    corners = np.concatenate([[0], np.flatnonzero(turn > math.radians(5)) + 1, [len(chain) - 1]])
    out = []
    for a, b in zip(corners[:-1], corners[1:]):  # a few smooth pieces
        piece = chain[a:b + 1]
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(piece, axis=0).T))])
        n = max(2, int(math.ceil(s[-1] / spacing)) + 1)
        u = np.linspace(0.0, s[-1], n)
        out.append(np.column_stack([np.interp(u, s, piece[:, 0]), np.interp(u, s, piece[:, 1])])[:-1])
    return np.vstack([*out, chain[-1:]])


def vessel_profile(form: str, spacing: float = 0.3, lip: str = "flat", wall: float | None = None) -> np.ndarray:
    """The closed profile, axis to axis, with points at most `spacing` apart (corners kept).

    `lip` and `wall` as in `vessel_outlines`.

    Examples
    --------
    >>> p = vessel_profile("beaker", 2.0)
    >>> p[0].tolist(), p[-1].tolist(), bool(np.hypot(*np.diff(p, axis=0).T).max() <= 2.0)
    ([0.0, 0.0], [0.0, 5.0], True)
    """
    outer, inner = vessel_outlines(form, lip, wall)
    return _resample(np.vstack([outer, inner]), spacing)


def handle_mesh(spacing: float = 0.3):
    """The jug's handle: vertices and faces of an oval tube on the +x side, ends buried in the wall.

    The centre line runs in the xz plane from the middle of the wall at
    z = 55 mm out 34 mm and back in at z = 105 mm, leaving and entering the
    wall radially; the tube is 14 mm wide (y) and 7 mm thick, each end
    closed by a fan.

    Returns
    -------
    vertices : (m, 3) ndarray
    faces : (n, 3) int ndarray
        Wound outward.

    Examples
    --------
    >>> v, f = handle_mesh(2.0)
    >>> bool(v[:, 0].max() > 80), bool(v[:, 0].min() > 40)
    (True, True)
    """
    z0, z1, reach, half_w, half_t = _JUG["handle"]
    n_u = max(8, int(math.ceil(math.pi * reach / spacing)))
    n_v = max(8, int(math.ceil(2 * math.pi * half_w / spacing)))
    t = np.linspace(0.0, 1.0, n_u + 1)
    z = z0 + (z1 - z0) * (1 - np.cos(np.pi * t)) / 2
    r_mid = _JUG["R0"] + _JUG["A"] * np.sin(np.pi * z / _JUG["L"]) - _JUG["wall"] / 2
    x = r_mid + reach * np.sin(np.pi * t)
    tangent = np.gradient(np.column_stack([x, z]), axis=0)
    tangent /= np.hypot(tangent[:, 0], tangent[:, 1])[:, None]
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])  # in the xz plane
    psi = 2 * np.pi * np.arange(n_v) / n_v
    px = x[:, None] + half_t * np.cos(psi) * normal[:, None, 0]
    pz = z[:, None] + half_t * np.cos(psi) * normal[:, None, 1]
    py = np.broadcast_to(half_w * np.sin(psi), px.shape)
    ring = np.stack([px, py, pz], axis=-1).reshape(-1, 3)
    rid = np.arange(len(ring)).reshape(n_u + 1, n_v)
    j, j1 = np.arange(n_v), (np.arange(n_v) + 1) % n_v
    A, A1, B, B1 = rid[:-1][:, j], rid[:-1][:, j1], rid[1:][:, j], rid[1:][:, j1]
    faces = np.stack([np.stack([A, A1, B1], -1), np.stack([A, B1, B], -1)], 1).reshape(-1, 3)
    c0, c1 = len(ring), len(ring) + 1
    vertices = np.vstack([ring, [[x[0], 0.0, z[0]], [x[-1], 0.0, z[-1]]]])
    faces = np.vstack([faces, np.stack([np.full(n_v, c0), rid[0, j1], rid[0, j]], 1),
                       np.stack([rid[-1, j], rid[-1, j1], np.full(n_v, c1)], 1)])
    tri = vertices[faces]
    # Outward: the tube's centre line lies behind every facet of its side wall.
    mid = tri[: 2 * n_u * n_v].mean(axis=1)
    nrm = np.cross(tri[: 2 * n_u * n_v, 1] - tri[: 2 * n_u * n_v, 0], tri[: 2 * n_u * n_v, 2] - tri[: 2 * n_u * n_v, 0])
    axis_pts = np.repeat(np.column_stack([x[:-1], np.zeros(n_u), z[:-1]]), 2 * n_v, axis=0)
    if float(np.einsum("ij,ij->", nrm, mid - axis_pts)) < 0:
        faces = faces[:, ::-1]
    return vertices, faces


def handle_truth() -> dict:
    """The jug's handle measured on a dense copy: the part of its surface outside the body.

    Returns
    -------
    dict
        ``angle`` (degrees about the axis; the handle is on +x), ``span``
        (degrees), ``z_from``, ``z_to`` (mm), ``thickness`` (radial extent of
        its section at mid-height, mm), ``width`` (across the radius, mm),
        ``reach`` (how far it stands out of the body, mm).

    Examples
    --------
    >>> t = handle_truth()
    >>> t["angle"], t["thickness"], t["width"], round(t["z_from"], 1), round(t["z_to"], 1)
    (0.0, 7.0, 14.0, 51.5, 108.5)
    """
    v, _ = handle_mesh(0.25)
    r = np.hypot(v[:, 0], v[:, 1])
    above = r - (_JUG["R0"] + _JUG["A"] * np.sin(np.pi * v[:, 2] / _JUG["L"]))
    out = above > 0
    t = np.degrees(np.arctan2(v[out, 1], v[out, 0]))
    half_w, half_t = _JUG["handle"][3:]
    return {"angle": 0.0, "span": float(t.max() - t.min()), "z_from": float(v[out, 2].min()),
            "z_to": float(v[out, 2].max()), "thickness": 2 * half_t, "width": 2 * half_w,
            "reach": float(above.max())}


def sealed_vessel(form: str = "pot", lid: float = 4.0, spacing: float = 1.5, n_theta: int = 256):
    """A vessel form closed at the rim by a lid `lid` mm thick: an outer solid and an inward cavity shell.

    Returns
    -------
    mesh : Mesh
        Two shells: the outer surface (normals out) and the cavity (normals into the void).
    capacity : float
        The cavity's volume (mm^3): the interior up to `lid` under the rim top, by Pappus' theorem
        on the dense outline (the revolved mesh is smaller by its polygon's share, about
        ``1 - (2 pi / n_theta)^2 / 6``).

    Examples
    --------
    >>> mesh, cap = sealed_vessel("beaker", spacing=3.0, n_theta=64)
    >>> round(cap / 1e6, 4)
    0.3082
    """
    from .solids import revolve
    outer, inner = vessel_outlines(form)
    H = float(outer[-1, 1])
    top = H - lid
    inner = np.vstack([[[float(np.interp(top, inner[::-1, 1], inner[::-1, 0])), top]], inner[inner[:, 1] < top]])
    cavity = np.vstack([inner[::-1], [[0.0, top]]])  # axis (floor) round to the axis (lid's underside)
    solid = np.vstack([outer, [[0.0, H]]])
    r, z = cavity[:, 0], cavity[:, 1] - cavity[:, 1].mean()
    r1, z1 = np.roll(r, -1), np.roll(z, -1)
    capacity = abs(float(2 * np.pi * ((r + r1) * (r * z1 - r1 * z)).sum() / 6.0))
    void = revolve(_resample(cavity, spacing), n_theta)
    body = revolve(_resample(solid, spacing), n_theta)
    return type(body)(np.concatenate([body.triangles, void.triangles[:, ::-1]])), capacity


def _revolve_even(profile: np.ndarray, spacing: float, steps: int | None = None):
    """Revolve an axis-to-axis profile with about `spacing` between vertices everywhere.

    Each ring of the profile gets a power-of-two share of the widest ring's
    vertices (`steps`, or as many as keep them `spacing` apart; at least 8), so
    that its vertices stay about `spacing` apart near the axis too, as a
    scanner's would; neighbouring rings differ by a factor of two at most, and
    such a pair is joined by three triangles per segment of the smaller ring.
    The poles are fans.
    """
    ring_pts = profile[1:-1]
    r = ring_pts[:, 0]
    n_full = max(16, int(math.ceil(2 * math.pi * float(r.max()) / spacing / 8)) * 8) if steps is None \
        else int(steps)
    levels = int(math.log2(n_full // 8)) if n_full >= 16 else 0
    while n_full % (2 ** levels):
        levels -= 1
    fill = n_full * spacing / (2 * np.pi * np.maximum(r, 1e-12)) if steps is None else float(r.max()) / np.maximum(r, 1e-12)
    want = np.floor(np.log2(np.maximum(fill, 1.0)))
    h = np.clip(want, 0, levels).astype(np.int64)
    idx = np.arange(len(h))
    h = np.minimum(h, np.minimum.accumulate(h - idx) + idx)  # neighbours one halving apart at most:
    h = np.minimum(h, (np.minimum.accumulate((h + idx)[::-1]) - idx[::-1])[::-1])  # forward, then back
    counts = n_full >> h
    starts = np.concatenate([[0], np.cumsum(counts)])
    j = np.arange(int(starts[-1])) - np.repeat(starts[:-1], counts)
    ring_of = np.repeat(np.arange(len(ring_pts)), counts)
    theta = 2 * np.pi * j / counts[ring_of]
    vertices = np.column_stack([r[ring_of] * np.cos(theta), r[ring_of] * np.sin(theta), ring_pts[ring_of, 1]])
    faces = []
    na, nb = counts[:-1], counts[1:]
    for ca, cb in sorted(set(zip(na.tolist(), nb.tolist()))):  # a few kinds of neighbouring rings
        k = np.flatnonzero((na == ca) & (nb == cb))
        a0, b0 = starts[k][:, None], starts[k + 1][:, None]
        if ca == cb:
            i = np.arange(ca)
            A, A1, B, B1 = a0 + i, a0 + (i + 1) % ca, b0 + i, b0 + (i + 1) % cb
            faces += [np.stack([A, A1, B1], -1).reshape(-1, 3), np.stack([A, B1, B], -1).reshape(-1, 3)]
            continue
        big, small, nbig, nsmall, flip = (a0, b0, ca, cb, False) if ca > cb else (b0, a0, cb, ca, True)
        i = np.arange(nsmall)
        P0, P1, P2 = big + 2 * i, big + (2 * i + 1) % nbig, big + (2 * i + 2) % nbig
        S0, S1 = small + i, small + (i + 1) % nsmall
        tri = np.concatenate([np.stack([P0, P1, S0], -1).reshape(-1, 3), np.stack([P1, S1, S0], -1).reshape(-1, 3),
                              np.stack([P1, P2, S1], -1).reshape(-1, 3)])
        faces.append(tri[:, ::-1] if flip else tri)
    p0, p1 = len(vertices), len(vertices) + 1
    vertices = np.vstack([vertices, [[0.0, 0.0, profile[0, 1]], [0.0, 0.0, profile[-1, 1]]]])
    n0, nl = int(counts[0]), int(counts[-1])
    i0, il = np.arange(n0), np.arange(nl)
    faces += [np.stack([np.full(n0, p0), starts[0] + (i0 + 1) % n0, starts[0] + i0], 1),
              np.stack([starts[-2] + il, starts[-2] + (il + 1) % nl, np.full(nl, p1)], 1)]
    return vertices, np.concatenate(faces).astype(np.int64)


def vessel_mesh(form: str, spacing: float = 0.3, *, steps: int | None = None, lip: str = "flat",
                wall: float | None = None):
    """Vertices and faces of a vessel form revolved with about `spacing` mm between vertices.

    The spacing holds everywhere, near the axis too (`_revolve_even`: rings
    near the axis get fewer vertices); the jug's handle (`handle_mesh`) is
    added as a second shell.

    Parameters
    ----------
    form : str
        One of `FORMS`.
    spacing : float
        Most distance (mm) between neighbouring vertices along the profile, and round the axis
        unless `steps` is given.
    steps : int, optional
        Vertices round the axis on the widest rings (decimated and older laser scans have
        180-240), whatever `spacing` is: the facets are then long and narrow.
    lip, wall
        As in `vessel_outlines`.

    Returns
    -------
    vertices : (m, 3) ndarray
    faces : (n, 3) int ndarray
        Wound outward.

    See Also
    --------
    slicelab.samples.scan : the same with noise, pose, holes and sherds.

    Examples
    --------
    >>> from slicelab import Mesh, check
    >>> v, f = vessel_mesh("plate", 4.0)
    >>> r = check(Mesh.from_vertices_faces(v, f)); r.watertight, round(float(v[:, 2].max()), 6)
    (True, 20.0)
    >>> v, f = vessel_mesh("bowl", 1.0, steps=180, lip="rounded")
    >>> check(Mesh.from_vertices_faces(v, f)).watertight, len(np.unique(np.round(np.arctan2(v[:, 1], v[:, 0]), 9)))
    (True, 180)
    """
    from ..mesh.validation import signed_volume
    if steps is not None and steps < 8:
        raise ValueError(f"a vessel needs 8 steps round its axis at least, got {steps}")
    v, f = _revolve_even(vessel_profile(form, spacing, lip, wall), spacing, steps)
    if signed_volume(v[f]) < 0:
        f = f[:, ::-1]
    if form == "jug":
        hv, hf = handle_mesh(spacing)
        f = np.vstack([f, hf + len(v)])
        v = np.vstack([v, hv])
    return v, f


def wall_thickness_samples(outer: np.ndarray, inner: np.ndarray, footprint_r: float, rim_z: float):
    """Perpendicular wall thickness along the interior, base and rim band left out (the shared definition).

    Parameters
    ----------
    outer, inner : (n, 2), (m, 2) ndarray
        Dense outlines, as `vessel_outlines` gives them.
    footprint_r : float
        Radius of the footprint: the floor over it (interior facing up, `FLOOR_COSINE`) is base, not wall.
    rim_z : float
        Height of the rim top.

    Returns
    -------
    thickness : (k,) ndarray
        At the interior points kept.
    weight : (k,) ndarray
        Arc length each stands for.

    Examples
    --------
    >>> t, w = wall_thickness_samples(*vessel_outlines("beaker"), 33.0, 100.0)
    >>> round(float(np.median(t)), 2)
    2.99
    """
    from scipy.spatial import cKDTree
    d = cKDTree(outer).query(inner)[0]
    step = np.diff(inner, axis=0)
    seg = np.hypot(step[:, 0], step[:, 1])
    w = np.concatenate([[seg[0] / 2], (seg[1:] + seg[:-1]) / 2, [seg[-1] / 2]])
    # Facing up: the interior runs from the rim to the axis, so the floor runs towards smaller r.
    dr = np.gradient(inner[:, 0])
    length = np.hypot(dr, np.gradient(inner[:, 1]))
    up = -dr >= FLOOR_COSINE * length
    base = up & (inner[:, 0] <= footprint_r)
    t_ref = float(np.median(d[~base])) if (~base).any() else 0.0
    keep = ~base & (inner[:, 1] <= rim_z - t_ref)
    return d[keep], w[keep]


def vessel_truth(form: str, lip: str = "flat", wall: float | None = None) -> dict:
    """True dimensions of a vessel form (mm, mm^3), from its dense outlines.

    Parameters
    ----------
    form, lip, wall
        As in `vessel_outlines`.

    Returns
    -------
    dict
        ``height`` (to the lip's crest), ``rim_diameter`` (twice the radius at
        which the exterior wall, continued up past the lip's rounding or
        bevel, meets the crest's plane: the outer edge of a square-cut lip),
        ``max_diameter`` (the body's; the jug's handle left out),
        ``base_diameter`` (the footprint), ``wall`` (mean perpendicular wall
        thickness, see `wall_thickness_samples`), ``wall_min``, ``wall_max``,
        ``capacity`` (filled to the crest, Pappus' theorem on the cavity).

    Examples
    --------
    >>> t = vessel_truth("pot")
    >>> round(t["max_diameter"], 3), round(t["base_diameter"], 3), round(t["capacity"] / 1e6, 4)
    (124.0, 60.0, 0.9211)
    >>> t = vessel_truth("pot", "everted")
    >>> round(t["rim_diameter"], 3), t["height"]
    (108.118, 120.0)
    """
    outer, inner, _, _, rim_r = _shaped(form, lip, wall)
    H = float(outer[-1, 1])
    foot = float(outer[outer[:, 1] <= 0.0, 0].max())
    t, w = wall_thickness_samples(outer, inner, foot, H)
    cavity = np.vstack([outer[-1:], inner, [[0.0, H]]])  # the crest's outer end, down the interior, the axis
    r, z = cavity[:, 0], cavity[:, 1] - cavity[:, 1].mean()
    r1, z1 = np.roll(r, -1), np.roll(z, -1)
    capacity = abs(float(2 * np.pi * ((r + r1) * (r * z1 - r1 * z)).sum() / 6.0))
    return {"height": H, "rim_diameter": 2 * rim_r, "max_diameter": 2 * float(outer[:, 0].max()),
            "base_diameter": 2 * foot, "wall": float((t * w).sum() / w.sum()), "wall_min": float(t.min()),
            "wall_max": float(t.max()), "capacity": capacity}
