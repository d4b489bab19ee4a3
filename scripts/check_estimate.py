"""Check the print-time estimate against PrusaSlicer's: the same machine model on the same file.

For each part, PrusaSlicer slices it (``--machine-limits-usage emit_to_gcode``,
flavour marlin2, so that its file states M201/M203/M204/M205) and announces its
own estimate in the file (``; estimated printing time (normal mode) = ...``);
slicelab's estimator then reads that same file (`slicelab.gcode.reading`: its
moves, and the limits from its M-lines) and estimates it. The two numbers and
their ratio are the check (target: within 10 %). slicelab also slices the part
itself at the same settings, and its own estimate (the header's, and the same
file read back) is printed beside: a different toolpath, so only a rough match.

Same settings on both sides, as scripts/bench_slice.py gives them: 0.2 mm
layers, 0.4 mm lines, two perimeters, 20 % rectilinear infill, 3 top and 3
bottom layers, no skirt, slicelab's speeds spelled out for PrusaSlicer; a
250 x 210 mm bed, each part at its own size or scaled (largest side) to fit.
The machine limits are both tools' defaults (PrusaSlicer's). The parts: the
project's samples in data/ and a few real meshes from ../shared/meshes (each
skipped with a note when missing). PrusaSlicer is Debian's ``prusa-slicer``;
without it only slicelab's own numbers are printed.

    python scripts/check_estimate.py [--parts cube,bridge,...] [--keep DIR]
"""
from __future__ import annotations

import argparse
import math
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "meshes"

#: (name, file, largest side to scale to or None, slicelab's further arguments: the scans have holes,
#: which PrusaSlicer closes unasked)
PARTS = (("cube", ROOT / "data" / "cube_with_hole.stl", None, ()),
         ("bridge", ROOT / "data" / "bridge.stl", None, ()),
         ("mushroom", ROOT / "data" / "mushroom.stl", None, ()),
         ("tray", ROOT / "data" / "tray.stl", 150.0, ()),
         ("pot", ROOT / "data" / "pot.stl", None, ()),
         ("teapot", SHARED / "scans" / "utah_teapot.stl", 80.0, ()),
         ("beethoven", SHARED / "scans" / "beethoven.stl", 70.0, ("--fill-holes",)),
         ("wuson", SHARED / "assimp" / "test" / "models" / "STL" / "Wuson.stl", 60.0, ("--fill-holes",)))

LAYER, WIDTH, PERIMETERS, INFILL, SOLID = 0.2, 0.4, 2, 20, 3
#: slicelab's default speeds (mm/s), spelled out for PrusaSlicer.
SPEEDS = dict(perimeter=40, external_perimeter=25, infill=80, solid_infill=60, top_solid_infill=40, gap_fill=20,
              bridge=25, travel=150, first_layer=20)
BED = (250.0, 210.0)

TARGET = 0.10


def _run(cmd: list) -> subprocess.CompletedProcess:
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=1800)


def slice_prusa(prusa: str, mesh: Path, factor: float | None, out: Path) -> str | None:
    """PrusaSlicer's G-code of the part (None, with its complaint printed, if it fails)."""
    speeds = [w for k, v in SPEEDS.items() for w in (f"--{k.replace('_', '-')}-speed", str(v))]
    cmd = [prusa, "--export-gcode", "--layer-height", LAYER, "--first-layer-height", LAYER,
           "--perimeters", PERIMETERS, "--fill-density", f"{INFILL}%", "--fill-pattern", "rectilinear",
           "--top-solid-layers", SOLID, "--bottom-solid-layers", SOLID, "--top-solid-min-thickness", "0",
           "--bottom-solid-min-thickness", "0", "--extrusion-width", WIDTH, "--first-layer-extrusion-width", WIDTH,
           "--skirts", "0", *speeds, "--bed-shape", f"0x0,{BED[0]:g}x0,{BED[0]:g}x{BED[1]:g},0x{BED[1]:g}",
           "--center", f"{BED[0] / 2:g},{BED[1] / 2:g}", "--machine-limits-usage", "emit_to_gcode",
           "--gcode-flavor", "marlin2", "-o", out] + (["--scale", f"{factor:.6f}"] if factor else []) + [mesh]
    r = _run(cmd)
    if r.returncode or not out.exists():
        print(f"  prusa-slicer failed: {(r.stderr or r.stdout).strip()[-500:]}")
        return None
    return out.read_text(encoding="utf-8", errors="replace")


