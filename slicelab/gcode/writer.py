"""G-code output of a print plan.

The G-code is Marlin-flavoured and written the way PrusaSlicer writes it, so
its G-code viewer and OctoPrint read it: absolute XYZ (G90), relative
extrusion (M83), per layer ``;LAYER_CHANGE``, ``;Z:``, ``;HEIGHT:`` and
``;LAYER:``, per path ``;TYPE:`` and ``;WIDTH:``, and at the end
``; filament used [mm] =``, ``; filament used [cm3] =`` and
``; estimated printing time (normal mode) = 1h 2m 3s``. Extrusion per move is
line width x layer height x length / filament cross-section (x the extrusion
multiplier); a travel longer than `retract_min_travel` retracts, lifts the
nozzle, moves, lowers and primes again. The part-cooling fan is off (M107)
for the first `fan_off_layers` layers and on at `fan_speed` (M106) from the
next. The first layer starts with its skirt and brim. The ``;TYPE:`` words
come from `slicelab.printing.roles.STYLES`; the time is the
sum of every written move's time (`slicelab.gcode.estimate.move_times`:
trapezoidal speed profiles at the settings' `acceleration`, junctions at
`jerk`).

See Also
--------
slicelab.printing.planner.plan : the print plan written here.
slicelab.gcode.layer_svgs.write_svgs : its layers as drawings.
slicelab.viz.layers.preview_png : a PNG of some layers.
"""
from __future__ import annotations

import math

import numpy as np

from .estimate import format_duration, move_times
from ..printing.config.settings import settings_dict
from ..printing.config.printers import MARLIN_END, MARLIN_START, render_gcode
from ..printing.roles import STYLES
from ..export.files import atomic_open
from .layer_inputs import SMALL_PERIMETER, CompiledLayer, WriterSettings, kind_speeds, lift_at
from .text_kernels import fixed

__all__ = ["write_gcode", "gcode_lines", "header_value", "layer_fan", "layer_texts"]


#: One extrusion move as written.
_G1 = "G1 X%.3f Y%.3f E%.5f\n"


class _Moves:
    """The moves of a stretch of G-code as given (rounded like the text once, in `seconds`), for the
    time estimate: rows of x, y, z, filament fed and feed rate (mm/s)."""

    def __init__(self, pos):
        self.start = np.asarray(pos, np.float64)
        self.last = tuple(float(v) for v in self.start[:3])  # the last move's end, x, y, z
        self.blocks, self.rows = [], []

    def point(self, x: float, y: float, z: float, e: float, feed: float) -> None:
        """One move to (x, y, z)."""
        self.rows.append((x, y, z, e, feed))
        self.last = (x, y, z)

    def block(self, rows: np.ndarray) -> None:
        """Moves given as rows of (x, y, z, e, feed)."""
        if self.rows:
            self.blocks.append(np.array(self.rows, np.float64))
            self.rows = []
        self.blocks.append(rows)
        self.last = (float(rows[-1, 0]), float(rows[-1, 1]), float(rows[-1, 2]))

    def seconds(self, s) -> float:
        """Time of the moves added since the last call."""
        if self.rows:
            self.blocks.append(np.array(self.rows, np.float64))
            self.rows = []
        if not self.blocks:
            return 0.0
        m = np.concatenate(self.blocks)
        ends = np.round(m[:, :3], 3)
        starts = np.vstack([self.start, ends[:-1]])
        t = move_times(starts, ends, np.round(m[:, 3], 5), m[:, 4], acceleration=s.acceleration, jerk=s.jerk)
        self.start = ends[-1]
        self.blocks = []
        return float(t.sum())


def header_value(value) -> str:
    """A setting's value as one comment line of the header: a multi-line value (start and end
    G-code) with its line breaks written ``\\n``, so that none of its lines is live.

    Examples
    --------
    >>> header_value("M104 S{nozzle_temperature:.0f}\\nG28\\n")
    'M104 S{nozzle_temperature:.0f}\\\\nG28\\\\n'
    >>> header_value((250.0, 210.0))
    '(250.0, 210.0)'
    """
    text = str(value)
    return text.replace("\\", "\\\\").replace("\r", "\\r").replace("\n", "\\n")


