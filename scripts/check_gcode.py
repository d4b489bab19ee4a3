#!/usr/bin/env python3
"""Check that a printer can trust a G-code file, read back from disk, independently of the slicer.

The checker reads the moves with its own parser and imports neither ``slicelab.printing`` nor
``slicelab.gcode``'s writer: the part is known only by its mesh and exact plane sections
(``slicelab.load``, ``slicelab.slice_layers``), with numpy and shapely. Seven checks, each giving
its offending line numbers (1-based), worst first:

- ``syntax``: every live line (code before ``;``) is a known G/M/T command whose words are a
  letter and a number: no ``{template}``, no ``Ynan``. A refused line is not executed.
- ``heaters``: nozzle and bed set hot and waited for (M109/M190) before the first extrusion, set
  to S0, and the motors off (M84/M18), after the last one only.
- ``z_order``: the z of extruding moves never goes down (travels may hop up and back).
- ``first_layer``: the first layer extrudes at the part's bottom + ``first_layer_height``.
- ``inside_part``: every extrusion but skirt, brim and support (by ``;TYPE:``) lies in its layer's
  section, cut at mid-layer (a tenth of a micrometre below and above it: a middle in a horizontal
  face counts either side), widened by half its width (``;WIDTH:`` or ``line_width``) + tolerance.
- ``on_bed``: every move ends on the bed and between 0 and the maximum height.
- ``retraction``: a travel (the moves between two extrusions) longer than the threshold is made
  retracted (E < 0 or G10 since the last extrusion), and the filament is pushed back before the next
  extrusion.

Settings come from the options, else from the header's ``; key = value`` comments (slicelab's or
PrusaSlicer's names); a check whose inputs are unknown is skipped, saying which.

Usage: ``python scripts/check_gcode.py part.gcode --mesh part.stl [--json] [--bed 250x210]``; exit
status 0 when every check passes, 1 when one fails, 2 (one line on stderr) for unusable input.

Examples
--------
>>> import tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "t.gcode")
>>> _ = open(path, "w").write("; bed_size = (100, 100)\\nM190 S60\\nM109 S210\\nG28\\nM83\\nG1 Z0.2\\n"
...                           "G1 X10 Y10\\nG1 X20 Y10 E0.5\\nG1 E-1\\nG0 X20 Y30\\nG1 E1\\nG1 X30 Y30 E0.5\\n"
...                           "M104 S0\\nM140 S0\\nM84\\n")
>>> r = check_gcode(path)
>>> r.passed, [c.status for c in r.checks]
(True, ['pass', 'pass', 'pass', 'skip', 'skip', 'pass', 'skip'])
>>> check_gcode(path, retract_travel=25.0)["retraction"].status   # the 20 mm travel need not retract
'pass'
"""
from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

__all__ = ["CHECKS", "Check", "Report", "GcodeInputError", "check_gcode", "main"]

#: How far below and above the middle of a layer the checker cuts the part (mm): both sections count.
DEGENERATE = 1e-4
CHECKS = ("syntax", "heaters", "z_order", "first_layer", "inside_part", "on_bed", "retraction")
KNOWN = ({f"G{k}" for k in (0, 1, 2, 3, 4, 10, 11, 17, 18, 19, 20, 21, 28, 29, 80, 90, 91, 92)}
         | {f"M{k}" for k in (0, 1, 17, 18, 31, 73, 75, 76, 77, 82, 83, 84, 104, 105, 106, 107, 109, 114, 140,
                              141, 142, 150, 190, 191, 201, 202, 203, 204, 205, 206, 207, 208, 209, 220, 221,
                              300, 302, 400, 486, 500, 501, 503, 555, 566, 572, 593, 600, 601, 900, 907)})
#: Commands whose argument is text (messages, file, firmware and printer names), not numbers.
TEXT_COMMANDS = {"M23", "M28", "M30", "M32", "M115", "M117", "M118", "M928", "M862.1", "M862.2", "M862.3",
                 "M862.4", "M862.5", "M862.6"}
