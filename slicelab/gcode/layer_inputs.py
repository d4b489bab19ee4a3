"""The inputs of the compiled G-code pass: the settings once for a plan, the paths once for a layer.

`slicelab.gcode.text_kernels.layer_moves` writes a layer's G-code from plain arrays:
its paths' points, point counts, kinds (indices into the tables here: each kind's
speed, whether it is a perimeter, its ``;TYPE:`` line) and widths, and a row of the
settings' numbers. `WriterSettings` holds what does not change from layer to layer;
`CompiledLayer` a layer's arrays, run at full speed and again slower when the layer
must take `min_layer_time`.

See Also
--------
slicelab.gcode.writer.write_gcode : the writer that uses them (and writes with Python what the pass cannot).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..printing.roles import STYLES
from .estimate import machine_limits
from .text_kernels import layer_moves

__all__ = ["SMALL_PERIMETER", "KIND_INDEX", "lift_at", "WORD_BYTES", "WORD_AT", "PERIMETER_KINDS", "BRIDGE", "kind_speeds",
           "WriterSettings", "CompiledLayer"]

#: Perimeter loops shorter than this (mm), a circle of radius 6.5 mm, are small (PrusaSlicer's rule).
SMALL_PERIMETER = 2 * math.pi * 6.5

#: Every kind's index in the compiled pass's tables, and its ``;TYPE:`` lines as bytes.
KIND_INDEX = {kind: i for i, kind in enumerate(STYLES)}
_WORDS = [f";TYPE:{STYLES[kind].gcode_type}\n".encode("ascii") for kind in STYLES]
WORD_BYTES = np.frombuffer(b"".join(_WORDS), np.uint8).copy()
WORD_AT = np.concatenate([[0], np.cumsum([len(w) for w in _WORDS])]).astype(np.int64)
PERIMETER_KINDS = np.array([kind in ("external", "hole", "internal") for kind in STYLES])
BRIDGE = KIND_INDEX["bridge"]


def kind_speeds(s) -> dict:
    """Each kind's print speed (mm/s) under settings `s`.

    Examples
    --------
    >>> from slicelab.printing import PrintSettings
    >>> s = PrintSettings()
    >>> kind_speeds(s)["hole"] == s.external_perimeter_speed, kind_speeds(s)["brim"] == s.first_layer_speed
    (True, True)
    """
    return {"external": s.external_perimeter_speed, "internal": s.perimeter_speed,
            "hole": s.external_perimeter_speed, "gap_fill": s.gap_fill_speed, "sparse": s.infill_speed,
            "solid": s.solid_infill_speed, "top": s.top_solid_infill_speed, "bridge": s.bridge_speed,
            "support": s.support_speed, "support_interface": s.support_speed,
            "overhang": s.bridge_speed,
            "skirt": s.first_layer_speed, "brim": s.first_layer_speed}


def lift_at(z: float, lift: float, max_height: float) -> float:
    """The nozzle's lift on travels at height `z`: `lift`, but never above the printer's `max_height`.

    Examples
    --------
    >>> lift_at(10.0, 0.2, 210.0), lift_at(209.9, 0.2, 210.0) < 0.1 + 1e-9, lift_at(210.0, 0.2, 210.0)
    (0.2, True, 0.0)
    """
    return float(min(lift, max(0.0, max_height - z)))


@dataclass(frozen=True, eq=False)
class WriterSettings:
    """The settings as the compiled writer takes them, made once for many layers: each kind's
    speed, the layer's numbers but z, height, first layer, factor and the move after the layer
    (`layer_moves`; the machine's limits among them, `slicelab.gcode.estimate.machine_limits`), and the
    travel and retraction feeds as written."""

    speeds: np.ndarray
    numbers: np.ndarray
    travel: str
    travel_f: np.ndarray
    retract_f: np.ndarray
    max_height: float = math.inf

    @classmethod
    def of(cls, s) -> "WriterSettings":
        speeds = kind_speeds(s)
        travel = f"{60 * s.travel_speed:.0f}"
        numbers = np.array([0.0, 0.0, s.extrusion_multiplier / s.filament_area, s.bridge_strand, 0.0, 1.0,
                            float(s.small_perimeter_speed), float(s.min_print_speed), float(s.first_layer_speed),
                            round(60 * s.travel_speed) / 60, round(60 * s.retraction_speed) / 60,
                            float(s.retraction_length), float(s.z_lift), float(s.retract_min_travel), SMALL_PERIMETER,
                            *machine_limits(s).vector(), 0.0, 0.0, 0.0, 0.0, 0.0])
        return cls(np.array([float(speeds[kind]) for kind in STYLES]), numbers, travel,
                   np.frombuffer(travel.encode("ascii"), np.uint8).copy(),
                   np.frombuffer(f"{60 * s.retraction_speed:.0f}".encode("ascii"), np.uint8).copy(),
                   float(s.max_height))


@dataclass(frozen=True, eq=False)
class CompiledLayer:
    """A layer's inputs to the compiled writer (`layer_moves`), made once for its runs at several speeds."""

    head: str
    xy: np.ndarray
    counts: np.ndarray
    kind: np.ndarray
    width: np.ndarray
    numbers: np.ndarray
    start: np.ndarray
    pos: np.ndarray
    settings: WriterSettings

    @classmethod
    def of(cls, k: int, lp, h: float, w: WriterSettings, off, pos, at, then=None) -> "CompiledLayer":
        """The layer's inputs (a path of a single point, which lays nothing, left out); `then` is
        the move after the layer (dx, dy, dz, de, feed), which its time ends into (default: the
        next layer's rise, `h` up at the travel feed; see `slicelab.gcode.writer.next_move`)."""
        pieces = [q for q in lp.pieces() if len(q[1]) >= 2]  # (a point alone lays nothing)
        z = lp.z + 0.0
        counts = np.array([len(q[1]) for q in pieces], np.int64)
        numbers = w.numbers.copy()
        numbers[:2] = z, h
        numbers[4] = 1.0 if k == 0 else 0.0
        numbers[12] = lift_at(z, numbers[12], w.max_height)
        numbers[32:37] = (0.0, 0.0, h, 0.0, numbers[9]) if then is None else then
        return cls(f"G1 Z{z:.3f} F{w.travel}\n",
                   np.ascontiguousarray(np.concatenate([q[1] for q in pieces] or [np.zeros((0, 2))]) + off[:2],
                                        np.float64), counts,
                   np.array([KIND_INDEX[q[0]] for q in pieces], np.int64),
                   np.concatenate([np.full(m, q[2], np.float64) if np.isscalar(q[2]) else
                                   np.asarray(q[2], np.float64) for m, q in zip(counts.tolist(), pieces)]
                                  or [np.zeros(0)]),
                   numbers, np.array([float(v) for v in np.asarray(at, np.float64)[:3]]),
                   np.zeros(3) if pos is None else np.array([float(pos[0]), float(pos[1]), 1.0]), w)

    def run(self, factor: float, text: bool):
        """(text or None, filament, seconds) at extrusion speeds times `factor`; the text is
        None if a number could not be written (beyond what G-code holds)."""
        numbers = self.numbers.copy()
        numbers[5] = factor
        w = self.settings
        out, size, used, t = layer_moves(self.xy, self.counts, self.kind, self.width, numbers, w.speeds,
                                         PERIMETER_KINDS, BRIDGE, WORD_BYTES, WORD_AT, w.travel_f, w.retract_f,
                                         self.start, self.pos, bool(text))
        if size < 0:
            return None, used, t
        return (self.head + out[:size].tobytes().decode("ascii") if text else ""), used, t