def gcode_lines(plan, totals: dict | None = None, *, workers: int | None = 1, compiled: bool = True, notes=()):
    """Yield the G-code text in blocks (header, each layer, end, the totals).

    Parameters
    ----------
    plan : PrintPlan
    totals : dict, optional
        Filled at the end with ``seconds`` (the estimated print time) and
        ``filament`` (mm), as the file's last lines say, and ``layer_seconds``
        (each layer's time, slowed to `min_layer_time` where needed).
    workers : int or None, default 1
        Processes formatting the layers; None: all cores when the layers left to format (those
        not formatted ahead, `layer_texts`) are worth a pool (`_pooled`). The text is the same
        for any number.
    compiled : bool, default True
        Layers written by the compiled pass (`slicelab.gcode.text_kernels.layer_moves`);
        False writes every layer with Python, the same bytes, a few times slower.
    notes : sequence of str
        Comment lines of the header, after its first (each line of each note a comment).

    See Also
    --------
    write_gcode : the blocks written to a file.
    """
    s = plan.settings
    off = plan.offset
    yield "; generated by slicelab\n" + "".join(f"; {header_value(n)}\n" for n in notes)
    yield f"; slicelab offset = {off[0]:.6f},{off[1]:.6f},{off[2]:.6f}\n"
    for k, v in settings_dict(s).items():
        yield f"; {k} = {header_value(v)}\n"
    yield (f"; layers = {len(plan.layers)}\n; estimated filament used [mm] = {plan.filament_length:.2f}\n"
           f"; flavor = {s.gcode_flavor}\n"
           + render_gcode(s.start_gcode if s.start_gcode is not None else MARLIN_START, s)
           + "G92 E0\nM107\n")
    starts = _layer_starts(plan)
    seconds = filament = 0.0
    z = 0.0
    fan_now = 0  # M107 above
    layer_seconds = []
    for k, (text, t, used) in enumerate(_layer_blocks(plan, starts, workers, compiled)):  # over layers, in order
        lp, h = plan.layers[k], plan.heights[k]
        z = lp.z + 0.0
        fan = layer_fan(k, t, s)
        head = (f";LAYER_CHANGE\n;Z:{z:.3f}\n;HEIGHT:{h:.3f}\n;LAYER:{k}\n"
                + ("" if fan == fan_now else _fan_command(fan)))
        fan_now = fan
        seconds, filament = seconds + t, filament + used
        layer_seconds.append(t)
        yield head + text.replace("\x00FAN\x00", _fan_command(fan))
    moves = _Moves(starts[-1][1])
    top = max(z, min(z + 10.0, s.max_height))
    x, y, z_end = moves.last
    moves.point(x, y, z_end, -s.retraction_length, round(60 * s.retraction_speed) / 60)
    moves.point(x, y, top, 0.0, 10.0)
    seconds += moves.seconds(s)
    if totals is not None:
        totals.update(seconds=seconds, filament=filament, layer_seconds=layer_seconds)
    yield (f"; end\nG1 E{-s.retraction_length:.5f} F{60 * s.retraction_speed:.0f}\n"
           f"G1 Z{top:.3f} F600\n" + render_gcode(s.end_gcode if s.end_gcode is not None else MARLIN_END, s))
    yield (f"\n; filament used [mm] = {filament:.2f}\n"
           f"; filament used [cm3] = {filament * s.filament_area / 1000:.2f}\n"
           f"; estimated printing time (normal mode) = {format_duration(seconds)}\n")


def _layer_starts(plan) -> list:
    """Where the nozzle is as each layer starts, and after the last: (xy of the last extrusion's end
    in bed coordinates, None before any; the position as written, xyz rounded to the micrometre).

    A layer moves up to its height, then ends on the last point of its last path; G28 leaves
    the nozzle at the origin.
    """
    off = plan.offset
    start = (None, np.zeros(3))
    out = []
    for lp in plan.layers:  # over layers: a few operations each
        out.append(start)
        start = _after(lp, off, start)
    out.append(start)
    return out


