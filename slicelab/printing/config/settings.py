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
slicelab.printing.config.printers : printer profiles and settings files.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields

from .fields import check_fields, check_template, setting

__all__ = ["Extrusion", "Walls", "Infill", "Skins", "Supports", "Motion", "Cooling", "Adhesion", "Machine", "Raster", "GROUPS",
           "PrintSettings", "settings_dict", "setting_names", "template_names", "sized_settings", "FLAVORS", "render_gcode"]

#: G-code dialects; each reads the same moves, they differ in the start and end blocks.
FLAVORS = ("marlin", "klipper", "reprapfirmware")


def _patterns() -> tuple:
    from ..fill import PATTERNS
    return tuple(sorted(PATTERNS))


def _placements() -> tuple:
    from ..supports.columns import PLACEMENTS
    return PLACEMENTS


def _support_styles() -> tuple:
    from ..supports import SUPPORTS
    return tuple(SUPPORTS)


def _flavors() -> tuple:
    return FLAVORS


class _Group:
    """What every settings group does when made: check each field against its declaration
    (`slicelab.printing.config.fields.check_field`)."""

    def __post_init__(self):
        check_fields(self)


@dataclass(frozen=True)
class Extrusion(_Group):
    """Layers and lines: heights, line width, perimeters, nozzle and filament (mm), the flow
    multiplier (and its share for bridge lines), and `gcode_resolution`, the tolerance every path
    is simplified to (PrusaSlicer's)."""

    layer_height: float = setting(0.2, "height of every layer but the first", "mm", 0.01, 2.0)
    first_layer_height: float = setting(0.2, "height of the first layer", "mm", 0.01, 2.0)
    line_width: float = setting(0.4, "extrusion width of every line", "mm", 0.05, 10.0)
    n_perimeters: int = setting(2, "perimeters around every island", "", 0, 50)
    nozzle_diameter: float = setting(0.4, "the nozzle's bore", "mm", 0.05, 5.0)
    filament_diameter: float = setting(1.75, "diameter of the filament", "mm", 0.5, 5.0)
    extrusion_multiplier: float = setting(1.0, "flow of every line, against the computed flow", "", 0.05, 5.0)
    gcode_resolution: float = setting(0.0125, "every path simplified to this tolerance", "mm", 0.0, 1.0)
    bridge_flow_ratio: float = setting(1.0, "flow of bridge lines, against other lines'", "", 0.05, 5.0)


@dataclass(frozen=True)
class Walls(_Group):
    """Perimeter loops: where each starts (`seam_position`: ``"aligned"`` with the layer below,
    ``"rear"``, ``"nearest"`` the nozzle, or ``"random"`` along the loop, seeded by the layer) and whether an island's outer perimeter goes first
    (by default the innermost goes first and the outer one last)."""

    seam_position: str = setting("aligned", "where perimeter loops start",
                                 choices=("aligned", "rear", "nearest", "random"))
    external_perimeters_first: bool = setting(False, "print each island's outer perimeter before the inner ones")


@dataclass(frozen=True)
class Infill(_Group):
    """Sparse filling: density (a fraction), angle (degrees), a pattern of
    `slicelab.printing.fill.PATTERNS`, its overlap with the perimeters (line widths), and the
    area (mm^2) under which a region of it is filled solid (PrusaSlicer's
    ``solid_infill_below_area``)."""

    infill_density: float = setting(0.2, "sparse infill density, a fraction", "", 0.0, 1.0)
    infill_angle: float = setting(45.0, "direction of the infill lines, turned 90 degrees every layer",
                                  "degrees", -360.0, 360.0)
    infill_pattern: str = setting("rectilinear", "sparse infill pattern", choices=_patterns)
    infill_overlap: float = setting(0.15, "overlap of the infill with the perimeters, in line widths", "",
                                    0.0, 1.0)
    solid_infill_below_area: float = setting(70.0, "a region of sparse infill smaller than this is filled "
                                                   "solid", "mm2", 0.0, 1e6)


