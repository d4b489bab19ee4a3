"""A G-code file read back for its time: its moves and the machine limits it states.

`read_moves` turns a file's text (slicelab's, PrusaSlicer's, any slicer's
Marlin, RepRapFirmware or Klipper G-code) into the arrays
`slicelab.gcode.estimate.move_times` takes: every G0/G1 move's start and end
(absolute XYZ, after G90/G91 and G92), the filament it feeds (relative, after
M82/M83), its feed rate (mm/s) and the limits in force when it runs, as the
file's M201 (axes' accelerations), M203 (feed rates), M204 (accelerations of
moves: P R T, or S for printing and travel and T for retracting, the old
Marlin form; Klipper's S is its one acceleration; RepRapFirmware's P T, a
retraction taking T), M205 (X Y Z E jerks, S T minimum feed rates) and M566
(RepRapFirmware's jerks) set them, over PrusaSlicer's defaults. RepRapFirmware's
M203 and M566 are in mm/min: the flavour is read from the file's ``; flavor =``
(slicelab's) or ``; gcode_flavor =`` (PrusaSlicer's) line, or given. G4 dwells
are summed; homing (G28) moves the nozzle to 0 on its axes without time, as
heating waits take none (neither counts in PrusaSlicer's estimate, but for its
G28, which it times as a move).

`file_seconds` is the estimate of the whole file (each stretch under one set of
limits a stream of its own), `stated_seconds` the time a file announces in
PrusaSlicer's words.

See Also
--------
slicelab.gcode.writer.machine_lines : the limits slicelab writes.
scripts/check_estimate.py : this estimate against PrusaSlicer's on PrusaSlicer's files.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .estimate import MachineLimits, move_times

__all__ = ["FileMoves", "read_moves", "file_seconds", "estimate_file", "stated_seconds", "file_flavor"]

_FLAVOR = re.compile(r"^; *(?:gcode_)?flavor *= *(\w+)", re.M)
_STATED = re.compile(r"^; estimated printing time \(normal mode\) = (.*)$", re.M)
_AXES = "XYZE"


@dataclass(frozen=True)
class FileMoves:
    """A file's moves: `start`, `end` (n, 3), `e` (n,: filament, relative), `feed` (n,: mm/s),
    `stretch` (n,: the index in `limits` of the limits each runs under), the `dwell` (s) of its
    G4s and its `flavor`."""

    start: np.ndarray
    end: np.ndarray
    e: np.ndarray
    feed: np.ndarray
    stretch: np.ndarray
    limits: list
    dwell: float
    flavor: str


def file_flavor(text: str, default: str = "marlin") -> str:
    """The flavour a G-code text names (slicelab's ``; flavor =``, PrusaSlicer's ``; gcode_flavor =``).

    Examples
    --------
    >>> file_flavor("; gcode_flavor = reprapfirmware\\n"), file_flavor("G1 X0\\n")
    ('reprapfirmware', 'marlin')
    """
    found = _FLAVOR.search(text)
    return found.group(1).lower() if found else default


def _words(parts: list) -> dict:
    """The numeric words of a command (``X12.5`` -> {'X': 12.5}); lone letters and bad numbers left out."""
    out = {}
    for w in parts:
        if len(w) > 1:
            try:
                out[w[0].upper()] = float(w[1:])
            except ValueError:
                pass
    return out


def _limited(value: float) -> float:
    """An axis's maximum acceleration or feed rate as a file states it: 0 (or less) is no limit."""
    return value if value > 0 else np.inf


def _new_limits(cmd: str, v: dict, m: MachineLimits, flavor: str) -> MachineLimits:
    """The limits after one M201/M203/M204/M205/M566 command."""
    per = 60.0 if flavor == "reprapfirmware" else 1.0
    if cmd == "M201":
        return m.replace(max_acceleration=tuple(_limited(v[a]) if a in v else x
                                                for a, x in zip(_AXES, m.max_acceleration)))
    if cmd == "M203":
        return m.replace(max_feedrate=tuple(_limited(v[a] / per) if a in v else x
                                            for a, x in zip(_AXES, m.max_feedrate)))
    if cmd == "M204":
        ok = {k: x for k, x in v.items() if x > 0}
        if "S" in ok:  # the old form: printing and travel (Klipper: every move), T retracting
            if flavor == "klipper":
                return m.replace(extruding=ok["S"], travel=ok["S"], retracting=ok["S"])
            return m.replace(extruding=ok["S"], travel=ok["S"], retracting=ok.get("T", m.retracting))
        if flavor == "reprapfirmware":  # printing and travel: a retraction is a travel move
            return m.replace(extruding=ok.get("P", m.extruding), retracting=ok.get("T", m.retracting),
                             travel=ok.get("T", m.travel))
        return m.replace(extruding=ok.get("P", m.extruding), retracting=ok.get("R", m.retracting),
                         travel=ok.get("T", m.travel))
    if cmd in ("M205", "M566"):
        per = 60.0 if cmd == "M566" else 1.0
        out = m.replace(max_jerk=tuple(max(v[a] / per, 0.0) if a in v else x for a, x in zip(_AXES, m.max_jerk)))
        if cmd == "M205":
            out = out.replace(min_extruding_rate=max(v.get("S", m.min_extruding_rate), 0.0),
                              min_travel_rate=max(v.get("T", m.min_travel_rate), 0.0))
        return out
    return m


