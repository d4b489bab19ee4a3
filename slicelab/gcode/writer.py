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
come from `slicelab.printing.roles.STYLES`. The header states the machine's
motion limits in the flavour's commands (`machine_lines`: M201, M203, M204,
M205; RepRapFirmware's M566; Klipper's M204 S alone), and the time is the sum
of every written move's time under those same limits
(`slicelab.gcode.estimate.move_times`: Marlin's planner, trapezoids, classic
jerk), so that the printer, PrusaSlicer's viewer and the estimate share one
machine.

See Also
--------
slicelab.printing.planner.plan : the print plan written here.
slicelab.gcode.layer_svgs.write_svgs : its layers as drawings.
slicelab.viz.layers.preview_png : a PNG of some layers.
"""
from __future__ import annotations


import numpy as np

from .estimate import format_duration, machine_limits, move_times
from ..printing.config.settings import settings_dict
from ..printing.config.printers import MARLIN_END, MARLIN_START
from ..printing.config.settings import render_gcode
from ..files.atomic import atomic_open
from .layer_inputs import CompiledLayer, WriterSettings

__all__ = ["write_gcode", "gcode_lines", "header_value", "layer_fan", "layer_texts", "layer_starts", "slowed",
           "machine_lines", "next_move"]


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


def _number(v: float) -> str:
    """A limit with two decimals, trailing zeros left out (1500, 0.2, 2.5)."""
    text = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def machine_lines(s) -> str:
    """The machine's motion limits as the flavour's G-code, for the top of the file: '' unless
    ``machine_limits_usage`` is ``"emit_to_gcode"``.

    Marlin: M201 (the axes' accelerations, mm/s^2), M203 (their feed rates, mm/s), M204 P R T
    (printing, retracting and travel accelerations), M205 X Y Z E (classic jerk, mm/s).
    RepRapFirmware: M201, M203 in mm/min, M204 P T, M566 (jerk, mm/min). Klipper: M204 S (its
    one acceleration) alone, for it rejects the others. The numbers are the ones the estimate
    takes (`slicelab.gcode.estimate.machine_limits`), with two decimals.

    Examples
    --------
    >>> from slicelab.printing import PrintSettings
    >>> print(machine_lines(PrintSettings()), end="")
    M201 X9000 Y9000 Z500 E10000 ; axis accelerations, mm/s^2
    M203 X500 Y500 Z12 E120 ; axis feed rates, mm/s
    M204 P1500 R1500 T1500 ; printing, retracting and travel accelerations, mm/s^2
    M205 X10 Y10 Z0.2 E2.5 ; jerk, mm/s
    >>> machine_lines(PrintSettings(gcode_flavor="klipper", acceleration=3000))
    'M204 S3000 ; acceleration, mm/s^2\\n'
    """
    if s.machine_limits_usage != "emit_to_gcode":
        return ""
    m = machine_limits(s)
    if s.gcode_flavor == "klipper":
        return f"M204 S{_number(m.extruding)} ; acceleration, mm/s^2\n"
    rrf = s.gcode_flavor == "reprapfirmware"
    unit, per = ("mm/min", 60.0) if rrf else ("mm/s", 1.0)

    def axes(values, scale=1.0):
        return " ".join(f"{a}{_number(v * scale)}" for a, v in zip("XYZE", values))

    lines = [f"M201 {axes(m.max_acceleration)} ; axis accelerations, mm/s^2",
             f"M203 {axes(m.max_feedrate, per)} ; axis feed rates, {unit}",
             f"M204 P{_number(m.extruding)} T{_number(m.travel)} ; printing and travel accelerations, mm/s^2" if rrf
             else f"M204 P{_number(m.extruding)} R{_number(m.retracting)} T{_number(m.travel)} ; printing, "
                  f"retracting and travel accelerations, mm/s^2",
             f"{'M566' if rrf else 'M205'} {axes(m.max_jerk, per)} ; jerk, {unit}"]
    return "\n".join(lines) + "\n"


def next_move(plan, k: int):
    """The move after layer k's last, (dx, dy, dz, de, feed), which the layer's time ends into: the
    next layer's rise (taken as this layer's height up, at the travel feed: the junction does
    not depend on its length), or after the last layer the end's retraction (its lift if it
    retracts nothing; None if neither moves).

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> p = slicelab.plan(box((0, 0, 0), (5, 5, 0.6)), slicelab.PrintSettings(pixel_size=0.1), workers=1)
    >>> next_move(p, 0), next_move(p, 2)
    ((0.0, 0.0, 0.2, 0.0, 150.0), (0.0, 0.0, 0.0, -0.8, 35.0))
    """
    s = plan.settings
    if k + 1 < len(plan.layers):
        return (0.0, 0.0, float(plan.heights[k]), 0.0, round(60 * s.travel_speed) / 60)
    if round(s.retraction_length, 5) > 0:
        return (0.0, 0.0, 0.0, -round(s.retraction_length, 5), round(60 * s.retraction_speed) / 60)
    z = plan.layers[k].z + 0.0
    top = max(z, min(z + 10.0, s.max_height))
    return (0.0, 0.0, round(top, 3) - round(z, 3), 0.0, 10.0) if round(top, 3) > round(z, 3) else None


def gcode_lines(plan, totals: dict | None = None, *, workers: int | None = 1, notes=()):
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
           f"; flavor = {s.gcode_flavor}\n" + machine_lines(s)
           + render_gcode(s.start_gcode if s.start_gcode is not None else MARLIN_START, s)
           + "G92 E0\nM107\n")
    starts = layer_starts(plan)
    seconds = filament = 0.0
    z = 0.0
    fan_now = 0  # M107 above
    layer_seconds = []
    for k, (text, t, used) in enumerate(_layer_blocks(plan, starts, workers)):  # over layers, in order
        lp, h = plan.layers[k], plan.heights[k]
        z = lp.z + 0.0
        fan = layer_fan(k, t, s)
        head = (f";LAYER_CHANGE\n;Z:{z:.3f}\n;HEIGHT:{h:.3f}\n;LAYER:{k}\n"
                + ("" if fan == fan_now else _fan_command(fan)))
        fan_now = fan
        seconds, filament = seconds + t, filament + used
        layer_seconds.append(t)
        yield head + text.replace("\x00FAN\x00", _fan_command(fan))
    top = max(z, min(z + 10.0, s.max_height))
    seconds += _end_seconds(starts[-1][1], top, s)
    if totals is not None:
        totals.update(seconds=seconds, filament=filament, layer_seconds=layer_seconds)
    yield (f"; end\nG1 E{-s.retraction_length:.5f} F{60 * s.retraction_speed:.0f}\n"
           f"G1 Z{top:.3f} F600\n" + render_gcode(s.end_gcode if s.end_gcode is not None else MARLIN_END, s))
    yield (f"\n; filament used [mm] = {filament:.2f}\n"
           f"; filament used [cm3] = {filament * s.filament_area / 1000:.2f}\n"
           f"; estimated printing time (normal mode) = {format_duration(seconds)}\n")


def _end_seconds(at, top: float, s) -> float:
    """The time of the end's two moves from `at` (xyz as written): the retraction, the lift to `top`."""
    at = np.asarray(at, np.float64)
    ends = np.round(np.array([at, [at[0], at[1], top]]), 3)
    return float(move_times(np.vstack([at, ends[:-1]]), ends, np.array([-round(s.retraction_length, 5), 0.0]),
                            np.array([round(60 * s.retraction_speed) / 60, 10.0]), machine_limits(s)).sum())