@dataclass(frozen=True)
class Skins(_Group):
    """Solid skins: how many layers at the top and bottom, and their angle (None: the infill's,
    turned 90 degrees every layer); the overhang angle from the vertical (degrees) up to which a
    wall holds itself (`slicelab.printing.steps.overhangs`): beyond it, material over nothing is a bridge
    when held on two sides (or on one, `Supports.dont_support_bridges`), else unheld, its lines
    running `bridge_anchor` mm onto the material below; and whether
    the shell stays as thick as the skins where the surface slopes (PrusaSlicer's
    ``ensure_vertical_shell_thickness``: `slicelab.printing.steps.skins.vertical_shell`)."""

    top_layers: int = setting(3, "solid layers under every top surface", "layers", 0, 100)
    bottom_layers: int = setting(3, "solid layers over every bottom surface", "layers", 0, 100)
    solid_angle: float | None = setting(None, "direction of solid lines (left out: the infill's)", "degrees",
                                        -360.0, 360.0, optional=True, kind=float)
    overhang_threshold: float = setting(50.0, "steepest wall, from the vertical, that holds itself", "degrees",
                                        0.0, 90.0, above=True, below=True)
    bridge_anchor: float = setting(3.0, "how far a bridge's lines run onto the material below it", "mm", 0.0, 50.0)
    ensure_vertical_shell_thickness: bool = setting(True, "solid infill where a layer within the skins' reach "
                                                          "above or below has its perimeters, so that a sloped "
                                                          "shell stays as thick as the skins")


@dataclass(frozen=True)
class Supports(_Group):
    """Support material (`slicelab.printing.supports`): `support` is ``"off"``, ``"auto"``
    (under every unheld overhang, standing on the bed or the part) or ``"bed"`` (only where a
    column reaches the bed), in a style of `slicelab.printing.supports.SUPPORTS`; sparse lines with a gap of `support_spacing` between them (so a
    line width more from centre to centre, as PrusaSlicer counts it), and
    `support_interface_layers` denser layers on top (gap `support_interface_spacing`); a gap
    of `support_xy_gap` (mm) to the part beside it and `support_z_gap_layers` layers under it.
    With `dont_support_bridges` (PrusaSlicer's default), material over nothing held by the layer
    below on one side only is bridged out from that side, and only a band along its outline (the
    perimeters and 2 mm more, `slicelab.printing.steps.overhangs.EDGE_MARGIN`) is unheld: supports hold
    that band; without it, such material is unheld whole. Held on two sides, it is a bridge either
    way. `support_sheath` (PrusaSlicer's default too) puts a loop around each region of sparse
    support, so that a narrow band stands."""

    support: str = setting("off", "support material under overhangs and mid-air islands: off (they are "
                                  "reported), auto (standing on the bed or the part), bed (only where they "
                                  "reach the bed)", choices=_placements)
    support_style: str = setting("snug", "the shape of the support regions", choices=_support_styles)
    support_spacing: float = setting(2.5, "gap between sparse support lines", "mm", 0.0, 50.0, above=True)
    support_interface_spacing: float = setting(0.2, "gap between interface lines", "mm", 0.0, 50.0, above=True)
    support_interface_layers: int = setting(2, "dense layers on top of the support", "layers", 0, 20)
    support_xy_gap: float = setting(0.6, "gap between the support and the part beside it", "mm", 0.0, 20.0)
    support_z_gap_layers: int = setting(1, "layers left empty between the support and the part over it",
                                        "layers", 0, 10)
    dont_support_bridges: bool = setting(True, "bridge what the layer below holds on one side only")
    support_sheath: bool = setting(True, "a loop around each region of sparse support")


def _speed(default: float, help: str):
    return setting(default, help, "mm/s", 0.0, 1000.0, above=True)


@dataclass(frozen=True)
class Motion(_Group):
    """Speeds by extrusion kind and for travel (mm/s), retraction and lift (mm), and two short
    hands for the printer's limits (`Machine`): `acceleration` (mm/s^2), when above 0, is the
    acceleration of printing, retracting and travel moves alike, in place of the three
    ``machine_max_acceleration_*`` of those moves; `jerk` (mm/s), when above 0, is the X and Y
    jerk in place of ``machine_max_jerk_x`` and ``_y``. Perimeter loops shorter
    than a 6.5 mm circle (PrusaSlicer's small perimeters) print at `small_perimeter_speed`, so that
    a small feature has time to cool."""

    perimeter_speed: float = _speed(40.0, "speed of inner perimeters")
    external_perimeter_speed: float = _speed(25.0, "speed of outer perimeters")
    infill_speed: float = _speed(80.0, "speed of sparse infill")
    solid_infill_speed: float = _speed(60.0, "speed of solid infill")
    top_solid_infill_speed: float = _speed(40.0, "speed of top solid infill")
    bridge_speed: float = _speed(25.0, "speed of bridge lines")
    small_perimeter_speed: float = _speed(15.0, "speed of perimeter loops shorter than a 6.5 mm circle")
    support_speed: float = _speed(50.0, "speed of support lines")
    gap_fill_speed: float = _speed(20.0, "speed of gap fill")
    first_layer_speed: float = _speed(20.0, "speed of every line of the first layer")
    travel_speed: float = _speed(150.0, "speed of moves without extrusion")
    retraction_length: float = setting(0.8, "filament pulled back before a travel", "mm", 0.0, 20.0)
    retraction_speed: float = setting(35.0, "speed of retraction", "mm/s", 0.0, 500.0, above=True)
    retract_min_travel: float = setting(1.0, "shortest travel that retracts", "mm", 0.0, 1000.0)
    z_lift: float = setting(0.2, "nozzle lift on retracted travels", "mm", 0.0, 20.0)
    acceleration: float = setting(0.0, "one acceleration for printing, retracting and travel moves, in place of "
                                       "the machine_max_acceleration_extruding, _retracting and _travel limits "
                                       "(0: those)", "mm/s2", 0.0, 100000.0)
    jerk: float = setting(0.0, "one jerk for X and Y, in place of the machine_max_jerk_x and _y limits (0: those)",
                          "mm/s", 0.0, 1000.0)