#: Commands that take lone axis letters (``G28 X Y``, ``M84 X Y E``).
FLAG_COMMANDS = {"G28", "G29", "M18", "M84"}
#: ``;TYPE:`` words of extrusions outside the part by design (slicelab's, PrusaSlicer's, Cura's).
EXEMPT_TYPES = {"skirt/brim", "skirt", "brim", "support material", "support material interface", "support",
                "support-interface", "wipe tower", "prime-tower", "custom"}
_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)"
_WORD = re.compile(rf"[A-Z]{_NUM}\Z")
_COMMAND = re.compile(r"(?:[GM]\d+(?:\.\d+)?|T\d+)\Z")
_FLOAT = re.compile(rf"{_NUM}(?:[eE][-+]?\d+)?")
#: The bulk of a slicer's file, read without splitting it into words.
_XY_MOVE = re.compile(rf"G[01] X({_NUM}) Y({_NUM})(?: E({_NUM}))?(?: F{_NUM})?\Z")


class GcodeInputError(ValueError):
    """The G-code, the mesh or an option cannot be used (exit status 2)."""


@dataclass(frozen=True)
class Check:
    """One check's outcome: `status` ``"pass"``, ``"fail"`` or ``"skip"`` (`detail` says why), the
    items `checked` and `failed`, the `worst` offenders as (line, how far off in mm or 0, message),
    worst first, and `value`, the worst measure (e.g. the largest distance outside, mm)."""

    name: str
    status: str
    checked: int = 0
    failed: int = 0
    worst: tuple = ()
    detail: str = ""
    value: float | None = None

    @property
    def passed(self) -> bool:
        return self.status != "fail"

    @property
    def lines(self) -> list:
        """The worst offenders' line numbers."""
        return [w[0] for w in self.worst]


@dataclass(frozen=True)
class Report:
    """Every check of one file (``report["inside_part"]`` is one), and the time they took (s)."""

    path: str
    checks: tuple
    seconds: float
    n_lines: int
    n_layers: int

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    def __getitem__(self, name: str) -> Check:
        return next(c for c in self.checks if c.name == name)

    def to_dict(self) -> dict:
        """Plain data for JSON; a distance without end (no section at that height) is None."""
        def plain(v):
            if isinstance(v, (list, tuple)):
                return [plain(x) for x in v]
            if isinstance(v, dict):
                return {k: plain(x) for k, x in v.items()}
            return None if isinstance(v, float) and not np.isfinite(v) else v
        return plain({**asdict(self), "passed": self.passed})


def _number(text, default=None):
    """The first number in `text` (``"0.2"``, ``"2,2"``, ``"75%"``), else `default`."""
    m = _FLOAT.search(str(text))
    return float(m.group()) if m else default


