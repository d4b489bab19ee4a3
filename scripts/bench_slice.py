"""Whole-part slicing to G-code: slicelab against PrusaSlicer on a broad set of real parts.

The broad set (the default, `BROAD`): 27 files from ``../shared/meshes`` and ``data/``, none
tuned for: PrusaSlicer's own test parts (a bridge, overhangs, an extruder idler, a 2 mm relief),
3-D scans (Beethoven, Nefertiti's 100k facets, a skull, the Utah teapot and two sub-millimetre
scans), CAD files from trimesh's and assimp's test models (a tray bottom, a counter of 84k
facets, plates with holes, a torus, parts drawn in inches), Thingi10K files with defects
(several bodies, open edges) and the project's pot and mushroom (sliced with supports on both
sides: `PRUSA_SUPPORT`). Each runs at its own size when that is 10-250 mm, and scaled to a size
between 100 and 180 mm (its largest side; the size drawn from its name, the same every run),
as a user would print it. ``--set bench`` runs instead the seven parts this project tuned
its planner on (`BENCH`; two need `make data-large`). A missing file is skipped with a note.
`--mesh` (repeatable) runs other files, with supports given `--support`; `--only` keeps the
runs whose label holds a word; `--prusa-arg` hands PrusaSlicer a further argument,
`--slicelab-arg` slicelab.

Same settings on both sides: 0.2 mm layers (first layer too), 0.4 mm lines everywhere, two
perimeters, 20% rectilinear infill, 3 top and 3 bottom solid layers, no skirt, no minimum shell
thickness (PrusaSlicer would otherwise add a fourth top layer), the same speeds, acceleration
and jerk. slicelab runs with its defaults otherwise (0.2 mm pixels, all cores, repair of what is
safe to repair) and a bed large enough for every part. Each tool runs as a command-line
subprocess from a cold start (load, slice, write G-code), the two tools taking turns `--repeat`
times (medians compared), after one untimed slicelab run that leaves its compiled kernels and
bytecode on disk as a user's first run does. Per run: wall time and ratio, peak memory (the
summed resident size of the process tree, sampled every 20 ms), G-code bytes, the share of
extrusion moves under 0.1 mm, filament, the print time each file announces, and the length each
tool extrudes under each ``;TYPE:`` word. The summary table ends with the geometric mean of
the time ratios and each target of issue #37 checked: geometric mean <= 1.0; no part above
2.0x where PrusaSlicer takes 1 s or more, nor more than 0.3 s above it where it takes less;
solid plus top-solid infill within 30 % of PrusaSlicer's; filament within 10 %; estimate
within 15 %; G-code <= 1.3x; moves under 0.1 mm <= 5 %. The floor of any Python slicer's wall
time here is printed apart: a process that imports the libraries a slice needs and does
nothing else. PrusaSlicer is Debian's `prusa-slicer` (`apt-get install -y prusa-slicer`); the
comparison is skipped with a note when it is absent. Cost: about 10 minutes per repeat for the
broad set on 2 cores. ``--preview`` has slicelab draw its previews too.

    python scripts/bench_slice.py [--set broad|bench] [--only WORD] [--mesh FILE ...] [--repeat 1]
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import benchlib  # noqa: E402

LAYER, WIDTH, PERIMETERS, INFILL, SOLID = 0.2, 0.4, 2, 20, 3


def _tree_rss_kb(pid: int) -> int:
    """Resident memory of a process and all its descendants (kB), from /proc."""
    total = 0
    kids = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open(f"/proc/{d}/stat") as fh:
                ppid = int(fh.read().rsplit(")", 1)[1].split()[1])
            kids.setdefault(ppid, []).append(int(d))
        except (OSError, ValueError, IndexError):
            pass
    todo = [pid]
    while todo:
        p = todo.pop()
        todo += kids.get(p, [])
        try:
            with open(f"/proc/{p}/status") as fh:
                for line in fh:
                    if line.startswith("VmRSS:"):
                        total += int(line.split()[1])
        except OSError:
            pass
    return total


#: The commands run as on a user's machine, where an install leaves compiled bytecode beside the
#: modules: a shell that forbids writing it (PYTHONDONTWRITEBYTECODE) would have every run compile
#: slicelab's modules again.
_ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def run(cmd: list[str]) -> tuple[float, float, subprocess.CompletedProcess]:
    """Wall time (s) and peak tree memory (MB) of a command."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT, env=_ENV)
    peak = [0]

    def sample():
        while proc.poll() is None:
            peak[0] = max(peak[0], _tree_rss_kb(proc.pid))
            time.sleep(0.02)

    th = threading.Thread(target=sample, daemon=True)
    th.start()
    out, err = proc.communicate()
    wall = time.perf_counter() - t0
    th.join()
    return wall, peak[0] / 1024, subprocess.CompletedProcess(cmd, proc.returncode, out, err)