def slice_ours(mesh: Path, factor: float | None, out: Path, more=()) -> str | None:
    """slicelab's G-code of the part (None, with its complaint printed, if it fails)."""
    cmd = [sys.executable, "-m", "slicelab", "slice", mesh, "-o", out, "--layer-height", LAYER,
           "--line-width", WIDTH, "--perimeters", PERIMETERS, "--infill-density", INFILL, "--top-layers", SOLID,
           "--bottom-layers", SOLID, "--skirt-loops", "0", "--bed-size", f"{BED[0]:g}x{BED[1]:g}"]
    cmd += (["--scale", f"{factor:.6f}"] if factor else []) + list(more)
    r = _run(cmd)
    if r.returncode or not out.exists():
        print(f"  slicelab failed: {(r.stderr or r.stdout).strip()[-500:]}")
        return None
    return out.read_text(encoding="utf-8")


def _hms(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "-"
    from slicelab.gcode.estimate import format_duration
    return format_duration(seconds)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    p.add_argument("--parts", default=",".join(part[0] for part in PARTS),
                   help="comma-separated part names (default: all): " + ", ".join(part[0] for part in PARTS))
    p.add_argument("--keep", type=Path, default=None, metavar="DIR", help="keep the G-code files in DIR")
    args = p.parse_args(argv)
    wanted = [w.strip() for w in args.parts.split(",") if w.strip()]
    unknown = sorted(set(wanted) - {part[0] for part in PARTS})
    if unknown:
        p.error(f"unknown parts: {', '.join(unknown)}")

    import slicelab
    from slicelab.gcode.reading import file_seconds, read_moves, stated_seconds

    prusa = shutil.which("prusa-slicer")
    print(f"{LAYER} mm layers, {WIDTH} mm lines, {PERIMETERS} perimeters, {INFILL}% infill; both tools' default "
          f"machine limits (PrusaSlicer's); PrusaSlicer: {prusa or 'not installed (its columns left empty)'}")
    folder = args.keep or Path(tempfile.mkdtemp(prefix="check_estimate_"))
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for name, mesh, size, more in PARTS:  # over parts: a few
        if name not in wanted:
            continue
        if not mesh.exists():
            print(f"{name}: {mesh} missing, skipped")
            continue
        factor = None
        if size is not None:
            lo, hi = slicelab.load(mesh).bounds
            factor = size / float(max(hi - lo))
        theirs_text = slice_prusa(prusa, mesh, factor, folder / f"{name}.prusa.gcode") if prusa else None
        ours_text = slice_ours(mesh, factor, folder / f"{name}.slicelab.gcode", more)
        prusa_says = stated_seconds(theirs_text) if theirs_text else math.nan
        ours_on_theirs = file_seconds(read_moves(theirs_text)) if theirs_text else math.nan
        header = stated_seconds(ours_text) if ours_text else math.nan
        read_back = file_seconds(read_moves(ours_text)) if ours_text else math.nan
        rows.append((name + (f" x{factor:.3g}" if factor else ""), prusa_says, ours_on_theirs, header, read_back))
    print(f"\n{'part':<18}{'PrusaSlicer':>13}{'ours, its file':>16}{'ratio':>8}{'ours, our file':>16}"
          f"{'read back':>12}{'vs Prusa':>10}")
    ratios = []
    for label, prusa_says, on_theirs, header, read_back in rows:
        ratio = on_theirs / prusa_says if prusa_says > 0 else math.nan
        if math.isfinite(ratio):
            ratios.append(ratio)
        versus = header / prusa_says if prusa_says > 0 else math.nan
        print(f"{label:<18}{_hms(prusa_says):>13}{_hms(on_theirs):>16}{ratio:>8.3f}{_hms(header):>16}"
              f"{_hms(read_back):>12}{versus:>10.3f}")
    if ratios:
        worst = max(abs(r - 1) for r in ratios)
        print(f"\nours on PrusaSlicer's files: ratio {min(ratios):.3f} to {max(ratios):.3f}; target within "
              f"{TARGET:.0%}: {'met' if worst <= TARGET else 'NOT met'}")
    else:
        print("\nno PrusaSlicer estimate to compare with")
    print(f"G-code in {folder}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