# ----------------------------------------------------------------------------- reading
def _parse(lines: list) -> dict:
    """Moves, events, layers and header of the lines, as a printer executes them.

    A move row is (line, x0, y0, z0, x1, y1, z1, e, G10/G11 as -1/+1, layer, type, width), e the
    filament fed whichever of M82/M83 is in force; positions not yet homed or given are NaN.
    """
    rows, bad, heat, motors_off, layers, types, header = [], [], [], [], [], {}, {}
    pos = [np.nan] * 3
    rel_xyz, abs_e, e_now, layer, typ, width, live = False, True, 0.0, -1, -1, np.nan, 0
    for no, raw in enumerate(lines, 1):  # over lines: the printer's state is sequential
        code, _, note = raw.partition(";")
        code = code.strip()
        if not code:
            if note.startswith("TYPE:"):
                typ = types.setdefault(note[5:].strip().lower(), len(types))
            elif note.startswith("WIDTH:"):
                width = _number(note[6:], np.nan)
            elif note.startswith("LAYER_CHANGE"):
                layer += 1
                layers.append([np.nan, np.nan])
            elif note.startswith(("Z:", "HEIGHT:")) and layers:
                layers[-1][note[0] == "H"] = _number(note, np.nan)
            elif " = " in note:
                key, _, value = note.partition(" = ")
                header.setdefault(key.strip(), value.strip())
            continue
        live += 1
        fast = None if rel_xyz else _XY_MOVE.match(code)
        if fast is not None:
            x, y, e = fast.groups()
            e = 0.0 if e is None else float(e)
            if abs_e and fast.group(3) is not None:
                e, e_now = e - e_now, e
            rows.append((no, *pos, float(x), float(y), pos[2], e, 0, layer, typ, width))
            pos = [float(x), float(y), pos[2]]
            continue
        words = code.upper().split()
        cmd = words[0]
        if "{" in code or "}" in code:
            bad.append((no, "template: " + code))
            continue
        if not _COMMAND.match(cmd) or not (cmd in KNOWN or cmd in TEXT_COMMANDS or cmd[0] == "T"):
            bad.append((no, "unknown command: " + code))
            continue
        v = {}
        for w in ([] if cmd in TEXT_COMMANDS else words[1:]):
            if _WORD.match(w):
                v[w[0]] = float(w[1:])
            elif len(w) == 1 and w.isalpha() and cmd in FLAG_COMMANDS:
                v[w] = None
            else:  # not executed: how a printer reads it is anyone's guess
                bad.append((no, f"bad word {w!r}: " + code))
                break
        else:
            if cmd in ("G0", "G1", "G2", "G3"):  # arcs by their chords
                new = [(p + v[a] if rel_xyz else v[a]) if a in v else p for a, p in zip("XYZ", pos)]
                e = 0.0
                if "E" in v:
                    e, e_now = (v["E"] - e_now, v["E"]) if abs_e else (v["E"], e_now)
                if any(a in v for a in "XYZE"):
                    rows.append((no, *pos, *new, e, 0, layer, typ, width))
                pos = new
            elif cmd in ("G10", "G11") and not v:  # firmware retraction (RepRapFirmware's G10 P.. sets a tool)
                rows.append((no, *pos, *pos, 0.0, -1 if cmd == "G10" else 1, layer, typ, width))
            elif cmd == "G28":
                pos = [0.0 if a in v or not any(b in v for b in "XYZ") else p for a, p in zip("XYZ", pos)]
            elif cmd in ("G90", "G91", "M82", "M83"):
                rel_xyz, abs_e = (cmd == "G91", abs_e) if cmd[0] == "G" else (rel_xyz, cmd == "M82")
            elif cmd == "G92":
                pos = [v[a] if v.get(a) is not None else p for a, p in zip("XYZ", pos)]
                e_now = v["E"] if v.get("E") is not None else e_now
            elif cmd in ("M104", "M109", "M140", "M190") and v.get("S", v.get("R")) is not None:
                heat.append((no, cmd, v.get("S", v.get("R"))))
            elif cmd in ("M84", "M18") and "S" not in v:  # M84 S<seconds> sets the idle time-out only
                motors_off.append(no)
    m = np.array(rows, np.float64).reshape(-1, 12)
    return dict(line=m[:, 0].astype(np.int64), start=m[:, 1:4], end=m[:, 4:7], e=m[:, 7], fw=m[:, 8],
                layer=m[:, 9].astype(np.int64), type=m[:, 10].astype(np.int64), width=m[:, 11], bad=bad,
                heat=heat, motors_off=motors_off, layers=np.array(layers, np.float64).reshape(-1, 2),
                types={i: t for t, i in types.items()}, header=header, live=live)


def _settings(header: dict, bed, max_height, offset, retract_travel) -> dict:
    """The options given, else the header's values under slicelab's or PrusaSlicer's names."""
    def get(*keys):  # a share ("112%", of the nozzle or the layer height) is not a length
        return next((_number(header[k]) for k in keys
                     if not header.get(k, "%").endswith("%") and _number(header[k]) is not None), None)

    def numbers(key):
        return [float(x) for x in _FLOAT.findall(header.get(key, ""))]
    box = None
    if bed is not None:
        box = (0.0, float(bed[0]), 0.0, float(bed[1]))
    elif len(numbers("bed_size")) == 2:
        box = (0.0, numbers("bed_size")[0], 0.0, numbers("bed_size")[1])
    elif len(numbers("bed_shape")) >= 6:  # PrusaSlicer's outline: "0x0,250x0,250x210,0x210"
        xy = np.array(numbers("bed_shape"), np.float64).reshape(-1, 2)
        box = (xy[:, 0].min(), xy[:, 0].max(), xy[:, 1].min(), xy[:, 1].max())
    if offset is None and len(numbers("slicelab offset")) == 3:
        offset = numbers("slicelab offset")
    flh = get("first_layer_height")
    if header.get("first_layer_height", "").endswith("%"):  # PrusaSlicer: of the layer height
        flh = _number(header["first_layer_height"], np.nan) / 100 * (get("layer_height") or np.nan)
    return dict(bed=box, max_height=max_height if max_height is not None else get("max_height", "max_print_height"),
                offset=None if offset is None else np.asarray(offset, np.float64), first_layer_height=flh,
                line_width=get("line_width", "extrusion_width") or np.nan,
                retract_length=get("retraction_length", "retract_length"),
                retract_travel=get("retract_min_travel", "retract_before_travel") if retract_travel is None
                else retract_travel)