def extruded_filament(gcode: Path) -> float:
    """Filament (mm) pushed by moves that extrude while moving in X or Y (relative or absolute E)."""
    total, relative, e_abs = 0.0, False, 0.0
    move = re.compile(r"^G[01]\s")
    for line in gcode.open():
        code = line.split(";")[0].strip()
        if code.startswith("M83"):
            relative = True
        elif code.startswith("M82"):
            relative = False
        elif code.startswith("G92"):
            for tok in code.split()[1:]:
                if tok[0] == "E":
                    e_abs = float(tok[1:])
        elif move.match(code) and "E" in code:
            args = {t[0]: float(t[1:]) for t in code.split()[1:] if len(t) > 1}
            e = args["E"] if relative else args["E"] - e_abs
            if not relative:
                e_abs = args["E"]
            if ("X" in args or "Y" in args) and e > 0:
                total += e
    return total


def gcode_stats(path: Path, roles: dict | None = None):
    """Bytes, extrusion moves, their median length (mm) and the share under 0.1 mm, parsed from the file;
    `roles`, if given, gets the extruded length (mm) under each ``;TYPE:`` word."""
    import numpy as np
    text = path.read_text()
    x = y = 0.0
    lengths = []
    role = None
    for line in text.splitlines():  # every move, to follow the nozzle
        if line.startswith(";TYPE:"):
            role = line[6:].strip()
            continue
        if not (line.startswith("G1 ") or line.startswith("G0 ")):
            continue
        words = dict((w[0], w[1:]) for w in line.split(";")[0].split()[1:] if w)
        nx, ny = float(words.get("X", x)), float(words.get("Y", y))
        if float(words.get("E", 0) or 0) > 0 and ("X" in words or "Y" in words):
            lengths.append(float(np.hypot(nx - x, ny - y)))
            if roles is not None:
                roles[role] = roles.get(role, 0.0) + lengths[-1]
        x, y = nx, ny
    lengths = np.asarray(lengths) if lengths else np.zeros(1)
    return len(text.encode()), len(lengths), float(np.median(lengths)), float(np.mean(lengths < 0.1))


def estimated_seconds(path: Path) -> float:
    """The print time a G-code file announces (PrusaSlicer's comment, which slicelab writes too)."""
    found = re.findall(r"; estimated printing time \(normal mode\) = (.*)", path.read_text()[-20000:])
    if not found:
        return float("nan")
    units = {"d": 86400, "h": 3600, "m": 60, "s": 1}
    return float(sum(int(v) * units[u] for v, u in re.findall(r"(\d+)([dhms])", found[-1])))


#: Speeds (mm/s), acceleration and jerk given to both tools, so that their print-time estimates
#: compare: slicelab's defaults, spelled out for PrusaSlicer (its estimate also uses its machine
#: limits, 1500 mm/s2 by default).
SPEEDS = dict(perimeter=40, external_perimeter=25, infill=80, solid_infill=60, top_solid_infill=40, gap_fill=20,
              bridge=25, travel=150, first_layer=20)
SAME_SPEEDS = ["--acceleration", "1500", "--jerk", "10"]  # slicelab's speeds are the defaults above
PRUSA_SPEEDS = [w for k, v in SPEEDS.items() for w in (f"--{k.replace('_', '-')}-speed", str(v))] + \
    ["--support-material-speed", "50"]

#: slicelab's support settings, spelled out for PrusaSlicer where its own defaults differ: an
#: overhang threshold of 50 degrees from the vertical (PrusaSlicer measures its slope from the
#: horizontal: 40), two interface layers with 0.2 mm gaps (its defaults: three, solid), a 0.6 mm
#: gap to the part beside. Both leave one layer (0.2 mm) under the part, lines with 2.5 mm gaps,
#: a loop around each region, and bridges unsupported but for the band along their outline.
PRUSA_SUPPORT = ["--support-material", "--support-material-threshold", "40",
                 "--support-material-interface-layers", "2", "--support-material-interface-spacing", "0.2",
                 "--support-material-xy-spacing", "0.6"]

