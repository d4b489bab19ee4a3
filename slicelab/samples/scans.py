"""Simulated scans of vessels, sherds and fragments, each with the truth to score a measurement against.

`scan` makes what a lab's scanner (or an archive) hands over: a vessel form
(`slicelab.samples.vessels`) with its lip shaped, at a chosen vertex spacing
or number of steps round the axis; or a sherd broken from it
(`slicelab.samples.fragments`: irregular, level or straight breaks), a
low-poly thick fragment, or the vessel reassembled from fragments with gaps;
Gaussian noise on every vertex (shared vertices move together, so a closed
surface stays closed), optional holes, a chipped rim, an oval distortion and
a random pose; and a dict of the true axis, dimensions and, for a fragment,
the angle it spans and the shares of the rim (its EVE) and of the base it
keeps.
"""
from __future__ import annotations

import math

import numpy as np

from ..mesh.core import Mesh
from .fragments import SHERDS, assembled_vessel, broken_sherd, lowpoly_sherd
from .solids import random_motion
from .vessels import FORMS, handle_truth, vessel_mesh, vessel_truth

__all__ = ["scan"]


def scan(form: str = "pot", *, spacing: float = 0.3, noise: float = 0.0, seed: int = 0, pose: bool = True,
         holes: int = 0, hole_radius: float = 6.0, oval: float = 0.0, sherd: str | None = None,
         span: float = 60.0, open_rim: bool = False, steps: int | None = None, lip: str = "flat",
         breaks: str = "irregular", rough: float | None = None, lowpoly: bool = False, fragments: int = 0,
         missing: float = 0.2, gap: float = 1.5, chip: float = 0.0):
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
        A sherd of the vessel (`slicelab.samples.broken_sherd`) instead of the whole.
    span : float
        The sherd's angle about the axis (degrees).
    open_rim : bool
        The rim's top land left unscanned (the scan is open there, as when a
        vessel was scanned standing and its rim top missed).
    steps : int, optional
        Vertices round the axis a whole turn has, whatever `spacing` is (decimated and older
        laser scans: 180-240; the facets are then long and narrow).
    lip : str
        The lip's shape (`slicelab.samples.LIPS`).
    breaks : {"irregular", "level", "straight"}
        How a sherd's breaks run (`slicelab.samples.fragments`).
    rough : float, optional
        The relief of a sherd's break faces (mm RMS; default drawn between 0.05 and 0.3).
    lowpoly : bool
        With `sherd`: a low-poly thick fragment (`slicelab.samples.lowpoly_sherd`, 250-420
        facets), `spacing` and `steps` unused.
    fragments : int
        The vessel reassembled from that many fragments (`slicelab.samples.assembled_vessel`),
        `missing` of them left out, `gap` mm between them.
    missing, gap : float
    chip : float
        Degrees of the rim broken away (a notch 8 mm deep, its facets removed: the scan is open there).

    Returns
    -------
    mesh : Mesh
    truth : dict
        ``form``, ``kind`` ("whole", "fragmentary" or the sherd's kind), ``noise``, ``spacing``,
        ``steps``, ``lip``, ``breaks``, ``motion`` (4 x 4, vessel to scan), ``axis`` (unit, base to rim,
        in scan coordinates), ``origin`` (the base centre, in scan coordinates), ``span`` (degrees),
        ``rim_fraction`` (share of the rim circle kept at its crest: the EVE; 0 without a rim),
        ``base_fraction`` (share of the footprint's edge kept; 0 without), ``ovality`` (%),
        ``open_rim``, and the dimensions of `vessel_truth` (``height``, ``rim_diameter``,
        ``max_diameter``, ``base_diameter``, ``wall``, ``capacity``; None where a sherd does not
        contain them); for the whole jug ``handle_direction`` (unit, in scan coordinates) and
        ``handle`` (`slicelab.samples.handle_truth`: its span, height range and section, in the
        vessel's frame; the oval distortion not applied).

    See Also
    --------
    slicelab.samples.vessel_truth, slicelab.samples.broken_sherd

    Examples
    --------
    >>> mesh, truth = scan("beaker", spacing=3.0, noise=0.1, seed=1)
    >>> round(truth["rim_diameter"], 3), truth["kind"], round(float(np.linalg.norm(truth["axis"])), 12)
    (80.0, 'whole', 1.0)
    >>> mesh, truth = scan("pot", spacing=3.0, sherd="rim", span=90.0, pose=False, breaks="straight")
    >>> truth["rim_fraction"], truth["capacity"]
    (0.25, None)
    >>> mesh, truth = scan("bowl", sherd="rim", lowpoly=True, seed=3)
    >>> 250 <= len(mesh) <= 420, truth["kind"]
    (True, 'rim')
    """
    if form not in FORMS:
        raise ValueError(f"unknown vessel form {form!r}; choose one of {', '.join(FORMS)}")
    rng = np.random.default_rng(seed)
    wall = None
    info = {}
    if sherd is None and not fragments:
        v, f = vessel_mesh(form, spacing, steps=steps, lip=lip)
    elif fragments:
        v, f, info = assembled_vessel(form, fragments=fragments, missing=missing, gap=gap, spacing=spacing,
                                      seed=seed, lip=lip)
    elif lowpoly:
        v, f, info = lowpoly_sherd(form, sherd, seed=seed, lip=lip)
        wall = info.pop("wall")
    else:
        v, f, info = broken_sherd(form, sherd, span, spacing=spacing, steps=steps, seed=seed,
                                  start=float(rng.uniform(0, 360)), lip=lip, breaks=breaks, rough=rough)
    dims = vessel_truth(form, lip, wall)
    kind = "fragmentary" if fragments else "whole" if sherd is None else sherd
    truth = {"form": form, "kind": kind, "noise": float(noise), "spacing": float(spacing), "steps": steps,
             "lip": lip, "breaks": None if sherd is None else breaks, "span": 360.0, "rim_fraction": 1.0,
             "base_fraction": 1.0, "ovality": 200.0 * oval, **dims}
    if sherd is not None:
        truth.update(span=info["span"], rim_fraction=info["rim_fraction"], base_fraction=info["base_fraction"],
                     rough=info["rough"], capacity=None, height=None, wall_min=None, wall_max=None)
        if sherd != "rim":
            truth["rim_diameter"] = None
        if sherd != "base":
            truth["base_diameter"] = None
        if sherd == "base":
            truth["max_diameter"] = None
        if lowpoly:
            truth.update(spacing=None, breaks="irregular")
    elif fragments:
        truth.update(rim_fraction=info["rim_fraction"], base_fraction=info["base_fraction"],
                     fragments=info["fragments"], missing=info["missing"])
    v = np.array(v, dtype=np.float64)
    if open_rim:
        top = float(v[:, 2].max())
        f = f[~(v[f, 2] >= top - 1e-9).all(axis=1)]
    truth["open_rim"] = bool(open_rim)
    if chip:
        # A notch broken out of the rim: facets within 8 mm of the top over `chip` degrees, from a random angle.
        top = float(v[:, 2].max())
        c = v[f].mean(axis=1)
        a0 = rng.uniform(0, 2 * np.pi)
        da = (np.arctan2(c[:, 1], c[:, 0]) - a0) % (2 * np.pi)
        f = f[~((da < math.radians(chip)) & (c[:, 2] > top - 8.0))]
    truth["chip"] = float(chip)
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
    if form == "jug" and sherd is None and not fragments:
        truth["handle_direction"] = motion[:3, :3] @ np.array([1.0, 0.0, 0.0])
        truth["handle"] = handle_truth()
    return Mesh.from_vertices_faces(v, f), truth