# ----------------------------------------------------------------------------- checks
def _check(name, checked, lines, values, message, detail="", worst=10) -> Check:
    """A check from its offenders: line numbers, how far off each is, and `message(i)` for the worst."""
    lines, values = np.asarray(lines, np.int64), np.asarray(values, np.float64)
    order = np.argsort(-values, kind="stable")[:worst]
    return Check(name, "fail" if len(lines) else "pass", int(checked), len(lines),
                 tuple((int(lines[i]), round(float(values[i]), 4), message(i)) for i in order), detail,
                 round(float(values.max()), 4) if len(values) else None)


def _heaters(g, ext_any, worst) -> Check:
    """Nozzle and bed hot and waited for before the first extrusion; off, motors too, after the last only."""
    lines = g["line"][ext_any]
    if not len(lines):
        return Check("heaters", "fail", 0, 1, ((0, 0.0, "the file extrudes nothing"),))
    first, last = int(lines[0]), int(lines[-1])
    found = []
    for kind, (set_, wait) in {"nozzle": ("M104", "M109"), "bed": ("M140", "M190")}.items():
        ev = [(no, cmd, t) for no, cmd, t in g["heat"] if cmd in (set_, wait)]
        if not any(t > 0 and cmd == wait and no < first for no, cmd, t in ev):
            found.append((first, f"{kind} not heated and waited for ({wait} S>0) before the first extrusion"))
        found += [(no, f"{kind} off ({cmd} S0) before the last extrusion (line {last})")
                  for no, cmd, t in ev if t <= 0 and no < last]
        if not any(t <= 0 and no > last for no, cmd, t in ev):
            found.append((last, f"{kind} not switched off ({set_} S0) after the last extrusion"))
    found += [(no, f"motors off (M84/M18) before the last extrusion (line {last})")
              for no in g["motors_off"] if no < last]
    if not any(no > last for no in g["motors_off"]):
        found.append((last, "motors not switched off (M84/M18) after the last extrusion"))
    found.sort()
    return _check("heaters", len(g["heat"]) + len(g["motors_off"]), [f[0] for f in found], np.zeros(len(found)),
                  lambda i: found[i][1], f"first extrusion line {first}, last {last}", worst)


def _layer_planes(g, ext, bottom: float) -> tuple:
    """Each move's layer id (-1 for none) and each layer's top z and thickness: from the
    ``;LAYER_CHANGE`` ``;Z:`` ``;HEIGHT:`` comments when the file has them, else from the extrusions' z."""
    if len(g["layers"]) and (g["layer"][ext] >= 0).any():
        top, height = g["layers"].T.copy()
        seen = ext & (g["layer"] >= 0)  # a layer without ;Z: is at its extrusions' z
        zs = np.full(len(top), np.nan)
        zs[g["layer"][seen]] = g["end"][seen, 2]
        top = np.where(np.isnan(top), zs, top)
        step = np.diff(np.concatenate([[bottom], np.fmax.accumulate(np.nan_to_num(top, nan=bottom))]))
        return g["layer"], top, np.where(np.isnan(height), step, height)  # no ;HEIGHT:: its step up
    z = np.round(g["end"][:, 2], 3)
    top = np.unique(z[ext])
    return np.where(ext, np.searchsorted(top, z), -1), top, np.diff(np.concatenate([[bottom], top]))


def _distance(region, xy) -> np.ndarray:
    """Distances of points (n, 2) from `region` (inf if it is empty)."""
    import shapely
    return np.full(len(xy), np.inf) if region.is_empty else shapely.distance(region, shapely.points(xy))


