"""Support material: columns under what hangs in the air, sparse lines with a denser top (the
machinery every support style of `slicelab.printing.supports.SUPPORTS` shares).

Each layer's unheld overhang (`slicelab.printing.steps.overhangs`: material over
nothing beyond the overhang threshold and held by no bridge) is projected
down, layer by layer, on one coarse pixel grid shared by all layers (supports
need line-width accuracy, not the perimeters' tenth of a millimetre):

- a column stops where it meets the part (``"auto"``: it then stands on the
  part's top), or is dropped wherever the part, or its XY gap, lies anywhere
  under it (``"bed"``: supports stand only on the bed);
- parts of a layer's support narrower than three pixels are dropped;
- it keeps `support_xy_gap` from the part on every layer and ends
  `support_z_gap_layers` layers under the overhang, so it breaks away;
- its top `support_interface_layers` layers are an interface, filled densely
  (`support_interface_spacing`); the rest is sparse lines `support_spacing`
  apart, turned 90 degrees on alternate layers, inside a loop around each region
  (a sheath).

Rasterising a layer and the projection cost the grid's pixels (the part's
footprint at `PIXEL`, a few hundred thousand at most), one vectorised pass
per layer.

Notes
-----
With ``dont_support_bridges`` (`slicelab.printing.PrintSettings`, on by default as
in PrusaSlicer), material held by the part on one side only (a cantilever, a
mushroom's cap) is bridged out from that side, and only a band along its
outline is unheld (`slicelab.printing.steps.overhangs.layer_overhangs`): the supports
stand under that band. Without it, such material is unheld whole, its first
layer is laid as solid infill over the interface, and its supports cover the
whole underside.

See Also
--------
slicelab.printing.planner.plan : adds the supports' paths to each layer.
"""
from __future__ import annotations

import numpy as np

from ...geometry.polygons import Polygon, loop_edges, signed_area
from ..fill.lines import rectilinear
from ..grid.masks import GridMask
from ..steps.perimeters import level_polygons, mask_rings
from ..grid.raster import draw_polylines, winding_numbers

__all__ = ["PIXEL", "PLACEMENTS", "support_masks", "support_paths"]

#: Pixel size (mm) of the supports' grid.
PIXEL = 0.2
#: Where supports stand (`PrintSettings.support`): none, where needed (on the bed or the part), only
#: where they reach the bed.
PLACEMENTS = ("off", "auto", "bed")