#: (label, file, largest size to scale to or None, supports on both sides): the parts the planner
#: was tuned on.
BENCH = (("pot", ROOT / "data" / "pot.stl", None, False),
         ("block 96 mm", ROOT / "data" / "large" / "block_100.stl", None, False),
         ("teapot 120 mm", ROOT.parent / "shared" / "meshes" / "scans" / "utah_teapot.stl", 120.0, False),
         ("torus 1M", ROOT / "data" / "large" / "torus_1m.stl", None, False),
         ("tray 180 mm", ROOT / "data" / "tray.stl", None, False),
         ("bridge 40 mm", ROOT / "data" / "bridge.stl", None, False),
         ("mushroom supp.", ROOT / "data" / "mushroom.stl", None, True))
PARTS = BENCH  # (the name `scripts/bench_revisions.py` reads)

SHARED = ROOT.parent / "shared" / "meshes"
#: The broad set: (label, file, supports on both sides). See the module's docstring.
BROAD_FILES = (
    ("A", SHARED / "prusaslicer" / "A.stl", False), ("U overhang", SHARED / "prusaslicer" / "U_overhang.stl", False),
    ("bridge", SHARED / "prusaslicer" / "bridge.stl", False),
    ("extruder idler", SHARED / "prusaslicer" / "extruder_idler.stl", False),
    ("frog legs", SHARED / "prusaslicer" / "frog_legs.stl", False),
    ("overhang", SHARED / "prusaslicer" / "overhang.stl", False),
    ("beethoven", SHARED / "scans" / "beethoven.stl", False), ("nefertiti", SHARED / "scans" / "nefertiti.stl", False),
    ("skull", SHARED / "scans" / "skull.stl", False), ("utah teapot", SHARED / "scans" / "utah_teapot.stl", False),
    ("demosthenes", SHARED / "scans" / "demosthenes-low-res.stl", False),
    ("lion statue", SHARED / "scans" / "lionstatue.stl", False),
    ("tray bottom", SHARED / "trimesh" / "models" / "1002_tray_bottom.STL", False),
    ("xyz cube", SHARED / "trimesh" / "models" / "20mm-xyz-cube.stl", False),
    ("busted", SHARED / "trimesh" / "models" / "busted.STL", False),
    ("counter", SHARED / "trimesh" / "models" / "counter.unitsmm.STL", False),
    ("plate holes", SHARED / "trimesh" / "models" / "plate_holes.STL", False),
    ("round", SHARED / "trimesh" / "models" / "round.stl", False),
    ("teapot (trimesh)", SHARED / "trimesh" / "models" / "teapot.stl", False),
    ("torus", SHARED / "trimesh" / "models" / "torus.STL", False),
    ("feature type", SHARED / "trimesh" / "models" / "featuretype.STL", False),
    ("idler riser", SHARED / "trimesh" / "models" / "idler_riser.STL", False),
    ("3ds max export", SHARED / "assimp" / "test" / "models" / "STL" / "3DSMaxExport.STL", False),
    ("two bodies", SHARED / "defects" / "multiple_components" / "85770.stl", False),
    ("open bracket", SHARED / "defects" / "complex" / "73335.stl", False),
    ("pot", ROOT / "data" / "pot.stl", False), ("mushroom", ROOT / "data" / "mushroom.stl", True))


def broad_set() -> list:
    """The runs of the broad set: each file at its own size (when 10-250 mm) and scaled to a size
    of 100-180 mm drawn from its label (the same every run)."""
    import zlib
    import slicelab
    out = []
    for label, path, support in BROAD_FILES:
        if not path.exists():
            out.append((label, path, None, support))  # (reported missing)
            continue
        lo, hi = slicelab.load(path).bounds
        size = float(max(hi - lo))
        if 10.0 <= size <= 250.0:
            out.append((f"{label} {size:.0f}", path, None, support))
        target = 100.0 + zlib.crc32(label.encode()) % 81
        out.append((f"{label} @{target:.0f}", path, target, support))
    return out