def _farthest(region, lines, points: int) -> np.ndarray:
    """Each line's largest distance from `region` over its points 0.01 mm apart, or `points` along it if
    fewer (the distance is 1-Lipschitz: within half their spacing)."""
    import shapely
    lines = shapely.segmentize(lines, np.maximum(0.01, shapely.length(lines) / points))
    pts, which = shapely.get_coordinates(lines, return_index=True)
    return np.maximum.reduceat(_distance(region, pts), np.searchsorted(which, np.arange(len(lines))))


def _inside(g, ext, layers, s, mesh, tol, worst) -> Check:
    """Extrusions inside their layer's exact section widened by half their width (+ `tol`)."""
    import shapely
    import slicelab
    if mesh is None or s["offset"] is None:
        return Check("inside_part", "skip", detail="needs the mesh and its offset (header or --offset)")
    off, (ids, top, height) = s["offset"], layers
    width = np.where(np.isnan(g["width"]), s["line_width"], g["width"])
    exempt = np.isin(g["type"], [i for i, t in g["types"].items() if t in EXEMPT_TYPES])
    sel = np.flatnonzero(ext & ~exempt & (ids >= 0))
    if np.isnan(width[sel]).any():
        return Check("inside_part", "skip", detail="line width unknown (no ;WIDTH: nor line_width)")
    sel = sel[np.argsort(ids[sel], kind="stable")]
    used = np.unique(ids[sel])
    # The section a hair (DEGENERATE mm) below and above the middle of each layer: a middle that lies
    # in a horizontal face (a bridge's underside) is cut by both slicer and checker a float's rounding
    # off, and either side of the face is the part's section there.
    mid = top[used] - height[used] / 2 - off[2]
    below, above = ((slicelab.slice_layers(mesh, heights=mid + d) if len(used) else []) for d in
                    (-DEGENERATE, DEGENERATE))
    bad, far, reach, regions = [], [], [], {}
    for lo_sec, hi_sec, idx in zip(below, above, np.split(sel, np.flatnonzero(np.diff(ids[sel])) + 1)):
        region = shapely.union_all([shapely.make_valid(shapely.Polygon(p.exterior, [h for h in p.holes
                                                                                     if len(h) > 2]))
                                    for sec in (lo_sec, hi_sec) for p in sec.polygons
                                    if len(p.exterior) > 2])  # overlapping shells: union
        lines = shapely.linestrings(np.stack([g["start"][idx, :2], g["end"][idx, :2]], axis=1) - off[:2])
        wide = shapely.buffer(region, float(width[idx].min()) / 2 + tol, quad_segs=16)
        shapely.prepare(wide)
        outside = ~shapely.covers(wide, lines)  # every segment of the layer at once
        if not outside.any():
            continue
        out, lines, w = idx[outside], lines[outside], width[idx[outside]]
        # Those outside the narrowest widening, against their own width: one with an end beyond its
        # allowance fails; the others are settled by their own widening, a buffer per width.
        ends = _distance(region, shapely.get_coordinates(lines)).reshape(-1, 2)
        over = ends.max(axis=1) - w / 2
        fail = over > tol
        for wv in np.unique(w[~fail]):
            m = ~fail & (w == wv)
            fail[m] = ~shapely.covers(shapely.buffer(region, wv / 2 + tol, quad_segs=16), lines[m])
        cross = fail & (over <= tol)  # both ends inside, the middle out (across a hole): sampled
        over[cross] = _farthest(region, lines[cross], 100) - w[cross] / 2
        bad.append(out[fail])
        far.append(over[fail])
        reach.append(ends[fail].min(axis=1) + shapely.length(lines[fail]) / 2 - w[fail] / 2)
        regions[int(ids[out[0]])] = region
    bad, far, reach = ((np.concatenate(bad), np.concatenate(far), np.concatenate(reach)) if bad
                       else (np.zeros(0, int), np.zeros(0), np.zeros(0)))
    # The worst, by their ends or by how far their middle may reach, get their farthest point sampled
    # finely; the others keep their ends' distance (a lower bound).
    for i in {int(i) for key in (far, reach) for i in np.argsort(-key)[:worst]}:
        k = bad[i]
        line = shapely.linestrings([g["start"][k, :2] - off[:2], g["end"][k, :2] - off[:2]])
        far[i] = max(far[i], _farthest(regions[int(ids[k])], np.array([line]), 10000)[0] - width[k] / 2)
    far = np.maximum(far, tol)
    return _check("inside_part", len(sel), g["line"][bad], far,
                  lambda i: (f"{far[i]:.3f} mm outside the part + half its width" if np.isfinite(far[i]) else
                             "no closed section of the part at this layer")
                            + f" (layer {ids[bad[i]]}, {g['types'].get(int(g['type'][bad[i]]), 'no type')})",
                  f"{len(used)} layers; {int((ext & exempt).sum())} skirt/brim/support extrusions exempt", worst)


