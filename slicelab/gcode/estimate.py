"""Print-time estimate: every move's time under a firmware-like motion planner, vectorised.

The model is a printer firmware's (Grbl's and Marlin's look-ahead planner):

- a move of length L (mm; an extrusion-only move counts its filament length)
  runs a trapezoidal speed profile: it accelerates at `acceleration` from its
  entry speed to its feed rate F, cruises, and decelerates to its exit speed
  (a triangle when it is too short to reach F);
- consecutive moves in the plane (travel or extrusion) pass their junction
  without stopping, at most at ``min(F_in, F_out, jerk / (2 sin(phi / 2)))``,
  phi the turn between them: the speed vector may change by at most `jerk`
  (classic jerk, as Prusa's firmware has it); a straight junction needs no
  slowing;
- the printer stops at every other junction: before and after a Z move
  (layer change, lift), a retraction or a prime, and at the start and end;
- junction speeds are then lowered until every move can make them: a move
  cannot gain or lose more than ``2 a L`` of squared speed (the planner's
  forward and backward passes). Both passes are one ``np.minimum.accumulate``
  each: with ``u = v^2`` and S the running sum of ``2 a L``, the forward pass
  ``u[j] = min(C[j], u[j-1] + 2 a L[j-1])`` is
  ``S[j] + min over k <= j of (C[k] - S[k])``.

Homing, heating and dwell times are not counted.

References
----------
S. K. Jeon, Grbl's motion planner (planner.c, 2011-2016), and Marlin's
(Marlin/src/module/planner.cpp): trapezoid generation with look-ahead.

See Also
--------
slicelab.gcode.writer.write_gcode : writes the estimate in PrusaSlicer's words.
"""
from __future__ import annotations

import numpy as np

__all__ = ["move_times", "format_duration"]


def move_times(start: np.ndarray, end: np.ndarray, extrusion: np.ndarray, feed: np.ndarray, *,
               acceleration: float = 1000.0, jerk: float = 8.0) -> np.ndarray:
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
    acceleration : float, default 1000
        mm/s^2, the same on every axis.
    jerk : float, default 8
        Largest instant change of the speed vector at a junction (mm/s).

    Returns
    -------
    (n,) ndarray

    See Also
    --------
    format_duration : a time as PrusaSlicer writes it.

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [100, 0, 0], [200, 0, 0], [200, 100, 0]], float)
    >>> t = move_times(p[:-1], p[1:], np.zeros(3), np.full(3, 50.0), acceleration=1000, jerk=8)
    >>> round(float(t[:2].sum()), 4)   # 200 mm at 50 mm/s, slowing to 8 / (2 sin 45) for the corner
    4.0447
    >>> round(float(move_times(p[:1], p[1:2], [0.0], [50.0])[0]), 4)   # alone: L / F + F / a
    2.05
    """
    start = np.asarray(start, np.float64).reshape(-1, 3)
    end = np.asarray(end, np.float64).reshape(-1, 3)
    e = np.asarray(extrusion, np.float64).reshape(-1)
    f = np.asarray(feed, np.float64).reshape(-1)
    n = len(start)
    if n == 0:
        return np.zeros(0)
    a = float(acceleration)
    d = end - start
    planar = np.hypot(d[:, 0], d[:, 1])
    length = np.sqrt(planar ** 2 + d[:, 2] ** 2)
    length = np.where(length > 0, length, np.abs(e))
    in_plane = (planar > 0) & (d[:, 2] == 0)
    # Junction j lies between moves j - 1 and j; 0 and n are the stream's ends.
    cap = np.zeros(n + 1)
    join = in_plane[:-1] & in_plane[1:]
    if join.any():
        u0 = d[:-1, :2] / np.where(planar[:-1] > 0, planar[:-1], 1.0)[:, None]
        u1 = d[1:, :2] / np.where(planar[1:] > 0, planar[1:], 1.0)[:, None]
        half_sin = 0.5 * np.hypot(*(u1 - u0).T)  # sin(phi / 2)
        with np.errstate(divide="ignore"):
            corner = np.where(half_sin > 1e-12, float(jerk) / (2 * half_sin), np.inf)
        v = np.minimum(np.minimum(f[:-1], f[1:]), corner)
        cap[1:-1] = np.where(join, v * v, 0.0)
    gain = 2 * a * length  # squared speed a move can gain or lose
    s = np.concatenate([[0.0], np.cumsum(gain)])
    fwd = np.minimum.accumulate(cap - s) + s  # u[j] <= u[j - 1] + gain[j - 1]
    fwd = np.minimum(fwd, cap)
    bwd = np.minimum.accumulate((fwd + s)[::-1])[::-1] - s  # u[j] <= u[j + 1] + gain[j]
    u = np.clip(np.minimum(bwd, fwd), 0.0, None)
    v0, v1 = np.sqrt(u[:-1]), np.sqrt(u[1:])
    peak2 = a * length + 0.5 * (u[:-1] + u[1:])  # the squared speed a triangle profile reaches
    cruise = peak2 >= f * f
    t_cruise = (f - v0) / a + (f - v1) / a + (length - (2 * f * f - u[:-1] - u[1:]) / (2 * a)) / f
    vp = np.sqrt(peak2)
    t_triangle = (2 * vp - v0 - v1) / a
    return np.where(length > 0, np.where(cruise, t_cruise, t_triangle), 0.0)


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
