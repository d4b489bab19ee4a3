"""Whole-part slicing to G-code: slicelab against PrusaSlicer, on a part of real size or the 1M torus.

Same settings on both sides: 0.2 mm layers (first layer too), 0.4 mm lines everywhere, two
perimeters, 20% rectilinear infill, 3 top and 3 bottom solid layers, no skirt, no minimum shell
thickness (PrusaSlicer would otherwise add a fourth top layer). Each tool runs as a
command-line subprocess from a cold start (load, slice, write G-code), the two tools taking turns
`--repeat` times (3 by default; the medians are compared); wall time, peak memory (the
summed resident size of the process and its children, sampled every 20 ms) and the filament each
G-code extrudes are printed, with the ratios, and the G-code itself: bytes, extrusion moves, the
median extrusion move and the share of extrusion moves under 0.1 mm (a printer's planner stutters
on streams of tiny moves). Cost: linear in the layers; a layer's cost follows its boundary. slicelab runs at its default 0.05 mm pixel on all
cores. PrusaSlicer is Debian's `prusa-slicer` (`apt-get install -y prusa-slicer`); the comparison is
skipped with a note when it is absent. The machine is shared, so timings are noisy.

    python scripts/bench_slice.py [--mesh data/pot.stl] [--workers N] [--repeat 3]
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


def run(cmd: list[str]) -> tuple[float, float, subprocess.CompletedProcess]:
    """Wall time (s) and peak tree memory (MB) of a command."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
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


def gcode_stats(path: Path):
    """Bytes, extrusion moves, their median length (mm) and the share under 0.1 mm, parsed from the file."""
    import numpy as np
    text = path.read_text()
    x = y = 0.0
    lengths = []
    for line in text.splitlines():  # every move, to follow the nozzle
        if not (line.startswith("G1 ") or line.startswith("G0 ")):
            continue
        words = dict((w[0], w[1:]) for w in line.split(";")[0].split()[1:] if w)
        nx, ny = float(words.get("X", x)), float(words.get("Y", y))
        if float(words.get("E", 0) or 0) > 0 and ("X" in words or "Y" in words):
            lengths.append(float(np.hypot(nx - x, ny - y)))
        x, y = nx, ny
    lengths = np.asarray(lengths) if lengths else np.zeros(1)
    return len(text.encode()), len(lengths), float(np.median(lengths)), float(np.mean(lengths < 0.1))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", type=Path, default=ROOT / "data" / "large" / "torus_1m.stl")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--pixel-size", type=float, default=0.05)
    ap.add_argument("--repeat", type=int, default=3, help="alternating runs per tool (median wall time)")
    args = ap.parse_args(argv)
    if not args.mesh.exists():
        print(f"{args.mesh} is missing: run `make data-large`")
        return 1
    tmp = Path(tempfile.mkdtemp(prefix="bench_slice_"))
    ours = tmp / "slicelab.gcode"
    cmd = [sys.executable, "-m", "slicelab", "slice", str(args.mesh), "-o", str(ours), "--layer-height", str(LAYER),
           "--line-width", str(WIDTH), "--perimeters", str(PERIMETERS), "--infill-density", str(INFILL),
           "--top-layers", str(SOLID), "--bottom-layers", str(SOLID), "--pixel-size", str(args.pixel_size),
           "--skirt-loops", "0", "--bed-size", "1000x1000", "--max-height", "1000"]
    if args.workers:
        cmd += ["--workers", str(args.workers)]
    print(f"{args.mesh.name}: {LAYER} mm layers, {WIDTH} mm lines, {PERIMETERS} perimeters, {INFILL}% infill, "
          f"{SOLID} top/bottom layers; {os.cpu_count()} cores, shared machine (noisy timings); "
          f"{args.repeat} alternating run(s) per tool, medians compared")
    prusa = shutil.which("prusa-slicer") or shutil.which("prusaslicer")
    if prusa is None:
        print("prusa-slicer is not installed (apt-get install -y prusa-slicer): no comparison")
    theirs = tmp / "prusa.gcode"
    pcmd = [prusa, "--export-gcode", "--layer-height", str(LAYER), "--first-layer-height", str(LAYER),
            "--perimeters", str(PERIMETERS), "--fill-density", f"{INFILL}%", "--fill-pattern", "rectilinear",
            "--top-solid-layers", str(SOLID), "--bottom-solid-layers", str(SOLID),
            "--top-solid-min-thickness", "0", "--bottom-solid-min-thickness", "0",
            "--extrusion-width", str(WIDTH), "--first-layer-extrusion-width", str(WIDTH),
            "--skirts", "0", "-o", str(theirs), str(args.mesh)]
    runs = {"slicelab": [], "PrusaSlicer": []}
    for _ in range(args.repeat):  # alternating, so both tools see the same machine load
        t, m, r = run(cmd)
        if r.returncode:
            print(r.stderr[-3000:])
            return 1
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
    stats = {"slicelab": gcode_stats(ours)}
    if runs["PrusaSlicer"]:
        filament["PrusaSlicer"] = extruded_filament(theirs)
        stats["PrusaSlicer"] = gcode_stats(theirs)
    print(f"\n{'tool':<12}{'G-code MB':>10}{'extrusions':>12}{'median mm':>11}{'< 0.1 mm':>10}")
    for name, (size, n, median, short) in stats.items():
        print(f"{name:<12}{size / 1e6:>10.2f}{n:>12,d}{median:>11.3f}{100 * short:>9.1f}%")
    if len(stats) == 2:
        b = stats["slicelab"][0] / stats["PrusaSlicer"][0]
        print(f"target: G-code <= 1.3x PrusaSlicer's size: {b:.2f}x  {'PASS' if b <= 1.3 else 'MISS'}; "
              f"<= 5 % of extrusion moves under 0.1 mm: {100 * stats['slicelab'][3]:.1f} %  "
              f"{'PASS' if stats['slicelab'][3] <= 0.05 else 'MISS'}")
    print(f"\n{'tool':<12}{'wall s':>9}{'peak MB':>10}{'filament mm':>13}   runs (s)")
    med = {}
    for name, rs in runs.items():
        if not rs:
            continue
        med[name] = (statistics.median(t for t, _ in rs), max(m for _, m in rs))
        print(f"{name:<12}{med[name][0]:>9.2f}{med[name][1]:>10.0f}{filament[name]:>13.0f}   "
              + " ".join(f"{t:.2f}" for t, _ in rs))
    if len(med) == 2:
        (t0, m0), (t1, m1) = med["slicelab"], med["PrusaSlicer"]
        f0, f1 = filament["slicelab"], filament["PrusaSlicer"]
        print(f"{'ratio':<12}{t0 / t1:>9.2f}{m0 / m1:>10.2f}{f0 / f1:>13.3f}   (slicelab / PrusaSlicer)")
        print(f"target: wall time <= PrusaSlicer's: {t0 / t1:.2f}x  {'PASS' if t0 <= t1 else 'MISS'}")
        print(f"target: filament within 10% of PrusaSlicer's: {100 * (f0 / f1 - 1):+.1f}%  "
              f"{'PASS' if abs(f0 / f1 - 1) <= 0.10 else 'MISS'}")
    shutil.rmtree(tmp, ignore_errors=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