def _on_bed(g, moving, s, worst) -> Check:
    """Every move's end on the bed, 0 <= z <= max height (a straight move between two such points stays)."""
    if s["bed"] is None:
        return Check("on_bed", "skip", detail="bed size unknown (header bed_size/bed_shape or --bed)")
    x0, x1, y0, y1 = s["bed"]
    top = np.inf if s["max_height"] is None else s["max_height"]
    p = np.where((moving | (g["start"][:, 2] != g["end"][:, 2]))[:, None], g["end"], np.nan)  # moves only
    with np.errstate(invalid="ignore"):
        excess = np.nanmax(np.column_stack([x0 - p[:, 0], p[:, 0] - x1, y0 - p[:, 1], p[:, 1] - y1, -p[:, 2],
                                            p[:, 2] - top, np.zeros(len(p))]), axis=1)
    off = np.flatnonzero(excess > 1e-6)
    return _check("on_bed", int((~np.isnan(p[:, 0])).sum()), g["line"][off], excess[off],
                  lambda i: f"move to ({p[off[i], 0]:.3f}, {p[off[i], 1]:.3f}, {p[off[i], 2]:.3f}) is "
                            f"{excess[off[i]]:.3f} mm off the bed", f"bed {s['bed']}, max height {top}", worst)


def _retraction(g, ext, moving, s, worst) -> Check:
    """Long travels start retracted; no extrusion starts retracted. The filament fed by the moves that
    do not extrude (retractions < 0, primes > 0, G10/G11 as -1/+1 mm) since the last extrusion tells
    whether the nozzle is retracted at each move."""
    if s["retract_travel"] is None:
        return Check("retraction", "skip", detail="retraction threshold unknown (--retract-travel)")
    if s["retract_length"] == 0:
        return Check("retraction", "skip", detail="retraction is off in the file's settings")
    e, n = g["e"], len(g["e"])
    idx = np.arange(n)
    prev = np.concatenate([[-1], np.maximum.accumulate(np.where(ext, idx, -1))[:-1]])  # last extrusion before
    fed = np.concatenate([[0.0], np.cumsum(np.where(ext, 0.0, e + g["fw"]))])  # fed[i]: before move i
    since = fed[idx] - fed[prev + 1]
    travel = (e == 0) & (g["fw"] == 0) & moving & (prev >= 0)  # before the first extrusion: nothing to ooze
    length = np.hypot(*(g["end"][:, :2] - g["start"][:, :2]).T)
    run = np.bincount(prev[travel], np.nan_to_num(length[travel]), minlength=n)  # travel from each extrusion
    loose = travel & (since > -0.005) & (run[np.maximum(prev, 0)] > s["retract_travel"] + 2e-3)  # 3 decimals
    runs, first = np.unique(prev[loose], return_index=True)
    starved = np.flatnonzero(ext & (since < -0.01))
    rows = np.concatenate([np.flatnonzero(loose)[first], starved])
    vals = np.concatenate([run[runs], -since[starved]])
    return _check("retraction", len(np.unique(prev[travel])) + int(ext.sum()), g["line"][rows], vals,
                  lambda i: (f"travel of {vals[i]:.3f} mm starts unretracted" if i < len(runs)
                             else f"extrudes while retracted by {vals[i]:.3f} mm"),
                  f"travels over {s['retract_travel']} mm retract", worst)