@dataclass(frozen=True)
class Cooling(_Group):
    """Temperatures (degrees Celsius) and cooling: the part-cooling fan is off for the first
    `fan_off_layers` layers, then at `fan_speed` percent, raised towards full for layers that
    print in less than `fan_below_layer_time` seconds; a layer quicker than `min_layer_time`
    is slowed to last that long (speeds not below `min_print_speed`, mm/s)."""

    nozzle_temperature: float = setting(210.0, "nozzle temperature", "C", 0.0, 1000.0)
    bed_temperature: float = setting(60.0, "bed temperature", "C", 0.0, 1000.0)
    fan_speed: float = setting(100.0, "part-cooling fan after the first layers", "%", 0.0, 100.0)
    fan_off_layers: int = setting(1, "first layers printed with the fan off", "layers", 0, 100000)
    fan_below_layer_time: float = setting(60.0, "a layer quicker than this gets more fan", "s", 0.0, 3600.0)
    min_layer_time: float = setting(5.0, "a quicker layer is slowed to last this long", "s", 0.0, 3600.0)
    min_print_speed: float = _speed(10.0, "the slowest a layer is slowed to")


@dataclass(frozen=True)
class Adhesion(_Group):
    """Around the first layer: `skirt_loops` loops `skirt_distance` away, and a brim
    `brim_width` wide (mm; 0: none)."""

    skirt_loops: int = setting(1, "loops around the first layer; 0: no skirt", "", 0, 100)
    skirt_distance: float = setting(6.0, "gap between the skirt and the part", "mm", 0.0, 100.0)
    brim_width: float = setting(0.0, "brim around the first layer; 0: none", "mm", 0.0, 100.0)