def bench_part(label: str, mesh: Path, scale: float | None, args, prusa: str | None,
               support: bool = False) -> dict | None:
    """Both tools on one part, alternating; prints the part's tables and returns its summary row."""
    tmp = Path(tempfile.mkdtemp(prefix="bench_slice_"))
    ours = tmp / "slicelab.gcode"
    factor = []
    if scale is not None:  # to `scale` mm across (largest side), on both sides
        import slicelab
        lo, hi = slicelab.load(mesh).bounds
        factor = [f"{scale / float(max(hi - lo)):.6f}"]
    cmd = [sys.executable, "-m", "slicelab", "slice", str(mesh), "-o", str(ours), "--layer-height", str(LAYER),
           "--line-width", str(WIDTH), "--perimeters", str(PERIMETERS), "--infill-density", str(INFILL),
           "--top-layers", str(SOLID), "--bottom-layers", str(SOLID),
           "--skirt-loops", "0", "--bed-size", "1000x1000", "--max-height", "1000"] + SAME_SPEEDS
    cmd += ["--scale", factor[0]] if factor else []
    cmd += ["--support", "auto"] if support else []
    if args.pixel_size:
        cmd += ["--pixel-size", str(args.pixel_size)]
    if args.workers:
        cmd += ["--workers", str(args.workers)]
    if args.preview:
        cmd += ["--preview", str(tmp / "preview")]
    cmd += list(args.slicelab_arg)
    print(f"\n=== {label}: {mesh.name}" + (f" x {factor[0]}" if factor else ""))
    theirs = tmp / "prusa.gcode"
    pcmd = [prusa, "--export-gcode", "--layer-height", str(LAYER), "--first-layer-height", str(LAYER),
            "--perimeters", str(PERIMETERS), "--fill-density", f"{INFILL}%", "--fill-pattern", "rectilinear",
            "--top-solid-layers", str(SOLID), "--bottom-solid-layers", str(SOLID),
            "--top-solid-min-thickness", "0", "--bottom-solid-min-thickness", "0",
            "--extrusion-width", str(WIDTH), "--first-layer-extrusion-width", str(WIDTH),
            "--skirts", "0", *PRUSA_SPEEDS, "--bed-shape", "0x0,1000x0,1000x1000,0x1000", "--center", "500,500",
            "--max-print-height", "1000", "-o", str(theirs)] + (["--scale", factor[0]] if factor else []) \
        + (PRUSA_SUPPORT if support else []) + list(args.prusa_arg) + [str(mesh)]
    runs = {"slicelab": [], "PrusaSlicer": []}
    for _ in range(args.repeat):  # alternating, so both tools see the same machine load
        t, m, r = run(cmd)
        if r.returncode == 2 and "--fill-holes" in r.stderr and "--fill-holes" not in cmd:
            # Refused (an open scan): run again with the fix the refusal names, as a user would.
            print(f"refused: {r.stderr.strip()[-300:]}\nrun again with --fill-holes")
            cmd.append("--fill-holes")
            t, m, r = run(cmd)
        if r.returncode:
            print(r.stderr[-3000:])
            return None
        runs["slicelab"].append((t, m))
        if prusa is not None:
            t, m, rp = run(pcmd)
            if rp.returncode or not theirs.exists():
                print("prusa-slicer failed:", (rp.stderr or rp.stdout)[-2000:])
                prusa = None
            else:
                runs["PrusaSlicer"].append((t, m))
    print(r.stdout.strip())
    filament = {"slicelab": extruded_filament(ours)}
    roles = {"slicelab": {}, "PrusaSlicer": {}}
    stats = {"slicelab": gcode_stats(ours, roles["slicelab"])}
    estimate = {"slicelab": estimated_seconds(ours)}
    if runs["PrusaSlicer"]:
        filament["PrusaSlicer"] = extruded_filament(theirs)
        stats["PrusaSlicer"] = gcode_stats(theirs, roles["PrusaSlicer"])
        estimate["PrusaSlicer"] = estimated_seconds(theirs)
    print(f"{'extruded (m) by ;TYPE:':<28}{'slicelab':>10}{'Prusa':>10}")
    for word in sorted(set(roles["slicelab"]) | set(roles["PrusaSlicer"]), key=str):
        print(f"{str(word):<28}{roles['slicelab'].get(word, 0) / 1000:>10.2f}"
              f"{roles['PrusaSlicer'].get(word, 0) / 1000:>10.2f}")
    print("estimated print time: " + ", ".join(f"{k} {v / 60:.1f} min" for k, v in estimate.items()))
    print(f"{'tool':<12}{'G-code MB':>10}{'extrusions':>12}{'median mm':>11}{'< 0.1 mm':>10}")
    for name, (size, n, median, short) in stats.items():
        print(f"{name:<12}{size / 1e6:>10.2f}{n:>12,d}{median:>11.3f}{100 * short:>9.1f}%")
    print(f"{'tool':<12}{'wall s':>9}{'peak MB':>10}{'filament mm':>13}   runs (s)")
    med = {}
    for name, rs in runs.items():
        if rs:
            med[name] = (statistics.median(t for t, _ in rs), max(m for _, m in rs))
            print(f"{name:<12}{med[name][0]:>9.2f}{med[name][1]:>10.0f}{filament[name]:>13.0f}   "
                  + " ".join(f"{t:.2f}" for t, _ in rs))
    shutil.rmtree(tmp, ignore_errors=True)
    row = {"part": label, "ours_s": med["slicelab"][0], "ours_mb": med["slicelab"][1],
           "short": stats["slicelab"][3], "estimate": estimate, "roles": roles}
    if "PrusaSlicer" in med:
        row.update(theirs_s=med["PrusaSlicer"][0], theirs_mb=med["PrusaSlicer"][1],
                   bytes=stats["slicelab"][0] / stats["PrusaSlicer"][0],
                   filament=filament["slicelab"] / filament["PrusaSlicer"])
    return row