def check_gcode(gcode_path, mesh_or_path=None, *, bed=None, max_height=None, offset=None, retract_travel=None,
                tolerance: float = 0.02, first_layer_tolerance: float = 0.01, worst: int = 10,
                units: str | None = None, scale: float | None = None, repair: bool = False,
                fill_holes: bool = False) -> Report:
    """Check a G-code file on disk (the seven checks of the module's docstring).

    Parameters
    ----------
    gcode_path : str or Path
    mesh_or_path : slicelab.Mesh or str or Path, optional
        The part, for ``inside_part`` and the part's bottom in ``first_layer`` (a path is read with
        ``slicelab.load(path, units=units, scale=scale)``).
    repair, fill_holes : bool, default False
        Mend the mesh first as ``slicelab slice --repair`` / ``--fill-holes`` did (``slicelab.repair``
        when its check finds something to mend, or to close holes): the part the G-code was made of.
    bed : (float, float), optional
        Bed size (mm); else the header's ``bed_size`` or ``bed_shape``.
    max_height, retract_travel : float, optional
        Else the header's ``max_height`` / ``max_print_height`` and ``retract_min_travel`` /
        ``retract_before_travel``.
    offset : (3,) float, optional
        Mesh + offset = bed coordinates; else the header's ``slicelab offset``.
    tolerance : float, default 0.02
        Slack (mm) on the widened section: the file's 3-decimal rounding, path simplification.
    first_layer_tolerance : float, default 0.01
    worst : int, default 10
        Offenders kept per check.

    Returns
    -------
    Report

    Raises
    ------
    GcodeInputError
        The file is not G-code text, the mesh cannot be loaded, or a tolerance is negative.
    """
    t0 = time.perf_counter()
    path = Path(gcode_path)
    if not (tolerance >= 0 and first_layer_tolerance >= 0):
        raise GcodeInputError(f"tolerances must be >= 0 mm, got {tolerance!r} and {first_layer_tolerance!r}")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise GcodeInputError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if b"\0" in data[:65536] or not data.strip():
        raise GcodeInputError(f"{path}: {'binary, not G-code text' if data.strip() else 'empty'}")
    # A mesh slicelab repaired on the way in says so in its header (`; repaired: ...`): the checker
    # mends its copy the same way, so that it checks against the part that was sliced.
    said = re.findall(rb"^; repaired: (.*)$", data[:65536], flags=re.M)
    repair = repair or bool(said)
    fill_holes = fill_holes or any(x.startswith(b"filled") for x in said)
    mesh = mesh_or_path
    if mesh is not None:
        import slicelab
        try:
            mesh = slicelab.load(mesh, units=units, scale=scale) if isinstance(mesh, (str, Path)) else mesh
        except (OSError, ValueError) as exc:
            raise GcodeInputError(str(exc).splitlines()[0]) from None
        if fill_holes or (repair and slicelab.check(mesh).needs_repair):
            mesh = slicelab.repair(mesh, fill_holes=fill_holes).mesh
    lines = data.decode("utf-8", errors="replace").splitlines()
    g = _parse(lines)
    s = _settings(g["header"], bed, max_height, offset, retract_travel)
    moving = ~np.all(g["start"][:, :2] == g["end"][:, :2], axis=1)  # from an unknown (NaN) start too
    ext = (g["e"] > 0) & moving
    bottom = 0.0 if mesh is None or s["offset"] is None else float(mesh.bounds[0][2] + s["offset"][2])
    layers = _layer_planes(g, ext, bottom)
    line = g["line"]
    checks = [_check("syntax", g["live"], [b[0] for b in g["bad"]], np.zeros(len(g["bad"])),
                     lambda i: g["bad"][i][1], "live lines", worst), _heaters(g, g["e"] > 0, worst)]
    z = g["end"][ext, 2]
    drop = np.concatenate([[-np.inf], np.fmax.accumulate(z)[:-1]]) - z  # below the highest layer so far
    down = np.flatnonzero(drop > 1e-4)
    checks.append(_check("z_order", len(z), line[ext][down], drop[down],
                         lambda i: f"extrudes at z {z[down[i]]:.3f}, {drop[down[i]]:.3f} mm below an earlier layer",
                         worst=worst))
    if not ext.any():
        checks.append(Check("first_layer", "fail", 0, 1, ((0, 0.0, "the file extrudes nothing"),)))
    elif s["first_layer_height"] is None:
        checks.append(Check("first_layer", "skip", detail="first_layer_height unknown"))
    else:  # the extrusions of the first layer that holds any (not a purge line before the first layer)
        ids = layers[0][ext]
        first = ids == (ids[ids >= 0][0] if (ids >= 0).any() else ids[0])
        # A part sunk into the bed (slicelab lowers one that touches it at a point) starts at the bed.
        want = max(bottom, 0.0) + s["first_layer_height"]
        off_by = np.abs(z[first] - want)
        bad = np.flatnonzero(off_by > first_layer_tolerance)
        checks.append(_check("first_layer", first.sum(), line[ext][first][bad], off_by[bad],
                             lambda i: f"first layer at z {z[first][bad[i]]:.3f}, not {want:.3f}",
                             f"expected z {want:.3f}", worst))
    checks += [_inside(g, ext, layers, s, mesh, tolerance, worst), _on_bed(g, moving, s, worst),
               _retraction(g, ext, moving, s, worst)]
    return Report(str(path), tuple(checks), round(time.perf_counter() - t0, 3), len(lines),
                  len(np.unique(layers[0][ext])))