@dataclass(frozen=True)
class Machine(_Group):
    """The printer: bed (size and the centre the part goes to, mm), height, G-code flavour,
    start and end G-code templates (None: the flavour's), and the limits it sets: temperatures,
    layer height at most `max_layer_ratio` x the nozzle, line width within `line_width_ratio`
    (low, high) x the nozzle.

    And its motion limits, named and defaulted as PrusaSlicer's machine limits (the first of its
    normal/silent pairs): the acceleration of printing, retracting and travel moves and of each
    axis (mm/s^2), each axis's largest feed rate (mm/s) and its jerk (mm/s, Marlin's classic
    jerk: the speed an axis may change by at once). With `machine_limits_usage`
    ``"emit_to_gcode"`` they are written at the top of the G-code in the flavour's commands
    (`slicelab.gcode.writer.machine_lines`) and the time estimate uses them
    (`slicelab.gcode.estimate.machine_limits`); ``"time_estimate_only"``: the estimate alone;
    ``"ignore"``: neither, the estimate taking PrusaSlicer's defaults as its own estimator does."""

    bed_size: tuple = setting((250.0, 210.0), "the bed (x, y)", "mm", 0.0, 10000.0, above=True, size=2)
    max_height: float = setting(210.0, "the printer's build height", "mm", 0.0, 10000.0, above=True)
    bed_center: tuple | None = setting(None, "where the part's footprint is centred on the bed (x, y)", "mm",
                                       0.0, 10000.0, size=2, optional=True, kind=float)
    gcode_flavor: str = setting("marlin", "the firmware's G-code dialect", choices=_flavors)
    start_gcode: str | None = setting(None, "G-code before the print ({setting} placeholders)", optional=True,
                                      kind=str)
    end_gcode: str | None = setting(None, "G-code after the print ({setting} placeholders)", optional=True,
                                    kind=str)
    max_nozzle_temperature: float = setting(300.0, "the hottest the nozzle may be set", "C", 0.0, 500.0,
                                            above=True)
    max_bed_temperature: float = setting(120.0, "the hottest the bed may be set", "C", 0.0, 200.0, above=True)
    max_layer_ratio: float = setting(0.8, "the thickest layer, against the nozzle", "", 0.0, 1.5, above=True)
    line_width_ratio: tuple = setting((0.6, 2.5), "the narrowest and widest line, against the nozzle", "",
                                      0.0, 10.0, above=True, size=2)
    machine_limits_usage: str = setting("emit_to_gcode", "the motion limits: written into the G-code and used by "
                                                         "the time estimate, used by the estimate only, or neither",
                                        choices=("emit_to_gcode", "time_estimate_only", "ignore"))
    machine_max_acceleration_extruding: float = setting(1500.0, "acceleration of printing moves (M204 P)", "mm/s2",
                                                        0.0, 100000.0, above=True)
    machine_max_acceleration_retracting: float = setting(1500.0, "acceleration of retractions (M204 R)", "mm/s2",
                                                         0.0, 100000.0, above=True)
    machine_max_acceleration_travel: float = setting(1500.0, "acceleration of travel moves (M204 T)", "mm/s2",
                                                     0.0, 100000.0, above=True)
    machine_max_acceleration_x: float = setting(9000.0, "largest acceleration of the X axis (M201)", "mm/s2",
                                                0.0, 100000.0, above=True)
    machine_max_acceleration_y: float = setting(9000.0, "largest acceleration of the Y axis (M201)", "mm/s2",
                                                0.0, 100000.0, above=True)
    machine_max_acceleration_z: float = setting(500.0, "largest acceleration of the Z axis (M201)", "mm/s2",
                                                0.0, 100000.0, above=True)
    machine_max_acceleration_e: float = setting(10000.0, "largest acceleration of the extruder (M201)", "mm/s2",
                                                0.0, 100000.0, above=True)
    machine_max_feedrate_x: float = setting(500.0, "largest feed rate of the X axis (M203)", "mm/s", 0.0, 10000.0,
                                            above=True)
    machine_max_feedrate_y: float = setting(500.0, "largest feed rate of the Y axis (M203)", "mm/s", 0.0, 10000.0,
                                            above=True)
    machine_max_feedrate_z: float = setting(12.0, "largest feed rate of the Z axis (M203)", "mm/s", 0.0, 10000.0,
                                            above=True)
    machine_max_feedrate_e: float = setting(120.0, "largest feed rate of the extruder (M203)", "mm/s", 0.0, 10000.0,
                                            above=True)
    machine_max_jerk_x: float = setting(10.0, "jerk of the X axis, the speed it may change by at once (M205)",
                                        "mm/s", 0.0, 1000.0)
    machine_max_jerk_y: float = setting(10.0, "jerk of the Y axis (M205)", "mm/s", 0.0, 1000.0)
    machine_max_jerk_z: float = setting(0.2, "jerk of the Z axis (M205)", "mm/s", 0.0, 1000.0)
    machine_max_jerk_e: float = setting(2.5, "jerk of the extruder (M205)", "mm/s", 0.0, 1000.0)