def _after(lp, off, start: tuple) -> tuple:
    """Where the nozzle is after a layer that started at `start` (see `_layer_starts`)."""
    z = lp.z + 0.0
    if lp.paths:
        pos = lp.paths[-1][-1] + off[:2]
        return pos, np.round([pos[0], pos[1], z], 3)
    at = start[1]
    return start[0], np.round([at[0], at[1], z], 3)


def layer_texts(first: int, layers: list, heights, settings, offset) -> list:
    """The G-code of consecutive layers, formatted ahead of `write_gcode` (by the planner's workers).

    A layer's text depends on where the nozzle starts it, the end of the layer
    before it: each layer after the first whose start these layers tell is
    formatted (compiled writer), with that start. `write_gcode` takes a block
    whose start is the one it finds, and formats the others itself.

    Parameters
    ----------
    first : int
        Index of ``layers[0]`` in its plan.
    layers : list of LayerPaths
    heights : sequence of float
        Their thicknesses.
    settings : PrintSettings
    offset : (3,) ndarray
        The plan's translation to the bed (`PrintPlan.offset`).

    Returns
    -------
    list
        Per layer, None or ``(start, (text, seconds, filament))``.

    See Also
    --------
    slicelab.printing.planner.plan : calls it on each run of layers it plans (``layer_text``).

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> p = slicelab.plan(box((0, 0, 0), (5, 5, 0.6)), slicelab.PrintSettings(pixel_size=0.1), workers=1)
    >>> got = layer_texts(0, p.layers, p.heights, p.settings, p.offset)
    >>> got[0] is None, got[1][1][0].splitlines()[0]   # the first layer's start lies before them
    (True, 'G1 Z0.400 F9000')
    """
    fixed_inputs = WriterSettings.of(settings)
    out, start = [], None
    for k, lp, h in zip(range(first, first + len(layers)), layers, heights):  # over layers
        if start is None:  # the layer before lies elsewhere: where it ends is not known here
            out.append(None)
        else:
            out.append((start, _layer_block(k, lp, float(h), settings, offset, *start, fixed_inputs)))
        if lp.paths or start is not None:
            start = _after(lp, offset, start or (None, np.zeros(3)))
    return out


def _same_start(a: tuple, b: tuple) -> bool:
    """Whether two nozzle starts (`_layer_starts`) are the same."""
    return (a[0] is None) == (b[0] is None) and (a[0] is None or np.array_equal(a[0], b[0])) \
        and np.array_equal(a[1], b[1])


#: Layers per task when several processes format the G-code.
_GCODE_RUN = 25


def _pooled(plan, layers: list | None = None) -> bool:
    """Whether formatting the plan's layers (all, or those listed) is worth a pool: its time in
    one process, about 0.1 ms a layer and 0.35 us a path point with the compiled writer, above
    0.15 s, against some 20 ms to start a pool plus the layers' pickling and the gathering of
    their text (in one process and with two: the pot's 600 layers and 336,000 points 0.17 and
    0.15 s, the block's 300 layers and 250,000 points 0.10 and 0.11 s, the teapot's 293 layers
    0.07 and 0.08 s)."""
    ks = range(len(plan.layers)) if layers is None else layers
    points = sum(len(q) for k in ks for q in plan.layers[k].paths)  # over paths
    return len(ks) > 2 * _GCODE_RUN and 1e-4 * len(ks) + 3.5e-7 * points > 0.15


def _layer_blocks(plan, starts: list, workers: int, compiled: bool = True):
    """Each layer's (text, seconds, filament), in order: formatted ahead (`layer_texts`, when its
    start is the one found here), here, or by a pool of processes."""
    n = len(plan.layers)
    s, off = plan.settings, plan.offset
    ahead = plan.texts if compiled else {}
    ready = {k: got[1] for k, got in ahead.items() if k < n and _same_start(got[0], starts[k])}
    left = [k for k in range(n) if k not in ready]
    runs = [left[a:a + _GCODE_RUN] for a in range(0, len(left), _GCODE_RUN)]

    def job(run):
        return (run, [plan.layers[k] for k in run], [float(plan.heights[k]) for k in run], s, off,
                [starts[k] for k in run], compiled)

    def merged(formatted):  # the ready blocks and the formatted ones, in order
        k = 0
        for run, blocks in formatted:
            for j, block in zip(run, blocks):
                while k < j:
                    yield ready[k]
                    k += 1
                yield block
                k = j + 1
        while k < n:
            yield ready[k]
            k += 1

    if workers is None:
        import os
        workers = (os.cpu_count() or 1) if _pooled(plan, left) else 1
    if workers <= 1 or len(runs) < 2:
        yield from merged((run, _format_run(*job(run))) for run in runs)
        return
    from ..printing._pool import forked_pool
    with forked_pool(min(workers, len(runs))) as pool:
        # Submitted all at once; taken back in order, so the file is written while later runs format.
        futures = [(run, pool.submit(_format_run, *job(run))) for run in runs]
        yield from merged((run, fut.result()) for run, fut in futures)