def support_masks(sections, unheld, *, mode: str = "auto", xy_gap: float = 0.6, z_gap_layers: int = 1,
                  interface_layers: int = 2, pixel: float = PIXEL, close: float = 0.0):
    """Where each layer's supports go, on one grid.

    Parameters
    ----------
    sections : sequence of Section
        The layers, bottom to top.
    unheld : sequence of sequence of (k, 2) ndarray
        Per layer, the outlines (mm) of what hangs in the air (`LayerOverhangs.unheld`): a hole
        turns the other way from the ring around it (non-zero winding).
    mode : {"auto", "bed"}
        Columns stand on the part or the bed, or only on the bed.
    xy_gap : float, default 0.6
        Distance kept from the part in the plane (mm).
    z_gap_layers : int, default 1
        Layers left empty between a support's top and the overhang.
    interface_layers : int, default 2
        Layers of dense interface at the top of each column.
    pixel : float, default `PIXEL`
    close : float, default 0
        Gaps and notches narrower than this (mm) between a layer's support regions are filled
        (a morphological closing by a square of that side): fewer, blockier columns, as
        PrusaSlicer's "grid" style; 0 follows what hangs exactly ("snug").

    Returns
    -------
    support, interface : list of (h, w) bool ndarray or None
        Per layer (None: no support there); the interface is part of the support.
    window : (row0, col0)
        The grid's corner (world pixels of `pixel`).

    Examples
    --------
    >>> from slicelab import section
    >>> from slicelab.samples import box, concat
    >>> part = concat(box((0, 0, 0), (10, 10, 1)), box((20, 0, 2), (30, 10, 3)))  # a slab floating at 2 mm
    >>> secs = [section(part, (0, 0, z), (0, 0, 1)) for z in (0.5, 1.5, 2.5)]
    >>> sq = [np.array([[20, 0], [30, 0], [30, 10], [20, 10]], float)]
    >>> sup, inter, _ = support_masks(secs, [[], [], sq], z_gap_layers=1, interface_layers=1)
    >>> round(sup[0].sum() * PIXEL ** 2), sup[1] is None, bool(inter[0].sum() == sup[0].sum())
    (112, True, True)

    The slab's 100 mm^2 and the pixels its outline passes through (a pixel on each side); the
    layer under it is the gap; its one layer of support is all interface.
    """
    import cv2
    if mode not in ("auto", "bed"):
        raise ValueError(f"mode must be 'auto' or 'bed', got {mode!r}")
    n = len(sections)
    boxes = [s.bounds() for s in sections if len(s.segments)]
    if not boxes or not any(len(u) for u in unheld):
        return [None] * n, [None] * n, (0, 0)
    lo = np.min([b[0] for b in boxes], axis=0) - xy_gap - 2 * pixel
    hi = np.max([b[1] for b in boxes], axis=0) + xy_gap + 2 * pixel
    row0, col0 = int(np.floor(lo[1] / pixel)), int(np.floor(lo[0] / pixel))
    shape = (int(np.ceil(hi[1] / pixel)) - row0 + 1, int(np.ceil(hi[0] / pixel)) - col0 + 1)

    def material(j):
        s = sections[j]
        if not len(s.segments):
            return np.zeros(shape, bool)
        return winding_numbers(s.segments, row0, col0, shape, pixel) != 0

    def hanging(j):
        # (the rings as they turn: outer rings and holes turn opposite ways)
        e = loop_edges([np.asarray(r, np.float64) for r in unheld[j] if len(r) >= 3]) if 0 <= j < n \
            else np.zeros((0, 2, 2))
        if not len(e):
            return None
        # Inside the outlines, and every pixel they pass through: a strip narrower than a pixel
        # of this grid (a steep wall's overhang) still gets its support.
        inside = winding_numbers(e, row0, col0, shape, pixel) != 0
        return inside | (draw_polylines(shape, row0, col0, pixel, list(unheld[j]), pixel, closed=True) > 0)

    r = max(1, int(round(xy_gap / pixel)))
    gap = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    thin = cv2.getStructuringElement(cv2.MORPH_RECT, (3, 3))
    c = int(round(close / pixel))
    closing = cv2.getStructuringElement(cv2.MORPH_RECT, (2 * c + 1, 2 * c + 1)) if c > 0 else None
    # Bottom up, for "bed": where the part lies at or under each layer (a column there is dropped).
    blocked = None
    if mode == "bed":
        blocked, acc = [], np.zeros(shape, bool)
        for j in range(n):  # over layers
            acc = acc | cv2.dilate(material(j).astype(np.uint8), gap).astype(bool)  # with its XY gap
            blocked.append(np.packbits(acc))
    support, interface = [None] * n, [None] * n
    carry = np.zeros(shape, bool)
    tops = []  # the overhangs of the layers above, newest last, for the interface
    for j in range(n - 1, -1, -1):  # over layers, top down
        above = hanging(j + 1 + z_gap_layers)
        tops.append(above)
        if above is not None:
            carry |= above
        if not carry.any():
            continue
        m = material(j)
        carry &= ~m  # a column that meets the part stands on it
        if blocked is not None:
            carry &= ~np.unpackbits(blocked[j], count=carry.size).reshape(shape).astype(bool)
        region = carry
        if closing is not None:  # (on a frame of empty pixels: the grid's edge closes nothing)
            framed = cv2.copyMakeBorder(carry.astype(np.uint8), c + 1, c + 1, c + 1, c + 1, cv2.BORDER_CONSTANT,
                                        value=0)
            region = cv2.morphologyEx(framed, cv2.MORPH_CLOSE, closing)[c + 1:-c - 1, c + 1:-c - 1].astype(bool)
        sup = region & ~cv2.dilate(m.astype(np.uint8), gap).astype(bool)
        # What is narrower than about a line (three pixels) cannot be printed, and holds nothing.
        sup = cv2.morphologyEx(sup.astype(np.uint8), cv2.MORPH_OPEN, thin).astype(bool)
        if not sup.any():
            continue
        support[j] = sup
        recent = [t for t in tops[-interface_layers:] if t is not None] if interface_layers else []
        if recent:
            inter = sup & np.logical_or.reduce(recent)
            interface[j] = inter if inter.any() else None
    return support, interface, (row0, col0)