@dataclass(frozen=True)
class Raster(_Group):
    """The layers' pixel grid: pixel size (mm) and the fill rule for overlapping shells.

    The perimeters are moved onto the exact offsets of the section whatever
    the pixel size; the pixels set how finely thin walls, gap fill and the
    skins' masks are resolved. Left out (None), the pixel is half the line
    width (0.2 mm for 0.4 mm lines); it may not be coarser than the line width.
    """

    pixel_size: float | None = setting(None, "pixel grid of the layers (left out: half the line width)", "mm",
                                       0.005, 10.0, optional=True, kind=float)
    rule: str = setting("nonzero", "fill rule for overlapping shells", choices=("nonzero", "evenodd"))


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
    ValueError: fan_speed must be from 0 to 100 %, got 120
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

    def __init__(self, *, extrusion=None, walls=None, infill=None, skins=None, supports=None, motion=None,
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

    def _validate(self) -> None:
        """What no group can check alone (each checked its own fields when made): sizes against the
        line width and the nozzle, temperatures against the printer, the start and end G-code."""
        if self.pixel_size > self.line_width:
            raise ValueError(f"pixel_size must be at most the line width ({self.line_width:g} mm), "
                             f"got {self.pixel_size!r}")
        if not self.gcode_resolution < self.line_width:
            raise ValueError(f"gcode_resolution must be under the line width ({self.line_width:g} mm), "
                             f"got {self.gcode_resolution!r}")
        self._check_physical()
        cx, cy = self.centre
        if not (0 <= cx <= self.bed_size[0] and 0 <= cy <= self.bed_size[1]):
            raise ValueError(f"bed_center ({cx:g}, {cy:g}) must lie on the bed "
                             f"(0 to {self.bed_size[0]:g}, 0 to {self.bed_size[1]:g} mm)")
        numbers = template_names()
        for name in ("start_gcode", "end_gcode"):
            template = getattr(self, name)
            check_template(name, template, numbers)
            if template is not None:
                render_gcode(template, self, name=name)  # a format that does not fit its value ({x:d})

    def _check_physical(self) -> None:
        """What the printer and the nozzle allow (one sentence per refusal, naming the field)."""
        low, high = self.line_width_ratio
        if not low <= high:
            raise ValueError(f"line_width_ratio must be two numbers 0 < low <= high, got {self.line_width_ratio!r}")
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
            if v > limit:
                raise ValueError(f"{name} {v:g} C is outside what the printer allows (0 to {limit:g} C)")

    @property
    def centre(self) -> tuple:
        """Where the part's footprint is centred on the bed (x, y; mm)."""
        return tuple(self.bed_center) if self.bed_center is not None else (self.bed_size[0] / 2,
                                                                          self.bed_size[1] / 2)

    @property
    def filament_area(self) -> float:
        """Cross-section of the filament (mm^2)."""
        return math.pi * (self.filament_diameter / 2) ** 2

    @property
    def bridge_strand(self) -> float:
        """Cross-section (mm^2) of a bridge's strand: round, of the nozzle's diameter, times
        `bridge_flow_ratio`, as PrusaSlicer lays it. A strand over nothing is not flattened by a
        layer below, so its section is the nozzle's bore whatever the layer height and line width.

        References
        ----------
        .. [1] PrusaSlicer, ``src/libslic3r/Flow.cpp``: ``Flow::bridging_flow``, a round extrusion
           of diameter ``nozzle_diameter * sqrt(bridge_flow_ratio)``.

        Examples
        --------
        >>> round(PrintSettings(nozzle_diameter=0.4).bridge_strand, 4)   # pi 0.4^2 / 4
        0.1257
        >>> round(PrintSettings(nozzle_diameter=0.4, bridge_flow_ratio=0.8).bridge_strand, 4)
        0.1005
        """
        return math.pi * self.nozzle_diameter ** 2 / 4 * self.bridge_flow_ratio


def sized_settings() -> tuple:
    """The settings that are pairs of numbers (``bed_size``, ...).

    Examples
    --------
    >>> sized_settings()
    ('bed_size', 'bed_center', 'line_width_ratio')
    """
    return tuple(f.name for cls in GROUPS.values() for f in fields(cls) if f.metadata["size"])


def template_names() -> frozenset:
    """The settings a start or end G-code template may name: every single number, and the bed's
    ``bed_size_x`` and ``bed_size_y``.

    Examples
    --------
    >>> names = template_names()
    >>> "nozzle_temperature" in names, "bed_size_x" in names, "gcode_flavor" in names
    (True, True, False)
    """
    single = {f.name for cls in GROUPS.values() for f in fields(cls)
              if f.metadata["kind"] in (int, float) and not f.metadata["size"]}
    return frozenset(single | {"bed_size_x", "bed_size_y"})


def settings_dict(s: PrintSettings) -> dict:
    """The settings as a plain dict, field by field (for file headers and settings files).

    Examples
    --------
    >>> d = settings_dict(PrintSettings())
    >>> d["n_perimeters"], d["infill_density"]
    (2, 0.2)
    """
    return {k: getattr(s, k) for g in GROUPS for k in asdict(getattr(s, g))}  # defaults resolved


def render_gcode(template: str, settings, name: str = "start_gcode / end_gcode") -> str:
    """A start or end G-code template with the settings' ``{placeholders}`` filled in.

    Only the numeric settings (`template_names`) can be named, as
    ``{setting}`` or ``{setting:spec}``; `slicelab.printing.config.fields.check_template` refuses anything
    else when the settings are made.

    Examples
    --------
    >>> from slicelab.printing import PrintSettings
    >>> render_gcode("M190 S{bed_temperature:.0f} ; {bed_size_x:g} mm\\n", PrintSettings())
    'M190 S60 ; 250 mm\\n'
    """
    allowed = template_names()
    fields = {k: v for k, v in settings_dict(settings).items() if k in allowed}
    fields["bed_size_x"], fields["bed_size_y"] = settings.bed_size
    try:
        text = template.format(**fields)
    except (KeyError, IndexError, ValueError, AttributeError, TypeError) as exc:
        raise ValueError(f"{name}: unknown placeholder or bad format ({exc})") from None
    return text if text.endswith("\n") or not text else text + "\n"