def _format_run(ks: list, layers: list, heights: list, s, off, starts: list, compiled: bool = True) -> list:
    """The (text, seconds, filament) of some layers, each from its start (`_layer_starts`): its
    inputs come as arguments, so a pool's worker needs nothing from its parent."""
    fixed_inputs = WriterSettings.of(s) if compiled else None
    return [_layer_block(k, lp, h, s, off, pos, at, fixed_inputs)
            for k, lp, h, (pos, at) in zip(ks, layers, heights, starts)]


def _layer_block(k: int, lp, h: float, s, off, pos, at, fixed_inputs: WriterSettings | None = None) \
        -> tuple[str, float, float]:
    """One layer's G-code (without its header; its fan as a marker), its time and filament.

    Written at full speed first; a layer quicker than `min_layer_time` is written again slower,
    so that it has time to cool before the next one is laid on it. The compiled writer
    (`slicelab.gcode.text_kernels.layer_moves`) writes it when it can and `fixed_inputs` are
    given, else Python: the same bytes.
    """
    fast = None if fixed_inputs is None else CompiledLayer.of(k, lp, h, fixed_inputs, off, pos, at)
    if fast is not None:
        out = _slowed(fast.run, k, s)
        if out is not None:
            return out
    return _slowed(lambda factor, text: _python_layer(k, lp, h, s, off, pos, at, factor, text), k, s)


def _python_layer(k: int, lp, h: float, s, off, pos, at, factor: float, text: bool):
    """(text, filament, seconds) of a layer written by Python at extrusion speeds times `factor`."""
    moves = _Moves(at)
    written, used = _layer_gcode(k, lp, h, s, off, moves, pos, factor, text=text)
    return written, used, moves.seconds(s)


def _slowed(run, k: int, s):
    """A layer's (text, seconds, filament) from ``run(factor, text) -> (text, filament, seconds)``,
    at full speed or slowed to take `min_layer_time`; None if `run` gives no text."""
    text, used, t = run(1.0, True)
    factor = 1.0
    for _ in range(4):  # travel and acceleration do not slow in step: a few rounds, moves only
        if k == 0 or t >= 0.99 * s.min_layer_time or factor * s.min_layer_time <= 0:
            break
        factor *= t / s.min_layer_time
        _, used, t = run(factor, False)
    if factor < 1:  # the text once, at the speed found
        text, used, t = run(factor, True)
    return None if text is None else (text, t, used)


def _fan_command(percent: int) -> str:
    """The fan at a percentage, as PrusaSlicer writes it."""
    return f"M106 S{int(255 * percent / 100)}\n" if percent > 0 else "M107\n"


def layer_fan(k: int, seconds: float, s) -> int:
    """The part-cooling fan (percent) for layer k, which prints in `seconds`.

    Off for the first `fan_off_layers` layers; then `fan_speed`, raised towards full as the
    layer's time falls from `fan_below_layer_time` to `min_layer_time` (a small layer has
    less time to cool).

    Examples
    --------
    >>> from slicelab.printing import PrintSettings
    >>> s = PrintSettings(fan_speed=40, fan_below_layer_time=60, min_layer_time=5)
    >>> [layer_fan(0, 100, s), layer_fan(3, 100, s), layer_fan(3, 32.5, s), layer_fan(3, 2, s)]
    [0, 40, 70, 100]
    """
    if k < s.fan_off_layers or s.fan_speed <= 0:
        return 0
    lo, hi = s.min_layer_time, s.fan_below_layer_time
    share = 0.0 if hi <= lo else float(np.clip((hi - seconds) / (hi - lo), 0.0, 1.0))
    return int(round(s.fan_speed + (100 - s.fan_speed) * share))


