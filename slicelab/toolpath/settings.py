"""Print settings, in groups: what each stage of the slicer reads.

`PrintSettings` holds ten small frozen groups, one per concern: `Extrusion`
(layers, lines, nozzle, filament, the G-code resolution), `Walls` (seams and
the order of perimeters), `Infill`, `Skins` (and the overhang threshold),
`Supports`,
`Motion` (speeds, retraction, acceleration), `Cooling` (temperatures and the
fan), `Adhesion` (skirt and brim), `Machine` (bed, height, flavour, start and
end G-code, the limits the printer sets) and `Raster` (the pixel grid of the
layers). Every field has one name across the groups, so a setting can be
given and read by its name alone (``PrintSettings(layer_height=0.3).layer_height``)
or by its group (``PrintSettings(extrusion=Extrusion(layer_height=0.3)).extrusion``);
settings files and the command line use the plain names.

See Also
--------
slicelab.toolpath.printers : printer profiles and settings files.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace

import numpy as np

__all__ = ["Extrusion", "Walls", "Infill", "Skins", "Supports", "Motion", "Cooling", "Adhesion", "Machine", "Raster", "GROUPS",
           "PrintSettings", "settings_dict", "setting_names"]


@dataclass(frozen=True)
class Extrusion:
    """Layers and lines: heights, line width, perimeters, nozzle and filament (mm), the flow
    multiplier (and its share for bridge lines), and `gcode_resolution`, the tolerance every path
    is simplified to (PrusaSlicer's)."""

    layer_height: float = 0.2
    first_layer_height: float = 0.2
    line_width: float = 0.4
    n_perimeters: int = 2
    nozzle_diameter: float = 0.4
    filament_diameter: float = 1.75
    extrusion_multiplier: float = 1.0
    gcode_resolution: float = 0.0125
    bridge_flow_ratio: float = 1.0


@dataclass(frozen=True)
class Walls:
    """Perimeter loops: where each starts (`seam_position`: ``"aligned"`` with the layer below,
    ``"rear"`` or ``"nearest"`` the nozzle) and whether an island's outer perimeter goes first
    (by default the innermost goes first and the outer one last)."""

    seam_position: str = "aligned"
    external_perimeters_first: bool = False


@dataclass(frozen=True)
class Infill:
    """Sparse filling: density (a fraction), angle (degrees), a pattern of
    `slicelab.toolpath.patterns.PATTERNS`, and its overlap with the perimeters (line widths)."""

    infill_density: float = 0.2
    infill_angle: float = 45.0
    infill_pattern: str = "rectilinear"
    infill_overlap: float = 0.15


@dataclass(frozen=True)
class Skins:
    """Solid skins: how many layers at the top and bottom, and their angle (None: the infill's,
    turned 90 degrees every layer); the overhang angle from the vertical (degrees) up to which a
    wall holds itself (`slicelab.toolpath.overhangs`): beyond it, material over nothing is a bridge
    when held on two sides (or on one, `Supports.dont_support_bridges`), else unheld."""

    top_layers: int = 3
    bottom_layers: int = 3
    solid_angle: float | None = None
    overhang_threshold: float = 50.0


@dataclass(frozen=True)
class Supports:
    """Support material (`slicelab.toolpath.supports`): `support` is ``"off"``, ``"auto"``
    (under every unheld overhang, standing on the bed or the part) or ``"bed"`` (only where a
    column reaches the bed); sparse lines with a gap of `support_spacing` between them (so a
    line width more from centre to centre, as PrusaSlicer counts it), and
    `support_interface_layers` denser layers on top (gap `support_interface_spacing`); a gap
    of `support_xy_gap` (mm) to the part beside it and `support_z_gap_layers` layers under it.
    With `dont_support_bridges` (PrusaSlicer's default), material over nothing held by the layer
    below on one side only is bridged out from that side, and only a band along its outline (the
    perimeters and 2 mm more, `slicelab.toolpath.overhangs.EDGE_MARGIN`) is unheld: supports hold
    that band; without it, such material is unheld whole. Held on two sides, it is a bridge either
    way. `support_sheath` (PrusaSlicer's default too) puts a loop around each region of sparse
    support, so that a narrow band stands."""

    support: str = "off"
    support_spacing: float = 2.5
    support_interface_spacing: float = 0.2
    support_interface_layers: int = 2
    support_xy_gap: float = 0.6
    support_z_gap_layers: int = 1
    dont_support_bridges: bool = True
    support_sheath: bool = True


@dataclass(frozen=True)
class Motion:
    """Speeds by extrusion kind and for travel (mm/s), retraction and lift (mm), and the
    acceleration (mm/s^2) and jerk (mm/s) of the print-time estimate. Perimeter loops shorter
    than a 6.5 mm circle (PrusaSlicer's small perimeters) print at `small_perimeter_speed`, so that
    a small feature has time to cool."""

    perimeter_speed: float = 40.0
    external_perimeter_speed: float = 25.0
    infill_speed: float = 80.0
    solid_infill_speed: float = 60.0
    top_solid_infill_speed: float = 40.0
    bridge_speed: float = 25.0
    small_perimeter_speed: float = 15.0
    support_speed: float = 50.0
    gap_fill_speed: float = 20.0
    first_layer_speed: float = 20.0
    travel_speed: float = 150.0
    retraction_length: float = 0.8
    retraction_speed: float = 35.0
    retract_min_travel: float = 1.0
    z_lift: float = 0.2
    acceleration: float = 1000.0
    jerk: float = 8.0


@dataclass(frozen=True)
class Cooling:
    """Temperatures (degrees Celsius) and cooling: the part-cooling fan is off for the first
    `fan_off_layers` layers, then at `fan_speed` percent, raised towards full for layers that
    print in less than `fan_below_layer_time` seconds; a layer quicker than `min_layer_time`
    is slowed to last that long (speeds not below `min_print_speed`, mm/s)."""

    nozzle_temperature: float = 210.0
    bed_temperature: float = 60.0
    fan_speed: float = 100.0
    fan_off_layers: int = 1
    fan_below_layer_time: float = 60.0
    min_layer_time: float = 5.0
    min_print_speed: float = 10.0


@dataclass(frozen=True)
class Adhesion:
    """Around the first layer: `skirt_loops` loops `skirt_distance` away, and a brim
    `brim_width` wide (mm; 0: none)."""

    skirt_loops: int = 1
    skirt_distance: float = 6.0
    brim_width: float = 0.0


@dataclass(frozen=True)
class Machine:
    """The printer: bed (size and the centre the part goes to, mm), height, G-code flavour,
    start and end G-code templates (None: the flavour's), and the limits it sets: temperatures,
    layer height at most `max_layer_ratio` x the nozzle, line width within `line_width_ratio`
    (low, high) x the nozzle."""

    bed_size: tuple = (250.0, 210.0)
    max_height: float = 210.0
    bed_center: tuple | None = None
    gcode_flavor: str = "marlin"
    start_gcode: str | None = None
    end_gcode: str | None = None
    max_nozzle_temperature: float = 300.0
    max_bed_temperature: float = 120.0
    max_layer_ratio: float = 0.8
    line_width_ratio: tuple = (0.6, 2.5)


@dataclass(frozen=True)
class Raster:
    """The layers' pixel grid: pixel size (mm) and the fill rule for overlapping shells.

    The perimeters are moved onto the exact offsets of the section whatever
    the pixel size; the pixels set how finely thin walls, gap fill and the
    skins' masks are resolved. Left out (None), the pixel is half the line
    width (0.2 mm for 0.4 mm lines); it may not be coarser than the line width.
    """

    pixel_size: float | None = None
    rule: str = "nonzero"


#: The groups of `PrintSettings`, by attribute name.
GROUPS = {"extrusion": Extrusion, "walls": Walls, "infill": Infill, "skins": Skins, "supports": Supports,
          "motion": Motion, "cooling": Cooling,
          "adhesion": Adhesion, "machine": Machine, "raster": Raster}
_GROUP_OF = {f.name: g for g, cls in GROUPS.items() for f in fields(cls)}


def setting_names() -> tuple:
    """Every setting's plain name, group by group.

    Examples
    --------
    >>> names = setting_names()
    >>> "layer_height" in names and "pixel_size" in names, len(names) == len(set(names))
    (True, True)
    """
    return tuple(_GROUP_OF)


@dataclass(frozen=True, init=False)
class PrintSettings:
    """What a print needs to know (mm, mm/s, mm/s2, degrees Celsius, percent), in groups.

    Parameters
    ----------
    extrusion, walls, infill, skins, supports, motion, cooling, adhesion, machine, raster : optional
        The groups (`Extrusion`, ...); left out, their defaults.
    **settings
        Any field of any group by its plain name, applied over the groups.

    Every field reads by its plain name too (``s.layer_height`` is
    ``s.extrusion.layer_height``). Wrong values raise ValueError, its message
    beginning with the field's name; the printer's limits are checked
    (`Machine`).

    Examples
    --------
    >>> s = PrintSettings(layer_height=0.3, infill=Infill(infill_density=0.4))
    >>> s.extrusion.layer_height, s.layer_height, s.infill_density
    (0.3, 0.3, 0.4)
    >>> s.filament_area.__round__(4)
    2.4053
    >>> PrintSettings(fan_speed=120)
    Traceback (most recent call last):
    ...
    ValueError: fan_speed must be a percentage from 0 to 100, got 120
    """

    extrusion: Extrusion
    walls: Walls
    infill: Infill
    skins: Skins
    supports: Supports
    motion: Motion
    cooling: Cooling
    adhesion: Adhesion
    machine: Machine
    raster: Raster

    def __init__(self, extrusion=None, walls=None, infill=None, skins=None, supports=None, motion=None,
                 cooling=None, adhesion=None, machine=None, raster=None, **settings):
        given = dict(extrusion=extrusion, walls=walls, infill=infill, skins=skins, supports=supports, motion=motion,
                     cooling=cooling, adhesion=adhesion, machine=machine, raster=raster)
        unknown = sorted(set(settings) - set(_GROUP_OF))
        if unknown:
            raise TypeError(f"PrintSettings got unknown settings: {', '.join(unknown)}")
        for name, cls in GROUPS.items():
            group = given[name] if given[name] is not None else cls()
            if not isinstance(group, cls):
                raise TypeError(f"{name} must be a {cls.__name__}, got {type(group).__name__}")
            mine = {k: v for k, v in settings.items() if _GROUP_OF[k] == name}
            object.__setattr__(self, name, cls(**{**asdict(group), **mine}) if mine else group)
        self._validate()

    def __getattr__(self, name):
        group = _GROUP_OF.get(name)
        if group is None:
            raise AttributeError(f"PrintSettings has no setting {name!r}")
        value = getattr(object.__getattribute__(self, group), name)
        if value is None and name == "pixel_size":  # left out: half the line width, whatever it is
            return self.line_width / 2
        return value

    def _set(self, name: str, value) -> None:
        """Normalise a field while validating (its group replaced, never changed in place)."""
        group = _GROUP_OF[name]
        object.__setattr__(self, group, replace(object.__getattribute__(self, group), **{name: value}))

    def _validate(self) -> None:
        from .patterns import PATTERNS
        positive = ("layer_height", "first_layer_height", "line_width", "nozzle_diameter", "filament_diameter",
                    "extrusion_multiplier", "perimeter_speed", "external_perimeter_speed", "infill_speed",
                    "solid_infill_speed", "top_solid_infill_speed", "bridge_speed", "small_perimeter_speed", "bridge_flow_ratio", "gap_fill_speed", "first_layer_speed", "travel_speed",
                    "retraction_speed", "min_print_speed", "support_speed", "support_spacing",
                    "support_interface_spacing", "pixel_size", "acceleration", "jerk", "max_height")
        for name in positive:
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0 and math.isfinite(v)):
                raise ValueError(f"{name} must be a positive number, got {v!r}")
        for name in ("n_perimeters", "top_layers", "bottom_layers", "fan_off_layers", "skirt_loops",
                     "support_interface_layers", "support_z_gap_layers"):
            v = getattr(self, name)
            if not (isinstance(v, (int, np.integer)) and v >= 0):
                raise ValueError(f"{name} must be a whole number >= 0, got {v!r}")
        if not 0 <= self.infill_density <= 1:
            raise ValueError(f"infill_density must be in [0, 1], got {self.infill_density!r}")
        if not (isinstance(self.overhang_threshold, (int, float)) and 0 < self.overhang_threshold < 90):
            raise ValueError(f"overhang_threshold must be an angle from the vertical between 0 and 90 degrees, "
                             f"got {self.overhang_threshold!r}")
        for name in ("retraction_length", "retract_min_travel", "z_lift", "skirt_distance", "brim_width",
                     "fan_below_layer_time", "min_layer_time", "support_xy_gap"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v >= 0 and math.isfinite(v)):
                raise ValueError(f"{name} must be a number >= 0, got {v!r}")
        if self.pixel_size > self.line_width:
            raise ValueError(f"pixel_size must be at most the line width ({self.line_width:g} mm), "
                             f"got {self.pixel_size!r}")
        if not (isinstance(self.gcode_resolution, (int, float)) and 0 <= self.gcode_resolution < self.line_width):
            raise ValueError(f"gcode_resolution must be >= 0 and under the line width ({self.line_width:g} mm), "
                             f"got {self.gcode_resolution!r}")
        if not (isinstance(self.fan_speed, (int, float)) and 0 <= self.fan_speed <= 100):
            raise ValueError(f"fan_speed must be a percentage from 0 to 100, got {self.fan_speed!r}")
        if self.support not in ("off", "auto", "bed"):
            raise ValueError(f"support must be off, auto or bed, got {self.support!r}")
        if self.seam_position not in ("nearest", "rear", "aligned"):
            raise ValueError(f"seam_position must be nearest, rear or aligned, got {self.seam_position!r}")
        for name in ("external_perimeters_first", "dont_support_bridges", "support_sheath"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise ValueError(f"{name} must be true or false, got {getattr(self, name)!r}")
        if self.rule not in ("nonzero", "evenodd"):
            raise ValueError(f"rule must be 'nonzero' or 'evenodd', got {self.rule!r}")
        if self.infill_pattern not in PATTERNS:
            raise ValueError(f"infill_pattern must be one of {', '.join(sorted(PATTERNS))}, "
                             f"got {self.infill_pattern!r}")
        for name in ("bed_size", "bed_center"):
            v = getattr(self, name)
            if v is None and name == "bed_center":
                continue
            try:
                ok = len(v) == 2 and all(math.isfinite(float(x)) for x in v)
            except (TypeError, ValueError):
                ok = False
            if not ok or (name == "bed_size" and min(float(x) for x in v) <= 0):
                raise ValueError(f"{name} must be two {'positive ' if name == 'bed_size' else ''}numbers "
                                 f"(x, y in mm), got {v!r}")
            self._set(name, tuple(float(x) for x in v))
        self._check_physical()
        cx, cy = self.centre
        if not (0 <= cx <= self.bed_size[0] and 0 <= cy <= self.bed_size[1]):
            raise ValueError(f"bed_center ({cx:g}, {cy:g}) must lie on the bed "
                             f"(0 to {self.bed_size[0]:g}, 0 to {self.bed_size[1]:g} mm)")

    def _check_physical(self) -> None:
        """What the printer and the nozzle allow (one sentence per refusal, naming the field)."""
        from .printers import FLAVORS
        try:
            ratio = tuple(float(v) for v in self.line_width_ratio)
        except (TypeError, ValueError):
            ratio = ()
        if len(ratio) != 2 or not 0 < ratio[0] <= ratio[1]:
            raise ValueError(f"line_width_ratio must be two numbers 0 < low <= high, got {self.line_width_ratio!r}")
        self._set("line_width_ratio", ratio)
        if self.gcode_flavor not in FLAVORS:
            raise ValueError(f"gcode_flavor must be one of {', '.join(FLAVORS)}, got {self.gcode_flavor!r}")
        low, high = (float(v) for v in self.line_width_ratio)
        d = self.nozzle_diameter
        for name in ("layer_height", "first_layer_height"):
            v = getattr(self, name)
            if v > self.max_layer_ratio * d + 1e-12:
                raise ValueError(f"{name} {v:g} mm is more than {self.max_layer_ratio:g} x the {d:g} mm nozzle "
                                 f"({self.max_layer_ratio * d:g} mm): the layers would not bond")
        if not (low * d - 1e-12 <= self.line_width <= high * d + 1e-12):
            raise ValueError(f"line_width {self.line_width:g} mm is outside {low:g} to {high:g} x the {d:g} mm "
                             f"nozzle ({low * d:g} to {high * d:g} mm)")
        for name, limit in (("nozzle_temperature", self.max_nozzle_temperature),
                            ("bed_temperature", self.max_bed_temperature)):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and 0 <= v <= limit):
                raise ValueError(f"{name} {v:g} C is outside what the printer allows (0 to {limit:g} C)"
                                 if isinstance(v, (int, float)) else f"{name} must be a number, got {v!r}")

    @property
    def centre(self) -> tuple:
        """Where the part's footprint is centred on the bed (x, y; mm)."""
        return tuple(self.bed_center) if self.bed_center is not None else (self.bed_size[0] / 2,
                                                                          self.bed_size[1] / 2)

    @property
    def filament_area(self) -> float:
        """Cross-section of the filament (mm^2)."""
        return math.pi * (self.filament_diameter / 2) ** 2


def settings_dict(s: PrintSettings) -> dict:
    """The settings as a plain dict, field by field (for file headers and settings files).

    Examples
    --------
    >>> d = settings_dict(PrintSettings())
    >>> d["n_perimeters"], d["infill_density"]
    (2, 0.2)
    """
    return {k: getattr(s, k) for g in GROUPS for k in asdict(getattr(s, g))}  # defaults resolved
