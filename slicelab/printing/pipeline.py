"""A layer's toolpaths as a pipeline of named steps, each reading its own group of settings.

`STEPS` names them in order, as libslic3r's ``PrintObjectStep`` does for a
whole object (posSlice, posPerimeters, posPrepareInfill, posInfill,
posSupportMaterial):

==============  =================================================================  ========================
step            what it makes                                                      where
==============  =================================================================  ========================
``masks``       the layer and its neighbours on the pixel grid                     `LayerWindow`
``skins``       the solid region (top and bottom skins) and its exposed top        `steps.skins`
``overhangs``   bridges, unheld overhangs and mid-air islands                      `steps.overhangs`
``walls``       perimeters on the exact offsets, the region they leave, gap fill   `steps.perimeters`
``fill``        sparse, solid, top and bridge lines, gaps in solid filling         `steps.filling`
``supports``    support material (an object-wide pass: `planner.plan`)            `printing.supports`
``skirt``       skirt and brim around the first layer                              `steps.skirt`
``order``       islands, loops from their seams, paths nearest first               `steps.order`
``simplify``    every path to the G-code resolution                                `steps.simplify`
==============  =================================================================  ========================

`plan_layer` runs the steps from walls to simplify on one section given what
the earlier steps found (`LayerInputs`); `layer_paths` is its toolpaths.
`run_layer` runs every step of one layer of a print, reading its neighbours
from a `LayerWindow`; the planner calls it layer by layer, and reuses what a
layer two below made when all it depends on is the same (a memo around
`run_layer`, `slicelab.printing._reuse`).

References
----------
.. [1] PrusaSlicer, ``src/libslic3r/PrintObject.cpp``: the object's steps.

See Also
--------
slicelab.printing.planner.plan : the whole part.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .config.settings import PrintSettings
from .grid.raster import LayerRaster, rasterize
from .steps.filling import fill_step
from .steps.order import order_step
from .steps.perimeters import Perimeters, layer_perimeters, perimeter_band
from .steps.simplify import simplify_rows
from .table import LayerPaths

__all__ = ["STEPS", "LayerInputs", "LayerAreas", "LayerPlan", "plan_layer", "layer_paths", "layer_areas", "OverhangSummary",
           "LayerResult", "LayerWindow", "layer_inputs", "finish_layer", "at_height", "records", "OVERHANG_FIELDS",
           "AREA_FIELDS"]

#: The steps of a layer, in order.
STEPS = ("masks", "skins", "overhangs", "walls", "fill", "supports", "skirt", "order", "simplify")


@dataclass(frozen=True, eq=False)
class LayerInputs:
    """What the steps before the walls found for a layer (all optional: a lone section has none).

    Attributes
    ----------
    index : int
        The layer's index: its parity turns the filling.
    raster : LayerRaster, optional
        The section on the pixel grid (made by `plan_layer` if not given).
    solid : mask, optional
        Where the filling must be solid (skins), on the layer's pixel grid.
    top : mask, optional
        The part of `solid` the layer above leaves exposed: its lines are top solid infill.
    bridges : tuple of Bridge
        Regions over nothing held by the layer below, bridged along their angles.
    solid_angle : float, optional
        Angle of solid lines; default the layer's filling angle.
    """

    index: int = 0
    raster: LayerRaster | None = None
    solid: object = None
    top: object = None
    bridges: tuple = ()
    solid_angle: float | None = None


@dataclass(frozen=True)
class LayerAreas:
    """A layer's areas (mm^2), from its rasters, and the length of its sparse region's edge (mm):
    what the print is predicted to hold (`slicelab.printing.PrintPlan.predicted_volume`).

    Attributes
    ----------
    material : float
        The section's area.
    inner : float
        The area inside the last perimeter.
    solid : float
        Its solid (skin) part.
    fill_edge : float
        The length of the sparse filling region's boundary.
    """

    material: float = 0.0
    inner: float = 0.0
    solid: float = 0.0
    fill_edge: float = 0.0


@dataclass(frozen=True, eq=False)
class LayerPlan:
    """What the steps from walls to simplify make of a layer: its toolpaths, its walls (fields and
    regions, for plots and measures) and its areas."""

    paths: LayerPaths
    walls: Perimeters
    areas: LayerAreas


def plan_layer(section, settings: PrintSettings | None = None, inputs: LayerInputs | None = None, *,
               start=None, seam=None) -> LayerPlan:
    """The walls, fill, order and simplify steps of one layer.

    Parameters
    ----------
    section : Section
    settings : PrintSettings, optional
        Each step reads its group: the walls the extrusion's and the raster's, the fill the
        infill's, the order the walls', the simplification the G-code resolution.
    inputs : LayerInputs, optional
        What the earlier steps found (skins, bridges, the raster); none for a lone section.
    start : (2,) array_like, optional
        Nozzle position before the layer (default: the layer's lower-left corner).
    seam : (2,) array_like, optional
        With aligned or random seams (`slicelab.printing.seams`), each loop starts at its point
        nearest these points (one per loop of the section).

    Returns
    -------
    LayerPlan

    See Also
    --------
    layer_paths : its toolpaths alone.
    """
    s = settings if settings is not None else PrintSettings()
    inputs = inputs if inputs is not None else LayerInputs()
    ex, walls = s.extrusion, s.walls
    w = ex.line_width
    raster = inputs.raster
    if raster is None:
        raster = rasterize(section, s.pixel_size, rule=s.raster.rule,
                           band=perimeter_band(w, ex.n_perimeters, s.infill.infill_overlap, s.pixel_size))
    if inputs.solid is not None and inputs.solid.pixel_size != raster.pixel_size:
        raise ValueError("the solid mask must be on the layer's pixel grid (same pixel size)")
    per = layer_perimeters(raster, w, ex.n_perimeters, overlap=s.infill.infill_overlap, solid=inputs.solid)
    z = float(section.z) if hasattr(section, "z") else 0.0
    fills = fill_step(per, s.infill, line_width=w, pixel_size=raster.pixel_size, resolution=ex.gcode_resolution,
                      layer_index=inputs.index, z=z, top=inputs.top, bridges=inputs.bridges,
                      solid_angle=inputs.solid_angle)
    kinds, paths, widths, travel = order_step(section, per, fills, line_width=w, seam=walls.seam_position,
                                              seam_point=seam, external_first=walls.external_perimeters_first,
                                              start=start)
    paths, widths = simplify_rows(kinds, paths, widths, ex.gcode_resolution)
    table = LayerPaths(tuple(kinds), tuple(paths), tuple(widths), travel, w,
                       section.z if hasattr(section, "z") else float("nan"), per.thin_walls)
    return LayerPlan(table, per, layer_areas(per, inputs.solid, ex.n_perimeters * w))


def layer_paths(section, settings: PrintSettings | None = None, inputs: LayerInputs | None = None, *,
                start=None, seam=None) -> LayerPaths:
    """The toolpaths of one layer: perimeters, gap fill and filling, in print order.

    Parameters
    ----------
    section, settings, inputs, start, seam
        As for `plan_layer`.

    Returns
    -------
    LayerPaths

    See Also
    --------
    plan_layer : with the walls and areas.
    slicelab.printing.planner.plan : every layer of a part, with skins, bridges and supports.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (10, 6, 1)), (0, 0, .5), (0, 0, 1))
    >>> lp = layer_paths(s, PrintSettings(pixel_size=0.1))
    >>> len(lp.external_contour_segments), len(lp.internal_contour_segments), len(lp.filling_segments)
    (1, 1, 1)
    >>> lp.sequence[:2]
    (('internal', 0), ('external', 0))
    """
    return plan_layer(section, settings, inputs, start=start, seam=seam).paths


def layer_areas(per: Perimeters, solid, inner_level: float) -> LayerAreas:
    """A layer's material area, the area inside its last perimeter (deeper than `inner_level`), its
    solid part (pixel counts, mm^2), and the length of its sparse filling region's boundary (mm).

    Counted on the distance fields' blocks: blocks deep inside count whole.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (10, 6, 1)), (0, 0, .5), (0, 0, 1))
    >>> a = plan_layer(s, PrintSettings(pixel_size=0.1)).areas
    >>> float(a.material), float(a.inner)   # (pixels deeper than two lines: 8.4 x 4.4 mm and the rim of pixels)
    (60.0, 38.25)
    """
    from ..geometry.blocks import FULL
    from .grid.masks import bits_in_blocks
    edge = sum(float(np.hypot(*(np.concatenate((r[1:], r[:1])) - r).T).sum())
               for q in per.fill for r in (q.exterior, *q.holes))
    total = inner = sol = 0.0
    p = None
    for f in per.fields:  # over tiles
        g = f.grid.blocks
        p = f.grid.pixel_size
        whole = g.n_full * g.size ** 2
        region = f.grid.bits & (f.blocks >= inner_level)
        total += np.count_nonzero(f.grid.bits) + whole
        inner += np.count_nonzero(region) + whole
        if solid is not None:
            sol += np.count_nonzero(region & bits_in_blocks(solid, g.rows, g.cols, g.size))
            fr, fc = np.nonzero(g.table == FULL)
            sol += np.count_nonzero(bits_in_blocks(solid, fr + g.row0, fc + g.col0, g.size))
    if p is None:
        return LayerAreas(0.0, 0.0, 0.0, edge)
    return LayerAreas(total * p * p, inner * p * p, sol * p * p, edge)


# ---------------------------------------------------------------------- a layer of a print
#: A plan's per-layer overhang summary, as a record (`slicelab.printing.PrintPlan.overhangs`).
OVERHANG_FIELDS = ("area", "mid_air", "bridges", "x", "y", "angle")
#: A plan's per-layer areas, as a record (`slicelab.printing.PrintPlan.areas`).
AREA_FIELDS = ("material", "inner", "solid", "fill_edge")


@dataclass(frozen=True)
class OverhangSummary:
    """What hangs in a layer (`slicelab.printing.steps.overhangs.LayerOverhangs`), in numbers.

    Attributes
    ----------
    area : float
        Material over nothing beyond the overhang threshold and not bridged (mm^2).
    mid_air : int
        Islands that start with nothing under them.
    bridges : int
        Bridges laid.
    x, y : float
        A point of the largest unheld part (part coordinates; NaN if none).
    angle : float
        The steepest overhang measured (degrees from the vertical; 0 within the threshold).
    """

    area: float = 0.0
    mid_air: int = 0
    bridges: int = 0
    x: float = float("nan")
    y: float = float("nan")
    angle: float = 0.0

    @classmethod
    def of(cls, ov) -> "OverhangSummary":
        """The summary of a `LayerOverhangs` (None: the first layer, on the bed)."""
        if ov is None:
            return cls()
        x, y = ov.where if ov.where is not None else (np.nan, np.nan)
        return cls(ov.overhang_area, ov.mid_air, len(ov.bridges), x, y, ov.angle)


@dataclass(frozen=True, eq=False)
class LayerResult:
    """One layer of a print as the planner's workers hand it back.

    Attributes
    ----------
    index : int
    paths : LayerPaths
        Its toolpaths at its height (skirt and brim included, overhang perimeters marked).
    areas : LayerAreas
    overhang : OverhangSummary
    unheld : tuple of (k, 2) ndarray
        The outlines of what hangs unheld (for the supports).
    text : object
        Its G-code, when the workers format it (`plan`'s ``layer_text``).
    drawing : object
        Its SVG, when the workers draw it (`plan`'s ``layer_drawing``).
    """

    index: int
    paths: LayerPaths
    areas: LayerAreas = field(default_factory=LayerAreas)
    overhang: OverhangSummary = field(default_factory=OverhangSummary)
    unheld: tuple = ()
    text: object = None
    drawing: object = None


class LayerWindow:
    """The masks step for a run of layers: each layer's material mask, and the raster of the layer
    planned, made when the first layer that reads them comes and dropped when the last has.

    Parameters
    ----------
    sections : dict
        Layer index -> section: the layers planned and every layer their skins read.
    n : int
        Layers in the part.
    settings : PrintSettings
    """

    def __init__(self, sections: dict, n: int, settings: PrintSettings):
        self.sections, self.n, self.s = sections, n, settings
        s = settings
        self.band = perimeter_band(s.line_width, s.n_perimeters, s.infill_overlap, s.pixel_size)
        self.masks: dict = {}
        self.rasters: dict = {}
        self.bands: dict = {}

    def reach(self, k: int) -> None:
        """Masks of the layers layer k's skins read, and of none below them; the raster of layer k
        (its islands and the edges that bound its material: only a layer planned needs them)."""
        from .grid.raster import layer_mask
        s, masks = self.s, self.masks
        for j in [j for j in masks if j < k - s.bottom_layers - 1]:  # over the few left behind
            del masks[j]
            self.bands.pop(j, None)
        for j in range(max(0, k - s.bottom_layers - 1), min(self.n, k + s.top_layers + 1)):  # the window
            if j not in masks:
                masks[j] = layer_mask(self.sections[j], s.pixel_size, rule=s.rule, band=self.band)
        if k not in self.rasters:
            self.rasters.clear()
            self.rasters[k] = rasterize(self.sections[k], s.pixel_size, rule=s.rule, band=self.band,
                                        tile=masks[k])


    def shell_band(self, j: int):
        """The pixels of layer j within its perimeters' width of its outline (None for an empty
        layer): where its perimeters lie (`slicelab.printing.steps.skins.vertical_shell`), made
        once for the layers that read it."""
        if j not in self.bands:
            from .grid.masks import erode_mask, reach_disc
            m, s = self.masks.get(j), self.s
            self.bands[j] = None if m is None else m - erode_mask(m, reach_disc(s.n_perimeters * s.line_width,
                                                                             s.pixel_size))
        return self.bands[j]


def skins_step(k: int, window: LayerWindow, s: PrintSettings):
    """The skins step of layer k: its solid skin, with its vertical shell, and its top skin
    (`slicelab.printing.steps.skins`)."""
    from .steps.skins import layer_skins, vertical_shell
    shell = vertical_shell(k, window.masks, window.shell_band, s.skins) \
        if s.ensure_vertical_shell_thickness and s.infill_density < 1 and s.n_perimeters > 0 else None
    return layer_skins(k, window.masks, s.skins, s.line_width, shell)


def layer_inputs(k: int, window: LayerWindow, s: PrintSettings, below_solid):
    """The skins and overhangs steps of layer k: its `LayerInputs`, its `LayerOverhangs` (None on
    the first layer) and its solid skin (the next layer's `below_solid`)."""
    from .steps.overhangs import EDGE_MARGIN, layer_overhangs
    from .steps.skins import internal_bridge
    masks, rasters, sections = window.masks, window.rasters, window.sections
    solid, top = skins_step(k, window, s)
    solid_angle = (s.infill_angle + 90.0 * (k % 2)) if s.solid_angle is None else s.solid_angle
    ov = None
    if k > 0 and masks[k] is not None:  # the first layer lies on the bed
        edge_band = s.n_perimeters * s.line_width + EDGE_MARGIN if s.dont_support_bridges else None
        ov = layer_overhangs(masks[k], masks.get(k - 1), s.layer_height, threshold=s.overhang_threshold,
                             islands=rasters[k], edge_band=edge_band, angle=solid_angle,
                             below_section=sections.get(k - 1), anchor=s.bridge_anchor)
    bridges = list(ov.bridges) if ov else []
    for b in bridges:  # (a bridge's anchors over the material below are filled too: with its lines)
        solid = b.mask if solid is None else solid | b.mask
    if s.infill_density < 1 and k > 0:  # a skin's first layer over sparse infill bridges it
        below = masks.get(k - 1)
        if below is not None and solid is not None and s.n_perimeters > 0:
            # Not over the perimeters below (they are solid) but for the inner half of the last
            # one: the filling's region ends a little inside that, well within the bridge's.
            from .grid.masks import erode_mask, reach_disc
            below = erode_mask(below, reach_disc((s.n_perimeters - 0.5) * s.line_width, s.pixel_size))
        inner = internal_bridge(solid, below, below_solid, s.line_width, solid_angle)
        bridges += [inner] if inner is not None else []
    return LayerInputs(k, rasters[k], solid, top, tuple(bridges), solid_angle), ov, solid


def finish_layer(k: int, window: LayerWindow, s: PrintSettings, lp: LayerPaths, skirt=(), brim=()) -> LayerPaths:
    """The skirt step's loops put first, and the overhang perimeters marked against the layer below."""
    from .steps.overhangs import mark_overhangs
    from .steps.skirt import with_skirt
    lp = with_skirt(lp, skirt, brim)
    below = window.masks.get(k - 1)
    if k > 0 and below is not None:
        lp = mark_overhangs(lp, below, window.sections[k - 1], rule=s.rule)
    return lp


def at_height(lp: LayerPaths, z: float) -> LayerPaths:
    """The toolpaths at height `z`, their sums made (on the worker: they travel with the layer)."""
    lp = replace(lp, z=float(z))
    lp.extruded_area()
    return lp


def records(rows, names) -> np.ndarray:
    """Rows of numbers as a record array with the fields `names` (a plan's areas and overhangs).

    Examples
    --------
    >>> r = records([(1.0, 2.0)], ("a", "b"))
    >>> float(r["b"][0]), r.shape
    (2.0, (1,))
    """
    out = np.zeros(len(rows), dtype=[(n, np.float64) for n in names])
    for name, column in zip(names, np.asarray(rows, np.float64).reshape(-1, len(names)).T):
        out[name] = column
    return out