#: What every `slicelab slice` imports before it reads a file: the floor of its wall time.
FLOOR = "import numpy, cv2, shapely"
#: Libraries a slice no longer imports, and what each would add to the floor (the reason it does not).
AVOIDED = (("numpy-stl", "import stl.mesh"), ("SciPy's sparse graphs", "import scipy.sparse.csgraph"),
           ("scikit-image's morphology (and SciPy's)", "from skimage.morphology import skeletonize"))


SOLID_ROLES = ("Solid infill", "Top solid infill")


def summary(rows: list, floor: float) -> None:
    """The table of every run, the geometric mean of the time ratios and each target checked."""
    import math
    print(f"\n{'part':<24}{'ours s':>7}{'Prusa s':>8}{'ratio':>7}{'peak MB':>8}{'G-code':>8}{'<0.1mm':>7}"
          f"{'filament':>9}{'estimate':>9}{'solid+top':>10}")
    compared = [r for r in rows if "theirs_s" in r]
    for r in rows:
        if "theirs_s" not in r:
            print(f"{r['part']:<24}{r['ours_s']:>7.2f}{'-':>8}{'-':>7}{r['ours_mb']:>8.0f}{'-':>8}"
                  f"{100 * r['short']:>6.1f}%")
            continue
        ours, theirs = (sum(r["roles"][k].get(w, 0.0) for w in SOLID_ROLES) for k in ("slicelab", "PrusaSlicer"))
        r["solid"] = ours / theirs if theirs > 0 else float("nan")
        est = r["estimate"]["slicelab"] / r["estimate"]["PrusaSlicer"]
        print(f"{r['part']:<24}{r['ours_s']:>7.2f}{r['theirs_s']:>8.2f}{r['ours_s'] / r['theirs_s']:>6.2f}x"
              f"{r['ours_mb']:>8.0f}{r['bytes']:>7.2f}x{100 * r['short']:>6.1f}%{100 * (r['filament'] - 1):>+8.1f}%"
              f"{100 * (est - 1):>+8.1f}%{100 * (r['solid'] - 1):>+9.0f}%")
    print(f"floor: {floor:.2f} s before any work (the libraries' imports), in every slicelab run above")
    if not compared:
        return
    ratios = [r["ours_s"] / r["theirs_s"] for r in compared]
    print(f"geometric mean of the time ratios over {len(compared)} runs: "
          f"{math.exp(sum(map(math.log, ratios)) / len(ratios)):.2f}x (target <= 1.0, aim 0.5)")

    def missed(name, bad):
        print(f"  {name}: " + ("met" if not bad else f"missed by {len(bad)}: " + ", ".join(bad)))
    print("targets (issue #37):")
    missed("no part above 2.0x where PrusaSlicer takes >= 1 s",
           [r["part"] for r in compared if r["theirs_s"] >= 1 and r["ours_s"] > 2 * r["theirs_s"]])
    missed("no part more than 0.3 s above PrusaSlicer where it takes < 1 s",
           [r["part"] for r in compared if r["theirs_s"] < 1 and r["ours_s"] > r["theirs_s"] + 0.3])
    missed("solid + top-solid infill within 30 %",
           [f"{r['part']} ({100 * (r['solid'] - 1):+.0f}%)" for r in compared if abs(r["solid"] - 1) > 0.3])
    missed("filament within 10 %", [r["part"] for r in compared if abs(r["filament"] - 1) > 0.1])
    missed("print-time estimate within 15 %",
           [r["part"] for r in compared if abs(r["estimate"]["slicelab"] / r["estimate"]["PrusaSlicer"] - 1) > 0.15])
    missed("G-code <= 1.3x", [r["part"] for r in compared if r["bytes"] > 1.3])
    missed("moves under 0.1 mm <= 5 %", [r["part"] for r in rows if r["short"] > 0.05])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", type=Path, action="append", help="a part to run instead of the set (repeatable)")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--pixel-size", type=float, default=None, help="default: slicelab's own")
    ap.add_argument("--repeat", type=int, default=1, help="alternating runs per tool (median wall time)")
    ap.add_argument("--preview", action="store_true", help="slicelab draws its previews too (--preview DIR)")
    ap.add_argument("--support", action="store_true", help="the --mesh parts with supports on both sides")
    ap.add_argument("--slicelab-arg", action="append", default=[], metavar="ARG",
                    help="a further argument for slicelab slice (repeatable; --slicelab-arg=--repair for a flag)")
    ap.add_argument("--prusa-arg", action="append", default=[], metavar="ARG",
                    help="a further argument for PrusaSlicer (repeatable; --prusa-arg=--flag for a flag), "
                         "to see where a difference comes from")
    ap.add_argument("--set", choices=("broad", "bench"), default="broad",
                    help="the broad set of real parts (default) or the seven the planner was tuned on")
    ap.add_argument("--only", action="append", default=[], metavar="WORD",
                    help="keep the runs whose label holds this word (repeatable)")
    ap.add_argument("--docs", action="store_true",
                    help="also write what is printed, with the machine and date, for the docs' performance pages")
    args = ap.parse_args(argv)
    if args.mesh:
        parts = [(m.name, m, None, args.support) for m in args.mesh]
    else:
        parts = broad_set() if args.set == "broad" else list(BENCH)
    if args.only:
        parts = [q for q in parts if any(w.lower() in q[0].lower() for w in args.only)]
    prusa = shutil.which("prusa-slicer") or shutil.which("prusaslicer")
    print(f"{LAYER} mm layers, {WIDTH} mm lines, {PERIMETERS} perimeters, {INFILL}% infill, {SOLID} top/bottom "
          f"layers; {os.cpu_count()} cores, shared machine (noisy timings); {args.repeat} alternating run(s) "
          f"per tool, medians compared" + ("; slicelab draws its previews too (--preview), PrusaSlicer writes "
                                           "G-code only" if args.preview else ""))
    if prusa is None:
        print("prusa-slicer is not installed (apt-get install -y prusa-slicer): no comparison")
    # One untimed run first, as a user's first run after installing: it writes the modules' bytecode
    # (and, where `make` did not build the kernels, numba's disk cache), which every later run loads.
    with tempfile.TemporaryDirectory() as tmp:
        run([sys.executable, "-m", "slicelab", "slice", str(ROOT / "data" / "bridge.stl"), "-o",
             str(Path(tmp) / "warm.gcode")])
    floor = statistics.median(run([sys.executable, "-c", FLOOR])[0] for _ in range(5))
    print(f"floor: a Python process importing the libraries a slice needs (numpy, OpenCV, shapely), "
          f"nothing else: {floor:.2f} s (median of 5)")
    for name, statement in AVOIDED:  # (imports a slice does without: what each would cost it)
        t = statistics.median(run([sys.executable, "-c", f"{FLOOR}; {statement}"])[0] for _ in range(5))
        print(f"  not imported by a slice: {name}, which would add {t - floor:.2f} s (median of 5)")
    rows, failed = [], []
    for label, mesh, scale, support in parts:
        if not mesh.exists():
            print(f"\n=== {label}: {mesh} is missing (`make data-large`, or ../shared/meshes): skipped")
            continue
        row = bench_part(label, mesh, scale, args, prusa, support)
        if row is None:  # (its message printed above)
            failed.append(label)
            continue
        rows.append(row)
    summary(rows, floor)
    if failed:
        print(f"slicelab failed on {len(failed)} run(s): " + ", ".join(failed))
        return 1
    return 0


if __name__ == "__main__":
    with benchlib.docs_output("bench_slice", "--docs" in sys.argv[1:]):
        raise SystemExit(main())
