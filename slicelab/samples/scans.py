"""Simulated scans of vessels and sherds, each with the truth to score a measurement against.

`scan` makes what a lab's scanner hands over: a vessel form
(`slicelab.samples.vessels`) or a sherd cut from one (`sherd_mesh`) at a
chosen vertex spacing, Gaussian noise on every vertex (shared vertices move
together, so a closed surface stays closed), optional holes, an oval
distortion and a random pose; and a dict of the true axis, dimensions and,
for a sherd, the angle it spans and the share of the rim it keeps.

A sherd is a block of the wall: between the exterior and the interior
outlines (paired by their share of arc length from the axis), between two
meridian planes ``span`` degrees apart, and between two break lines whose
height wavers along the sherd (a break is never a level circle, a rim is).
A rim sherd keeps the rim land as its top; a base sherd keeps part of the
underside and the base corner.
"""
from __future__ import annotations

import math

import numpy as np

from ..mesh.core import Mesh
from .solids import random_motion
from .vessels import FORMS, handle_truth, vessel_mesh, vessel_outlines, vessel_truth

__all__ = ["SHERDS", "sherd_mesh", "scan"]

#: Kinds of sherd: with the rim, from the body, with the base corner.
SHERDS = ("rim", "body", "base")


def _arc(chain: np.ndarray) -> np.ndarray:
    step = np.diff(chain, axis=0)
    return np.concatenate([[0.0], np.cumsum(np.hypot(step[:, 0], step[:, 1]))])