def layer_starts(plan) -> list:
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
    """Where the nozzle is after a layer that started at `start` (see `layer_starts`)."""
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
    """Whether two nozzle starts (`layer_starts`) are the same."""
    return (a[0] is None) == (b[0] is None) and (a[0] is None or np.array_equal(a[0], b[0])) \
        and np.array_equal(a[1], b[1])


#: Layers per task when several processes format the G-code.
_GCODE_RUN = 25


def _pooled(plan, layers: list | None = None) -> bool:
    """Whether formatting the plan's layers (all, or those listed) is worth a pool: when its
    estimated time in one process (a cost per layer plus a cost per path point of the compiled
    writer) passes 0.15 s, which outweighs starting a pool, pickling the layers and gathering
    their text. Plans of at most twice `_GCODE_RUN` layers are formatted in one process."""
    ks = range(len(plan.layers)) if layers is None else layers
    points = sum(len(q) for k in ks for q in plan.layers[k].paths)  # over paths
    return len(ks) > 2 * _GCODE_RUN and 1e-4 * len(ks) + 3.5e-7 * points > 0.15


def _layer_blocks(plan, starts: list, workers: int):
    """Each layer's (text, seconds, filament), in order: formatted ahead (`layer_texts`, when its
    start is the one found here), here, or by a pool of processes."""
    n = len(plan.layers)
    s, off = plan.settings, plan.offset
    ahead = plan.texts
    # (The last layer's time ends into the end's retraction, which those formatted ahead do not know.)
    ready = {k: got[1] for k, got in ahead.items() if k < n - 1 and _same_start(got[0], starts[k])}
    left = [k for k in range(n) if k not in ready]
    runs = [left[a:a + _GCODE_RUN] for a in range(0, len(left), _GCODE_RUN)]

    def job(run):
        return (run, [plan.layers[k] for k in run], [float(plan.heights[k]) for k in run], s, off,
                [starts[k] for k in run], [next_move(plan, k) for k in run])

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
    from .._pools import process_pool
    with process_pool(min(workers, len(runs))) as pool:
        # Submitted all at once; taken back in order, so the file is written while later runs format.
        futures = [(run, pool.submit(_format_run, *job(run))) for run in runs]
        yield from merged((run, fut.result()) for run, fut in futures)


def _format_run(ks: list, layers: list, heights: list, s, off, starts: list, thens: list) -> list:
    """The (text, seconds, filament) of some layers, each from its start (`layer_starts`) and into
    the move after it (`next_move`): its inputs come as arguments, so a pool's worker needs
    nothing from its parent."""
    fixed_inputs = WriterSettings.of(s)
    return [_layer_block(k, lp, h, s, off, pos, at, fixed_inputs, then=then)
            for k, lp, h, (pos, at), then in zip(ks, layers, heights, starts, thens)]


def _layer_block(k: int, lp, h: float, s, off, pos, at, fixed_inputs: WriterSettings, *,
                 then=None) -> tuple[str, float, float]:
    """One layer's G-code (without its header; its fan as a marker), its time and filament, written
    by the compiled pass (`slicelab.gcode.text_kernels.layer_moves`); its time ends into `then`
    (`next_move`; None: the next layer's rise).

    Written at full speed first; a layer quicker than `min_layer_time` is written again slower,
    so that it has time to cool before the next one is laid on it.
    """
    out = slowed(CompiledLayer.of(k, lp, h, fixed_inputs, off, pos, at, then).run, k, s)
    if out is None:  # (the settings' ranges and the bed keep every number within what it writes)
        raise ValueError(f"layer {k}: a coordinate or an extrusion G-code cannot hold (beyond 1e9)")
    return out


def slowed(run, k: int, s):
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


def write_gcode(plan, path, *, workers: int | None = None, notes=()) -> dict:
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
                                 notes=notes):
            fh.write(block)
    return totals