def _polygons(mask: np.ndarray, row0: int, col0: int, pixel: float, min_area: float) -> list[Polygon]:
    """A mask's regions as polygons (mm) with their holes, those under `min_area` left out."""
    rings = mask_rings(GridMask(mask, row0, col0, pixel), mask)
    return [q for q in level_polygons(rings) if abs(signed_area(q.exterior)) >= min_area]


def support_paths(sections, unheld, *, mode: str = "auto", line_width: float = 0.4, spacing: float = 2.5,
                  interface_spacing: float = 0.6, xy_gap: float = 0.6, z_gap_layers: int = 1,
                  interface_layers: int = 2, angle: float = 0.0, sheath: bool = True,
                  pixel: float = PIXEL, close: float = 0.0) -> list[list]:
    """The supports' toolpath rows of every layer: ``(kind, polyline)``, kind ``"support"`` or
    ``"support_interface"``.

    Parameters
    ----------
    sections, unheld, mode, xy_gap, z_gap_layers, interface_layers, pixel, close
        As for `support_masks`.
    line_width : float
    spacing, interface_spacing : float
        Distance between lines of the sparse support and of its interface (mm).
    angle : float
        Direction of the sparse lines (degrees); alternate layers turn them by 90, and the
        interface runs across them.
    sheath : bool, default True
        A loop around each region of sparse lines (and its holes).

    Returns
    -------
    list of list of (str, (k, 2) ndarray)
        Per layer; empty where there is no support.

    See Also
    --------
    support_masks : where the supports go.
    """
    support, interface, (row0, col0) = support_masks(sections, unheld, mode=mode, xy_gap=xy_gap,
                                                     z_gap_layers=z_gap_layers, interface_layers=interface_layers,
                                                     pixel=pixel, close=close)
    out = []
    min_area = 4 * line_width ** 2
    made = {}  # parity -> (masks, rows) of the last layer with supports: a column repeats them
    for j, (sup, inter) in enumerate(zip(support, interface)):  # over layers
        rows = []
        last = made.get(j % 2)
        if sup is not None and last is not None and np.array_equal(last[0][0], sup) and (
                (inter is None and last[0][1] is None) or
                (inter is not None and last[0][1] is not None and np.array_equal(last[0][1], inter))):
            out.append(list(last[1]))  # the same masks as two layers below: the same lines
            continue
        if sup is not None:
            turn = angle + 90.0 * (j % 2)
            sparse = _polygons(sup & ~inter if inter is not None else sup, row0, col0, pixel, min_area)
            # A sheath: a loop around each region (and its holes) binds its lines together, so a
            # narrow band (an edge of a bridge, `LayerOverhangs.unheld`) stands, as PrusaSlicer's
            # default ``support_material_with_sheath`` does.
            rows += [("support", np.concatenate((r, r[:1]))) for q in sparse if sheath for r in (q.exterior, *q.holes)]
            rows += [("support", q) for q in rectilinear(sparse, spacing, turn)]
            if inter is not None:
                rows += [("support_interface", q) for q in
                         rectilinear(_polygons(inter, row0, col0, pixel, min_area), interface_spacing, turn + 90.0)]
            made[j % 2] = ((sup, inter), rows)
        out.append(rows)
    return out