def _at(chain: np.ndarray, s: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Points of `chain` at share `u` of its arc length (`s` its cumulative arc length)."""
    t = u * s[-1]
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


def sherd_mesh(form: str = "pot", kind: str = "rim", span: float = 60.0, *, spacing: float = 0.3,
               seed: int = 0, start: float = 0.0):
    """A sherd of a vessel form: a closed block of its wall, the breaks wavering.

    Parameters
    ----------
    form : str
        One of `slicelab.samples.FORMS` (the jug's body; no handle).
    kind : {"rim", "body", "base"}
        Rim sherd: the rim land and the wall below it, down about 45 mm (at
        most 45 % of the wall); body sherd: 40 mm (at most 40 %) of the middle
        of the wall; base sherd: the outer half of the underside, the base
        corner and up to 25 mm of wall.
    span : float
        Degrees about the axis.
    spacing : float
        About this far between vertices (mm).
    seed : int
        The breaks' wavering: up to 3 mm along the wall, waves 40 mm to 5 mm long.
    start : float
        Angle (degrees, from +x) of the first radial break.

    Returns
    -------
    vertices : (m, 3) ndarray
    faces : (n, 3) int ndarray
        Wound outward; the block is closed.

    See Also
    --------
    scan : with noise, pose and the truth.

    Examples
    --------
    >>> from slicelab import Mesh, check
    >>> v, f = sherd_mesh("pot", "rim", 60.0, spacing=2.0)
    >>> r = check(Mesh.from_vertices_faces(v, f)); r.watertight, round(float(v[:, 2].max()), 6)
    (True, 120.0)
    """
    if kind not in SHERDS:
        raise ValueError(f"unknown sherd kind {kind!r}; choose one of {', '.join(SHERDS)}")
    if not 0 < span < 360:
        raise ValueError(f"a sherd spans between 0 and 360 degrees, got {span}")
    outer, inner = vessel_outlines(form)
    inner = inner[::-1]  # both from the axis to the rim
    so, si = _arc(outer), _arc(inner)
    L = so[-1]
    foot = float(outer[outer[:, 1] <= 0.0, 0].max())
    wall = L - foot  # arc length of the outer wall
    rng = np.random.default_rng(seed)
    if kind == "rim":
        lo, hi = L - min(45.0, 0.45 * wall), L
    elif kind == "body":
        h = min(40.0, 0.4 * wall)
        lo, hi = foot + 0.45 * wall - h / 2, foot + 0.45 * wall + h / 2
    else:
        lo, hi = 0.5 * foot, foot + min(25.0, 0.3 * wall)
    width = math.radians(span)
    phi0 = math.radians(start)

    def waver(phi, on):  # a smooth random break line, 0 where the sherd keeps an edge of the vessel
        if not on:
            return np.zeros_like(phi)
        # Components a few centimetres to a few millimetres long, amplitude falling as 1/k.
        length = width * r_far
        k = np.arange(1, 9)
        amp, ph = rng.uniform(0.5, 1.0, 8) / k, rng.uniform(0, 2 * np.pi, 8)
        x = (phi - phi0) * r_far / 40.0 * 2 * np.pi  # k = 1: one wave per 40 mm of break
        wave = (np.sin(np.outer(x, k) + ph) * amp).sum(axis=1)
        return 3.0 * wave / max(float(np.abs(wave).max()), 1e-12) if length > 0 else wave

    thickness = float(np.median(np.hypot(*(_at(outer, so, np.linspace(0.2, 0.9, 9))
                                          - _at(inner, si, np.linspace(0.2, 0.9, 9))).T)))
    r_far = float(outer[(so >= lo) & (so <= hi), 0].max())
    na = max(2, int(math.ceil((hi - lo + 6.0) / spacing)))
    nb = max(2, int(math.ceil(width * r_far / spacing)))
    nc = max(2, int(math.ceil(thickness / spacing)))
    phis = phi0 + width * np.linspace(0.0, 1.0, nb + 1)
    w_lo = waver(phis, True)
    w_hi = waver(phis, kind != "rim")
    u_lo = np.clip(lo + w_lo, 0.05 * foot, L) / L
    u_hi = np.clip(hi + w_hi, 0.0, L) / L
    shape = (na + 1, nb + 1, nc + 1)
    border = np.zeros(shape, bool)
    border[[0, -1]] = True
    border[:, [0, -1]] = True
    border[:, :, [0, -1]] = True
    idx = np.full(shape, -1, np.int64)
    i, j, k = np.nonzero(border)
    idx[i, j, k] = np.arange(len(i))
    u = u_lo[j] + (i / na) * (u_hi[j] - u_lo[j])
    c = (k / nc)[:, None]
    rz = (1 - c) * _at(inner, si, u) + c * _at(outer, so, u)
    vertices = np.column_stack([rz[:, 0] * np.cos(phis[j]), rz[:, 0] * np.sin(phis[j]), rz[:, 1]])
    faces = _block_faces(idx)
    from ..mesh.validation import signed_volume
    if signed_volume(vertices[faces]) < 0:
        faces = faces[:, ::-1]
    return vertices, faces


def scan(form: str = "pot", *, spacing: float = 0.3, noise: float = 0.0, seed: int = 0, pose: bool = True,
         holes: int = 0, hole_radius: float = 6.0, oval: float = 0.0, sherd: str | None = None,
         span: float = 60.0, open_rim: bool = False):
    """A simulated scan of a vessel or a sherd, and the truth to score its measurements against.

    Parameters
    ----------
    form : str
        One of `slicelab.samples.FORMS`: "pot", "beaker", "bowl", "plate", "jug".
    spacing : float
        About this far between vertices (mm); a scanner's density is about 0.3 mm.
    noise : float
        Standard deviation (mm) of the Gaussian noise added to every vertex (each coordinate).
    seed : int
        Noise, pose, holes and breaks.
    pose : bool
        Turn and shift the scan at random (`slicelab.samples.random_motion`, up to 200 mm).
    holes : int
        Patches of the surface left unscanned: facets within `hole_radius` of that many random
        points of the surface are removed (the scan is then open).
    hole_radius : float
    oval : float
        Oval distortion: x scaled by 1 + oval, y by 1 - oval (the ovality is 2 oval).
    sherd : {None, "rim", "body", "base"}
        A sherd of the vessel (`sherd_mesh`) instead of the whole.
    span : float
        The sherd's angle about the axis (degrees).
    open_rim : bool
        The rim's top land left unscanned (the scan is open there, as when a
        vessel was scanned standing and its rim top missed).

    Returns
    -------
    mesh : Mesh
    truth : dict
        ``form``, ``kind`` ("whole" or the sherd's kind), ``noise``, ``spacing``,
        ``motion`` (4 x 4, vessel to scan), ``axis`` (unit, base to rim, in scan
        coordinates), ``origin`` (the base centre, in scan coordinates),
        ``span`` (degrees), ``rim_fraction`` (share of the rim circle kept),
        ``ovality`` (%), ``open_rim``, and the dimensions of `vessel_truth` (``height``,
        ``rim_diameter``, ``max_diameter``, ``base_diameter``, ``wall``,
        ``capacity``; None where a sherd does not contain them);
        for the whole jug ``handle_direction`` (unit, in scan coordinates) and
        ``handle`` (`slicelab.samples.handle_truth`: its span, height range and
        section, in the vessel's frame; the oval distortion not applied).

    See Also
    --------
    slicelab.samples.vessel_truth, sherd_mesh

    Examples
    --------
    >>> mesh, truth = scan("beaker", spacing=3.0, noise=0.1, seed=1)
    >>> round(truth["rim_diameter"], 3), truth["kind"], round(float(np.linalg.norm(truth["axis"])), 12)
    (80.0, 'whole', 1.0)
    >>> mesh, truth = scan("pot", spacing=3.0, sherd="rim", span=90.0, pose=False)
    >>> truth["rim_fraction"], truth["capacity"]
    (0.25, None)
    """
    if form not in FORMS:
        raise ValueError(f"unknown vessel form {form!r}; choose one of {', '.join(FORMS)}")
    rng = np.random.default_rng(seed)
    dims = vessel_truth(form)
    truth = {"form": form, "kind": "whole" if sherd is None else sherd, "noise": float(noise),
             "spacing": float(spacing), "span": 360.0, "rim_fraction": 1.0, "ovality": 200.0 * oval, **dims}
    if sherd is None:
        v, f = vessel_mesh(form, spacing)
    else:
        v, f = sherd_mesh(form, sherd, span, spacing=spacing, seed=seed, start=float(rng.uniform(0, 360)))
        truth.update(span=float(span), rim_fraction=span / 360.0 if sherd == "rim" else 0.0, capacity=None,
                     height=None, wall_min=None, wall_max=None)
        if sherd != "rim":
            truth["rim_diameter"] = None
        if sherd != "base":
            truth["base_diameter"] = None
        if sherd == "base":
            truth["max_diameter"] = None
    v = np.array(v, dtype=np.float64)
    if open_rim:
        top = float(v[:, 2].max())
        f = f[~(v[f, 2] >= top - 1e-9).all(axis=1)]
    truth["open_rim"] = bool(open_rim)
    if oval:
        v[:, 0] *= 1 + oval
        v[:, 1] *= 1 - oval
    if noise:
        v += rng.normal(scale=noise, size=v.shape)
    if holes:
        tri = v[f]
        cr = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        area = np.sqrt(np.einsum("ij,ij->i", cr, cr))
        centres = tri.mean(axis=1)
        picks = rng.choice(len(f), size=holes, replace=False, p=area / area.sum())
        gone = np.zeros(len(f), bool)
        for p in picks:  # a few holes
            gone |= np.einsum("ij,ij->i", centres - centres[p], centres - centres[p]) < hole_radius ** 2
        f = f[~gone]
    motion = random_motion(rng, shift=200.0) if pose else np.eye(4)
    v = v @ motion[:3, :3].T + motion[:3, 3]
    truth.update(motion=motion, axis=motion[:3, :3] @ np.array([0.0, 0.0, 1.0]), origin=motion[:3, 3].copy())
    if form == "jug" and sherd is None:
        truth["handle_direction"] = motion[:3, :3] @ np.array([1.0, 0.0, 0.0])
        truth["handle"] = handle_truth()
    return Mesh.from_vertices_faces(v, f), truth
