"""The G-code of a layer written by Python, line by line: the oracle the compiled writer is held to.

`slicelab.gcode.writer` writes every layer with one compiled pass
(`slicelab.gcode.text_kernels.layer_moves`). This module writes the same
layer the plain way, with Python's own ``%`` formatting and
`slicelab.gcode.estimate.move_times`, so a test can ask for the same bytes,
the same filament and the same time.
"""
from __future__ import annotations

import math

import numpy as np

from slicelab.gcode.estimate import machine_limits, move_times
from slicelab.gcode.layer_inputs import SMALL_PERIMETER, kind_speeds, lift_at
from slicelab.gcode.writer import slowed
from slicelab.printing.roles import STYLES

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

    def seconds(self, s, then=None) -> float:
        """Time of the moves added since the last call, ending into the move `then` (dx, dy, dz, de, feed)."""
        if self.rows:
            self.blocks.append(np.array(self.rows, np.float64))
            self.rows = []
        if not self.blocks:
            return 0.0
        m = np.concatenate(self.blocks)
        ends = np.round(m[:, :3], 3)
        starts = np.vstack([self.start, ends[:-1]])
        t = move_times(starts, ends, np.round(m[:, 3], 5), m[:, 4], machine_limits(s), then=then)
        self.start = ends[-1]
        self.blocks = []
        return float(t.sum())


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
    # A bridge is laid as a round strand of the nozzle's bore (times the bridge flow ratio).
    bridge = np.repeat([kind == "bridge" for kind in kinds], counts)[:-1]
    e = np.where(bridge, np.pi * s.nozzle_diameter ** 2 / 4 * s.bridge_flow_ratio, wm * h) * seg * k_e
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
    values = None
    if text:
        shown = np.empty((n, 3))
        shown[:, :2] = xy
        shown[1:, 2] = e
        values = shown.ravel().tolist()
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
            else:
                out.append(_G1 * (b - a - 1) % tuple(values[3 * a + 3:3 * b]))
        block = rows[a + 1:b]
        block[:, 4] = round(60 * speed) / 60
        moves.block(block)
        filament += float(e_written[a:b - 1].sum())
    if current_type == "bridge":
        out.append("\x00FAN\x00")
    return "".join(out), filament


def _python_layer(k: int, lp, h: float, s, off, pos, at, factor: float, text: bool, then):
    """(text, filament, seconds) of a layer written by Python at extrusion speeds times `factor`."""
    moves = _Moves(at)
    written, used = _layer_gcode(k, lp, h, s, off, moves, pos, factor, text=text)
    return written, used, moves.seconds(s, then)


def layer_block(k: int, lp, h: float, s, off, pos, at, then=None):
    """One layer's (text, seconds, filament), written by Python, slowed as the writer slows it; its
    time ends into `then` (`slicelab.gcode.writer.next_move`; None: the next layer's rise, `h` up)."""
    if then is None:
        then = (0.0, 0.0, h, 0.0, round(60 * s.travel_speed) / 60)
    return slowed(lambda factor, text: _python_layer(k, lp, h, s, off, pos, at, factor, text, then), k, s)