def _numbers(text: str, sep: str, k: int) -> tuple:
    """`k` finite numbers separated by `sep` (an option's value)."""
    try:
        out = tuple(float(v) for v in text.lower().split(sep))
    except ValueError:
        out = ()
    if len(out) != k or not all(np.isfinite(out)):
        raise GcodeInputError(f"expected {k} numbers separated by {sep!r}, got {text!r}")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("gcode")
    ap.add_argument("--mesh", help="the part (STL, PLY, OBJ) for inside_part and first_layer")
    ap.add_argument("--units", help="the mesh file's units, as slicelab slice --units")
    ap.add_argument("--scale", type=float, help="the mesh's scale, as slicelab slice --scale")
    ap.add_argument("--repair", action="store_true", help="mend the mesh first, as slicelab slice did")
    ap.add_argument("--fill-holes", action="store_true", help="close its holes first, as slicelab slice did")
    ap.add_argument("--bed", help="bed size WxD (mm), e.g. 250x210")
    ap.add_argument("--max-height", type=float)
    ap.add_argument("--offset", help="mesh + offset = bed coordinates: DX,DY,DZ")
    ap.add_argument("--retract-travel", type=float, help="travels longer than this (mm) must be retracted")
    ap.add_argument("--tolerance", type=float, default=0.02, help="slack on the widened section (mm)")
    ap.add_argument("--worst", type=int, default=10, help="offenders listed per check")
    ap.add_argument("--json", action="store_true", help="the report as JSON on stdout")
    a = ap.parse_args(argv)
    try:
        r = check_gcode(a.gcode, a.mesh, bed=None if a.bed is None else _numbers(a.bed, "x", 2),
                        max_height=a.max_height, offset=None if a.offset is None else _numbers(a.offset, ",", 3),
                        retract_travel=a.retract_travel, tolerance=a.tolerance, worst=a.worst, units=a.units,
                        scale=a.scale, repair=a.repair, fill_holes=a.fill_holes)
    except GcodeInputError as exc:
        print(f"check_gcode: {exc}", file=sys.stderr)
        return 2
    text = [json.dumps(r.to_dict(), indent=1)] if a.json else \
        [f"{r.path}: {r.n_lines} lines, {r.n_layers} layers, checked in {r.seconds:.2f} s"]
    for c in () if a.json else r.checks:
        what = f"{c.failed} of {c.checked} fail" if c.status == "fail" else f"{c.checked} checked"
        text += [f"  {c.status.upper():4} {c.name:12} {what}" + (f"; {c.detail}" if c.detail else "")]
        text += [f"       line {no}: {msg}" for no, _, msg in c.worst]
    try:
        print("\n".join(text), flush=True)
    except BrokenPipeError:  # the reader left (``| head``): the verdict stands
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0 if r.passed else 1


if __name__ == "__main__":
    sys.exit(main())
