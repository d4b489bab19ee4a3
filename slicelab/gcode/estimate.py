"""Print-time estimate: every move's time under a firmware's motion planner, vectorised.

The model is Marlin's planner with classic jerk, as PrusaSlicer's G-code
processor simulates it, under the machine's limits (`MachineLimits`: the
settings' ``machine_max_*``, as the G-code file states them to the printer):

- a move's length L is its XYZ distance (an extrusion-only move: its filament);
  its feed rate F (mm/s) is cut so that no axis runs faster than its maximum
  feed rate; it accelerates at the acceleration of its kind (printing:
  extruding, filament only: retracting, else travel), cut so that no axis
  accelerates faster than its maximum;
- it runs a trapezoidal speed profile: up from its entry speed to F, a cruise,
  down to its exit speed (a triangle when it is too short to reach F);
- the speed at a junction is Marlin's classic jerk: the smaller of the two feed
  rates, lowered until no axis's speed changes by more than that axis's jerk
  across the junction (the previous move's velocity taken at the junction
  speed, the next one's at its own feed rate, as the firmware does); where both
  moves' *safe* speeds (a move's F, at most each moving axis's jerk) exceed
  it, the next move's safe speed. A stream starts at its first move's safe
  speed and ends at its last one's (or at its junction with a move given to
  follow it, `then`);
- junction speeds are then lowered until every move can make them: a move
  cannot gain or lose more than ``2 a L`` of squared speed (the planner's
  forward and backward passes). Both passes are one ``np.minimum.accumulate``
  each: with ``u = v^2`` and S the running sum of ``2 a L``, the forward pass
  ``u[j] = min(C[j], u[j-1] + 2 a L[j-1])`` is
  ``S[j] + min over k <= j of (C[k] - S[k])``.

Moves of no length take no time and are left out of the planning (as the
firmware leaves them out). Homing and heating are not counted (nor by
PrusaSlicer); dwells (G4) are counted by `slicelab.gcode.reading.file_seconds`.

References
----------
Marlin's planner (Marlin/src/module/planner.cpp: classic jerk, trapezoid
generation with look-ahead); PrusaSlicer's GCodeProcessor, which simulates it
to estimate a G-code file's time.

See Also
--------
slicelab.gcode.writer.write_gcode : writes the estimate in PrusaSlicer's words.
slicelab.gcode.writer.machine_lines : the limits written into the G-code.
slicelab.gcode.reading : a G-code file's moves and limits, read back.
slicelab.gcode.text_kernels.stream_seconds : the same model, compiled, as the writer uses it.
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

__all__ = ["MachineLimits", "machine_limits", "move_times", "format_duration", "JUNCTION_FLOOR"]

#: A previous move slower than this (mm/s) has no junction with the next: the next starts at its safe speed.
JUNCTION_FLOOR = 1e-4


@dataclass(frozen=True)
class MachineLimits:
    """What the firmware's planner allows: accelerations (mm/s^2), feed rates and jerks (mm/s).

    Defaults are PrusaSlicer's (its machine limits' first values). Per-axis
    numbers are (X, Y, Z, E).

    Examples
    --------
    >>> MachineLimits().vector()[:4].tolist()
    [1500.0, 1500.0, 1500.0, 9000.0]
    >>> MachineLimits.from_vector(MachineLimits(travel=3000.0).vector()).travel
    3000.0
    """

    extruding: float = 1500.0
    retracting: float = 1500.0
    travel: float = 1500.0
    max_acceleration: tuple = (9000.0, 9000.0, 500.0, 10000.0)
    max_feedrate: tuple = (500.0, 500.0, 12.0, 120.0)
    max_jerk: tuple = (10.0, 10.0, 0.2, 2.5)
    min_extruding_rate: float = 0.0
    min_travel_rate: float = 0.0

    def vector(self) -> np.ndarray:
        """The 17 numbers the compiled planner takes: extruding, retracting, travel, the axes'
        accelerations, feed rates and jerks, the minimum extruding and travel rates."""
        return np.array([self.extruding, self.retracting, self.travel, *self.max_acceleration, *self.max_feedrate,
                         *self.max_jerk, self.min_extruding_rate, self.min_travel_rate], np.float64)

    @classmethod
    def from_vector(cls, v) -> "MachineLimits":
        v = [float(x) for x in v]
        return cls(v[0], v[1], v[2], tuple(v[3:7]), tuple(v[7:11]), tuple(v[11:15]), v[15], v[16])

    def replace(self, **changes) -> "MachineLimits":
        """A copy with some fields changed."""
        return type(self)(**{**{f.name: getattr(self, f.name) for f in fields(self)}, **changes})


def _written(v: float, scale: float = 1.0) -> float:
    """A limit as the G-code states it: `scale` x `v` with two decimals, read back (`machine_lines`)."""
    return float(f"{v * scale:.2f}") / scale


def machine_limits(s) -> MachineLimits:
    """The limits a print's moves run under, from settings `s`: what its G-code tells the printer.

    ``machine_limits_usage`` ``"ignore"``: PrusaSlicer's defaults (nothing is
    written; PrusaSlicer's estimator assumes them too). Otherwise the
    ``machine_max_*`` settings, with `acceleration` (above 0) in place of the
    three accelerations of moves and `jerk` (above 0) in place of the X and Y
    jerks. Written (``"emit_to_gcode"``), each is taken as written: two
    decimals, in the flavour's unit (RepRapFirmware's feed rates and jerks in
    mm/min); Klipper is told one acceleration (M204 S), which all moves take,
    as its firmware has one; RepRapFirmware has printing and travel
    accelerations (M204 P T), a retraction taking the travel one.

    Examples
    --------
    >>> from slicelab.printing import PrintSettings
    >>> machine_limits(PrintSettings()).extruding, machine_limits(PrintSettings(acceleration=800)).travel
    (1500.0, 800.0)
    >>> machine_limits(PrintSettings(jerk=8, gcode_flavor="klipper", machine_max_acceleration_travel=5000)).travel
    1500.0
    """
    if s.machine_limits_usage == "ignore":
        return MachineLimits()
    acc = (s.acceleration,) * 3 if s.acceleration > 0 else (
        s.machine_max_acceleration_extruding, s.machine_max_acceleration_retracting, s.machine_max_acceleration_travel)
    jx, jy = (s.jerk, s.jerk) if s.jerk > 0 else (s.machine_max_jerk_x, s.machine_max_jerk_y)
    axes = (s.machine_max_acceleration_x, s.machine_max_acceleration_y, s.machine_max_acceleration_z,
            s.machine_max_acceleration_e)
    feeds = (s.machine_max_feedrate_x, s.machine_max_feedrate_y, s.machine_max_feedrate_z, s.machine_max_feedrate_e)
    jerks = (jx, jy, s.machine_max_jerk_z, s.machine_max_jerk_e)
    if s.gcode_flavor == "klipper":  # one acceleration for every move
        acc = (acc[0],) * 3
    elif s.gcode_flavor == "reprapfirmware":  # a retraction, moving no axis, is a travel move to it
        acc = (acc[0], acc[2], acc[2])
    if s.machine_limits_usage == "emit_to_gcode":
        acc = tuple(_written(a) for a in acc)
        if s.gcode_flavor != "klipper":  # (Klipper is told the acceleration only)
            per_min = 60.0 if s.gcode_flavor == "reprapfirmware" else 1.0
            axes = tuple(_written(a) for a in axes)
            feeds = tuple(_written(f, per_min) for f in feeds)
            jerks = tuple(_written(j, per_min) for j in jerks)
    return MachineLimits(*(float(a) for a in acc), tuple(map(float, axes)), tuple(map(float, feeds)),
                         tuple(map(float, jerks)))


def _moves(D: np.ndarray, length: np.ndarray, feed: np.ndarray, L: np.ndarray):
    """Each move's cruise speed, acceleration, safe speed and velocity (X, Y, Z, E) under limits
    vector `L` (`MachineLimits.vector`): `D` the moves' (dx, dy, dz, de), all of some length."""
    inv = 1.0 / length
    share = np.abs(D) * inv[:, None]  # each axis's travel per mm of the move
    f = np.maximum(feed, np.where(D[:, 3] == 0, L[16], L[15]))
    speed = share * f[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        cut = np.where(speed > 0, L[7:11] / speed, np.inf).min(axis=1)
        cruise = f * np.minimum(cut, 1.0)
        v = (D * inv[:, None]) * cruise[:, None]
        xy = (D[:, 0] != 0) | (D[:, 1] != 0)
        base = np.where((D[:, 0] == 0) & (D[:, 1] == 0) & (D[:, 2] == 0), L[1],
                        np.where((D[:, 3] > 0) & xy, L[0], L[2]))
        acc = np.minimum(base, np.where(share > 0, L[3:7] / share, np.inf).min(axis=1))
    jerk = L[11:15]
    safe = np.minimum(cruise, np.where(np.abs(v) > jerk, jerk, np.inf).min(axis=1))
    return cruise, acc, safe, v


def _junctions(cruise: np.ndarray, safe: np.ndarray, v: np.ndarray, L: np.ndarray) -> np.ndarray:
    """The speed at each junction of consecutive moves (Marlin's classic jerk, see the module)."""
    pf, cf = cruise[:-1], cruise[1:]
    larger = pf > cf
    with np.errstate(divide="ignore", invalid="ignore"):
        vx = v[:-1] * np.where(larger, cf / pf, 1.0)[:, None]  # the previous move's velocity, at the junction
        vn = v[1:]
        jump = np.where(vx > vn, np.where((vn > 0) | (vx < 0), vx - vn, np.maximum(vx, -vn)),
                        np.where((vn < 0) | (vx > 0), vn - vx, np.maximum(-vx, vn)))
        jerk = L[11:15]
        factor = np.where(jump > jerk, jerk / jump, 1.0).min(axis=1)
    vj = np.where(larger, cf, pf) * factor
    near = vj * 0.99
    vj = np.where((safe[:-1] > near) & (safe[1:] > near), safe[1:], vj)
    return np.where(pf > JUNCTION_FLOOR, vj, safe[1:])


def move_times(start: np.ndarray, end: np.ndarray, extrusion: np.ndarray, feed: np.ndarray,
               limits: MachineLimits | None = None, *, then=None) -> np.ndarray:
    """Seconds each move of a stream takes (see the module's model).

    Parameters
    ----------
    start, end : (n, 3) ndarray
        Nozzle position (x, y, z) before and after each move; moves follow each
        other (``end[i] == start[i + 1]``).
    extrusion : (n,) ndarray
        Filament each move feeds (mm, relative; negative retracts).
    feed : (n,) ndarray
        Feed rate of each move (mm/s).
    limits : MachineLimits, optional
        The machine's (default: PrusaSlicer's defaults).
    then : sequence of 5 floats, optional
        The move after the stream, (dx, dy, dz, de, feed): its junction with the
        last move is where the stream ends (default: the last move's safe speed).
        Its own time is not counted.

    Returns
    -------
    (n,) ndarray

    See Also
    --------
    format_duration : a time as PrusaSlicer writes it.
    slicelab.gcode.reading.file_seconds : a G-code file's time.

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [100, 0, 0], [200, 0, 0], [200, 100, 0]], float)
    >>> t = move_times(p[:-1], p[1:], np.zeros(3), np.full(3, 50.0))
    >>> round(float(t[:2].sum()), 4)   # 200 mm at 50 mm/s from 10 mm/s (the jerk), down to 10 for the corner
    4.0213
    >>> still = MachineLimits(max_jerk=(0.0, 0.0, 0.0, 0.0))   # no jerk: from and to a stop
    >>> round(float(move_times(p[:1], p[1:2], [0.0], [50.0], still)[0]), 4)   # L / F + F / a
    2.0333
    """
    L = (MachineLimits() if limits is None else limits).vector()
    start = np.asarray(start, np.float64).reshape(-1, 3)
    end = np.asarray(end, np.float64).reshape(-1, 3)
    e = np.asarray(extrusion, np.float64).reshape(-1)
    f = np.asarray(feed, np.float64).reshape(-1)
    n = len(start)
    t = np.zeros(n)
    d = end - start
    xyz = np.sqrt((d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]) + d[:, 2] * d[:, 2])
    length = np.where(xyz > 0, xyz, np.abs(e))
    keep = np.flatnonzero((length > 0) & (f > 0))
    m = len(keep)
    if m == 0:
        return t
    D = np.column_stack([d[keep], e[keep]])
    lengths, feeds = length[keep], f[keep]
    if then is not None:
        nx = np.asarray(then, np.float64).reshape(5)
        nl = np.sqrt((nx[0] * nx[0] + nx[1] * nx[1]) + nx[2] * nx[2])
        nl = nl if nl > 0 else abs(nx[3])
        if nl > 0 and nx[4] > 0:
            D, lengths, feeds = np.vstack([D, nx[:4]]), np.append(lengths, nl), np.append(feeds, nx[4])
    cruise, acc, safe, v = _moves(D, lengths, feeds, L)
    cap = np.empty(m + 1)
    cap[0] = safe[0] * safe[0]
    vj = _junctions(cruise, safe, v, L)
    cap[1:1 + len(vj)] = vj * vj
    if len(vj) < m:  # nothing follows: the last move ends at its safe speed
        cap[m] = safe[m - 1] * safe[m - 1]
    cruise, acc, lengths = cruise[:m], acc[:m], lengths[:m]
    gain = 2 * acc * lengths  # squared speed a move can gain or lose
    s = np.concatenate([[0.0], np.cumsum(gain)])
    fwd = np.minimum.accumulate(cap - s) + s  # u[j] <= u[j - 1] + gain[j - 1]
    fwd = np.minimum(fwd, cap)
    bwd = np.minimum.accumulate((fwd + s)[::-1])[::-1] - s  # u[j] <= u[j + 1] + gain[j]
    u = np.clip(np.minimum(bwd, fwd), 0.0, None)
    ff = cruise * cruise
    u0, u1 = np.minimum(u[:-1], ff), np.minimum(u[1:], ff)  # (a junction above a move's feed rate: cruising)
    v0, v1 = np.sqrt(u0), np.sqrt(u1)
    peak2 = acc * lengths + 0.5 * (u0 + u1)  # the squared speed a triangle profile reaches
    t_cruise = (cruise - v0) / acc + (cruise - v1) / acc + (lengths - (2 * cruise * cruise - u0 - u1) / (2 * acc)) / cruise
    t_triangle = (2 * np.sqrt(peak2) - v0 - v1) / acc
    t[keep] = np.where(peak2 >= ff, t_cruise, t_triangle)
    return t


def format_duration(seconds: float) -> str:
    """A duration as PrusaSlicer writes it: ``1d 2h 3m 4s``, leading zero units left out.

    Examples
    --------
    >>> format_duration(3723.4), format_duration(59.6), format_duration(90061)
    ('1h 2m 3s', '1m 0s', '1d 1h 1m 1s')
    """
    t = int(round(float(seconds)))
    days, t = divmod(t, 86400)
    hours, t = divmod(t, 3600)
    minutes, secs = divmod(t, 60)
    if days:
        return f"{days}d {hours}h {minutes}m {secs}s"
    if hours:
        return f"{hours}h {minutes}m {secs}s"
    if minutes:
        return f"{minutes}m {secs}s"
    return f"{secs}s"