def _layer_gcode(k: int, lp, h: float, s, off, moves: "_Moves", pos, factor: float, text: bool = True):
    """One layer's moves as G-code text (without its header) and the filament it uses, from the
    nozzle at `pos` (xy, None before any extrusion); extrusion speeds times `factor` (not below `min_print_speed`). With
    ``text=False`` only the moves are added (for timing): the extrusions are not formatted.

    The layer's fan command is left as a marker where bridges change it back. The paths'
    points, segment lengths and extrusions are computed for the whole layer at once; the loop
    over paths only writes their headers and travels.
    """
    k_e = s.extrusion_multiplier / s.filament_area
    speeds = kind_speeds(s)
    travel_feed, retract_feed = round(60 * s.travel_speed) / 60, round(60 * s.retraction_speed) / 60
    z = lp.z + 0.0
    retract, lift, min_travel = s.retraction_length, lift_at(z, s.z_lift, s.max_height), s.retract_min_travel
    first_speed, small_speed, min_speed = s.first_layer_speed, s.small_perimeter_speed, s.min_print_speed
    travel_f, retract_f = f"{60 * s.travel_speed:.0f}", f"{60 * s.retraction_speed:.0f}"
    out = [f"G1 Z{z:.3f} F{travel_f}\n"]
    x, y, _ = moves.last
    moves.point(x, y, z, 0.0, travel_feed)
    pieces = list(lp.pieces())
    if not pieces:
        return "".join(out), 0.0
    kinds = [q[0] for q in pieces]
    counts = np.array([len(q[1]) for q in pieces])
    ends = np.cumsum(counts)
    begins = ends - counts
    xy = np.concatenate([q[1] for q in pieces]) + off[:2]
    n = len(xy)
    width = np.concatenate([np.full(m, q[2]) if np.isscalar(q[2]) else np.asarray(q[2], np.float64)
                            for m, q in zip(counts, pieces)])
    # Segment j joins points j and j + 1; those that join two paths are never used.
    d = np.diff(xy, axis=0)
    seg = np.hypot(d[:, 0], d[:, 1])
    wm = 0.5 * (width[:-1] + width[1:])
    flow = np.repeat([k_e * s.bridge_flow_ratio if kind == "bridge" else k_e for kind in kinds], counts)[:-1]
    e = wm * h * seg * flow
    # Each path's mean width (its own segments only: those joining two paths count nothing).
    inner = wm.copy()
    inner[ends[:-1] - 1] = 0.0
    mean_width = (np.add.reduceat(inner, begins) / np.maximum(counts - 1, 1)).tolist() if n > 1 else [0.0]
    e_written = np.round(e, 5)
    closed = np.all(xy[begins] == xy[ends - 1], axis=1)
    # The travel to each path's first point, from the last path's end (or the nozzle).
    before = np.vstack([[np.nan, np.nan] if pos is None else pos, xy[ends[:-1] - 1]])
    gap = xy[begins] - before
    travel = np.hypot(gap[:, 0], gap[:, 1])
    if pos is None:
        travel[0] = math.inf
    rows = np.empty((n, 5))  # the moves to each point: x, y, z, filament, feed
    rows[:, :2] = xy
    rows[:, 2] = z
    rows[1:, 3] = e
    values = moves_text = line_at = None
    if text:
        shown = np.empty((n, 3))
        shown[:, :2] = xy
        shown[1:, 2] = e
        # Every extrusion move of the layer formatted in one compiled pass (Python's digits);
        # a value it cannot format (not finite, or huge) leaves the layer to Python's %.
        formatted = fixed(shown)
        if formatted is None:
            values = shown.ravel().tolist()
        else:
            moves_text, line_at = formatted[0], formatted[1].tolist()
    starts, stops = begins.tolist(), ends.tolist()
    filament = 0.0
    current_type = None
    for i, kind in enumerate(kinds):  # over paths
        a, b = starts[i], stops[i]
        if kind != current_type:
            if current_type == "bridge":
                out.append("\x00FAN\x00")  # the layer's own fan again after a bridge
            out.append(f";TYPE:{STYLES[kind].gcode_type}\n")
            if kind == "bridge":
                out.append("M106 S255\n")  # bridge threads set in the air: full cooling
            current_type = kind
        if travel[i] > 1e-9:
            x0, y0 = float(xy[a, 0]), float(xy[a, 1])
            if travel[i] > min_travel and retract > 0:
                x, y, zz = moves.last
                out.append(f"G1 E{-retract:.5f} F{retract_f}\n")
                moves.point(x, y, zz, -retract, retract_feed)
                if lift > 0:
                    out.append(f"G1 Z{z + lift:.3f} F{travel_f}\n")
                    moves.point(x, y, z + lift, 0.0, travel_feed)
                out.append(f"G0 X{x0:.3f} Y{y0:.3f} F{travel_f}\n")
                moves.point(x0, y0, z + lift, 0.0, travel_feed)
                if lift > 0:
                    out.append(f"G1 Z{z:.3f}\n")
                    moves.point(x0, y0, z, 0.0, travel_feed)
                out.append(f"G1 E{retract:.5f} F{retract_f}\n")
                moves.point(x0, y0, z, retract, retract_feed)
            else:
                out.append(f"G0 X{x0:.3f} Y{y0:.3f} F{travel_f}\n")
                moves.point(x0, y0, z, 0.0, travel_feed)
        speed = first_speed if k == 0 else speeds[kind]
        if kind in ("external", "hole", "internal") and b - a > 3 and closed[i] \
                and seg[a:b - 1].sum() < SMALL_PERIMETER:
            speed = min(speed, small_speed)
        if factor < 1:
            speed = max(min(speed, min_speed), speed * factor)
        out.append(f";WIDTH:{mean_width[i]:.3f}\nG1 F{60 * speed:.0f}\n")
        if text:
            if b - a < 2:
                out.append("\n")
            elif moves_text is not None:  # the moves to points a + 1 .. b - 1
                out.append(moves_text[line_at[a + 1]:line_at[b]])
            else:
                out.append(_G1 * (b - a - 1) % tuple(values[3 * a + 3:3 * b]))
        block = rows[a + 1:b]
        block[:, 4] = round(60 * speed) / 60
        moves.block(block)
        filament += float(e_written[a:b - 1].sum())
    if current_type == "bridge":
        out.append("\x00FAN\x00")
    return "".join(out), filament