def read_moves(text: str, *, flavor: str | None = None, limits: MachineLimits | None = None) -> FileMoves:
    """Every move of a G-code text with the machine limits it runs under (see the module).

    Parameters
    ----------
    text : str
        The file's text.
    flavor : str, optional
        marlin, klipper, reprapfirmware...; default: the one the file names, else marlin.
    limits : MachineLimits, optional
        The limits before the file states any (default: PrusaSlicer's defaults).

    Returns
    -------
    FileMoves

    Examples
    --------
    >>> f = read_moves("M204 P800 R900 T2000\\nG90\\nM83\\nG1 Z0.2 F600\\nG1 X10 E0.5 F1200\\nG4 P500\\n")
    >>> f.end.tolist(), f.e.tolist(), f.feed.tolist(), f.limits[f.stretch[-1]].travel, f.dwell
    ([[0.0, 0.0, 0.2], [10.0, 0.0, 0.2]], [0.0, 0.5], [10.0, 20.0], 2000.0, 0.5)
    """
    flavor = file_flavor(text) if flavor is None else flavor
    current = MachineLimits() if limits is None else limits
    all_limits = [current]
    pos = [0.0, 0.0, 0.0]
    e_at = 0.0
    feed = 0.0
    absolute, relative_e = True, False
    dwell = 0.0
    start, end, es, feeds, stretch = [], [], [], [], []
    for line in text.splitlines():  # over lines: a parser's loop
        code = line.split(";", 1)[0].strip()
        if not code:
            continue
        parts = code.split()
        cmd = parts[0].upper()
        if cmd in ("G0", "G1"):
            v = _words(parts[1:])
            if "F" in v:
                feed = v["F"] / 60.0
            new = [(v[a] if absolute else p + v[a]) if a in v else p for a, p in zip("XYZ", pos)]
            de = 0.0
            if "E" in v:
                if relative_e or not absolute:
                    de = v["E"]
                    e_at += de
                else:
                    de, e_at = v["E"] - e_at, v["E"]
            if new == pos and de == 0.0:
                continue
            start.append(pos)
            end.append(new)
            es.append(de)
            feeds.append(feed)
            stretch.append(len(all_limits) - 1)
            pos = new
        elif cmd == "G90":
            absolute = True
        elif cmd == "G91":
            absolute = False
        elif cmd == "M82":
            relative_e = False
        elif cmd == "M83":
            relative_e = True
        elif cmd == "G92":
            v = _words(parts[1:])
            if not v:
                v = dict(X=0.0, Y=0.0, Z=0.0, E=0.0)
            pos = [v.get(a, p) for a, p in zip("XYZ", pos)]
            e_at = v.get("E", e_at)
        elif cmd == "G28":
            axes = {w[0].upper() for w in parts[1:] if w[0].upper() in "XYZ"} or set("XYZ")
            pos = [0.0 if a in axes else p for a, p in zip("XYZ", pos)]
        elif cmd == "G4":
            v = _words(parts[1:])
            dwell += v.get("S", 0.0) + v.get("P", 0.0) / 1000.0
        elif cmd in ("M201", "M203", "M204", "M205", "M566"):
            changed = _new_limits(cmd, _words(parts[1:]), current, flavor)
            if changed != current:
                current = changed
                if stretch and stretch[-1] == len(all_limits) - 1:
                    all_limits.append(current)
                else:  # nothing ran under the last ones: replaced
                    all_limits[-1] = current
    n = len(start)
    return FileMoves(np.array(start, np.float64).reshape(n, 3), np.array(end, np.float64).reshape(n, 3),
                     np.array(es, np.float64), np.array(feeds, np.float64), np.array(stretch, np.int64),
                     all_limits, dwell, flavor)


def file_seconds(moves: FileMoves) -> float:
    """The estimated time of a file's moves (`read_moves`): each stretch under one set of limits
    planned as one stream (`slicelab.gcode.estimate.move_times`), plus its dwells.

    Examples
    --------
    >>> f = read_moves("M205 X0 Y0 Z0 E0\\nG1 X100 F3000\\n")   # no jerk: from and to a stop
    >>> round(file_seconds(f), 4)   # 100 mm at 50 mm/s, accelerating at 1500 mm/s^2: L / F + F / a
    2.0333
    """
    total = moves.dwell
    if len(moves.e) == 0:
        return total
    cuts = np.flatnonzero(np.diff(moves.stretch)) + 1
    for a, b in zip(np.r_[0, cuts], np.r_[cuts, len(moves.e)]):  # over stretches: a few
        t = move_times(moves.start[a:b], moves.end[a:b], moves.e[a:b], moves.feed[a:b],
                       moves.limits[int(moves.stretch[a])])
        total += float(t.sum())
    return total


def estimate_file(path, **options) -> float:
    """The estimated print time (s) of a G-code file (`read_moves` options)."""
    return file_seconds(read_moves(Path(path).read_text(encoding="utf-8", errors="replace"), **options))


def stated_seconds(text: str) -> float:
    """The time a G-code text announces in PrusaSlicer's words (``; estimated printing time (normal
    mode) = 1h 2m 3s``), the last such line; NaN if none.

    Examples
    --------
    >>> stated_seconds("; estimated printing time (normal mode) = 1h 2m 3s\\n")
    3723.0
    """
    found = _STATED.findall(text)
    if not found:
        return float("nan")
    units = {"d": 86400, "h": 3600, "m": 60, "s": 1}
    return float(sum(int(v) * units[u] for v, u in re.findall(r"(\d+)([dhms])", found[-1])))
