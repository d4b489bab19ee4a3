"""`make demo`: run slicelab's main jobs on the bundled samples and write results/.

Each step runs the real command line, as a user would, and stops at the first failure.
``--out DIR`` writes elsewhere (`tests/test_demo.py` runs the demo into a temporary folder).
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"
SLICELAB = [sys.executable, "-m", "slicelab"]


def steps(out: Path) -> list:
    """The demo's steps: (title, the command's arguments, a file for its output or None)."""
    return [
        ("inspect every sample", ["inspect", *sorted(str(p) for p in DATA.glob("*.stl"))], "inspect.txt"),
        ("pot: section through the axis", ["section", str(DATA / "pot.stl"), "--origin", "0,0,0",
                                           "--normal", "0,-1,0", "-o", str(out / "pot_axial.svg")], None),
        ("pot: horizontal section at mid-height", ["section", str(DATA / "pot.stl"), "--z", "60",
                                                   "-o", str(out / "pot_z60.svg")], None),
        ("pot: every 2 mm layer", ["layers", str(DATA / "pot.stl"), "--layer-height", "2",
                                   "-o", str(out / "pot_layers")], None),
        ("pot: split through the axis into front, section and rear",
         ["split", str(DATA / "pot.stl"), "--origin", "0,0,60", "--normal", "0,-1,0", "-o", str(out / "pot_split")],
         None),
        ("pot: profile drawing and measurements",
         ["profile", str(DATA / "pot.stl"), "-o", str(out / "pot_profile.svg"), "--png", str(out / "pot_profile.png"),
          "--json", str(out / "pot_profile.json")], "pot_profile.txt"),
        ("torus: watertight cut by a tilted plane, both parts capped",
         ["cut", str(DATA / "torus.stl"), "--origin", "0,0,0.3", "--normal", "0.2,0.1,1", "-o", str(out / "torus_cut")],
         None),
        ("pot: pieces for an 80 mm printer, stair joints",
         ["partition", str(DATA / "pot.stl"), "--volume", "80x80x80", "--joint", "stair", "--step", "8,16",
          "-o", str(out / "pot_parts")], "pot_parts.txt"),
        # The print-test parts (a staircase, a bridge, a mushroom) are no vessels: a profile of them is refused.
        ("every other sample: batch profile (reports, summary.csv; reruns skip)",
         ["batch", str(DATA), "-o", str(out / "batch_profile"), "--task", "profile", "--planes", "6",
          "--exclude", "large/*", "--exclude", "staircase.stl", "--exclude", "bridge.stl", "--exclude", "mushroom.stl",
          "--workers", "2", "--no-progress"], None),
        ("cube with a hole: G-code (perimeters, solid skins, 20% infill) and previews",
         ["slice", str(DATA / "cube_with_hole.stl"), "-o", str(out / "cube_with_hole.gcode"),
          "--preview", str(out / "cube_with_hole_preview")], None),
        ("pot: G-code for a 0.8 mm nozzle, 0.6 mm layers (printable; the defaults are a 0.4 mm nozzle and 0.2 mm)",
         ["slice", str(DATA / "pot.stl"), "-o", str(out / "pot.gcode"), "--nozzle-diameter", "0.8", "--line-width",
          "0.8", "--layer-height", "0.6", "--pixel-size", "0.1", "--preview", str(out / "pot_preview")], None),
    ]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=ROOT / "results", help="where the results go (default results/)")
    out = ap.parse_args(argv).out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    for title, args, stdout_name in steps(out):
        print(f"\n== {title}: slicelab {' '.join(Path(a).name if '/' in a else a for a in args)}", flush=True)
        t0 = time.perf_counter()
        result = subprocess.run(SLICELAB + args, cwd=ROOT, text=True, capture_output=True)
        sys.stdout.write(result.stdout[-4000:])
        if stdout_name:
            (out / stdout_name).write_text(result.stdout)
        if result.returncode != 0:
            sys.stderr.write(result.stderr)
            print(f"demo step failed: {title}", file=sys.stderr)
            return result.returncode
        print(f"   ({time.perf_counter() - t0:.1f} s)")
    shown = out.relative_to(ROOT) if out.is_relative_to(ROOT) else out
    print(f"\nresults in {shown}/:")
    for p in sorted(out.iterdir()):
        if p.is_dir():
            print(f"   {shown / p.name}/ ({sum(1 for q in p.rglob('*') if q.is_file())} files)")
        else:
            print(f"   {shown / p.name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