def write_gcode(plan, path, *, workers: int | None = None, compiled: bool = True, notes=()) -> dict:
    """Write the plan's G-code to `path` (temporary name, renamed when whole).

    Parameters
    ----------
    plan : PrintPlan
    path : str or Path
    workers : int, optional
        Processes formatting the layers (default: all cores when the layers
        left to format, those the planner's workers did not format ahead
        (`layer_texts`), take longer than starting a pool and gathering its
        text, else 1: see `_pooled`); the file is the same for any number.
    compiled : bool, default True
        False writes every layer with Python (see `gcode_lines`): the same file.
    notes : sequence of str
        Lines said in the header, as comments (what a repair changed, say).

    Returns
    -------
    dict
        ``seconds``: the estimated print time; ``filament``: filament used (mm).

    See Also
    --------
    gcode_lines : the text written.
    slicelab.gcode.layer_svgs.write_svgs : the layers as drawings.

    Examples
    --------
    >>> import slicelab, tempfile, os
    >>> from slicelab.samples import box
    >>> p = slicelab.plan(box((0, 0, 0), (5, 5, 0.6)), slicelab.PrintSettings(pixel_size=0.1), workers=1)
    >>> out = os.path.join(tempfile.mkdtemp(), "box.gcode")
    >>> totals = write_gcode(p, out)
    >>> text = open(out).read(); text.count(";LAYER_CHANGE"), ";TYPE:External perimeter" in text
    (3, True)
    >>> text.splitlines()[-1], round(totals["seconds"])
    ('; estimated printing time (normal mode) = 20s', 20)
    """
    totals: dict = {}
    with atomic_open(path, "w", encoding="utf-8") as fh:
        for block in gcode_lines(plan, totals, workers=None if workers is None else max(1, int(workers)),
                                 compiled=compiled, notes=notes):
            fh.write(block)
    return totals
