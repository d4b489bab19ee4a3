"""Benchmark build plates: partition two objects for two printers and pack the pieces onto plates.

    .venv/bin/python scripts/bench_plates.py

Objects: the pot sample (data/pot.stl, 124 x 124 x 120 mm) and the 1-metre pot
of notebook 05 (the pot sample scaled to 1033 x 1033 x 1000 mm). Printers: a
200 x 200 x 200 mm and a 250 x 210 x 210 mm build volume (the pot sample is
partitioned for an 80 mm cube first, so that it has pieces to pack). For each
case: pieces, plates used, the area lower bound (total footprint / plate
area, rounded up), one piece per plate, the mean fill of the plates, and the
time of `arrange`. Cost: each piece's footprint is linear in its facets; the
bottom-left packing tries a few turns at the corners the placed pieces offer,
about quadratic in the pieces on a plate.

Reference, where `prusa-slicer` is installed: `prusa-slicer --export-stl --merge
--bed-shape ...` arranges the same pieces on its one bed and merges them; the
comparison is the extent of its arrangement (does it fit one bed?) against
slicelab's plate count.

    .venv/bin/python scripts/bench_plates.py --object pot   # the pot sample only (seconds, not minutes)
"""
from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import slicelab  # noqa: E402
from slicelab.slicing import arrange  # noqa: E402


#: The objects by the name ``--object`` takes.
OBJECTS = ("pot", "metre")


def _objects(names=OBJECTS):
    pot = slicelab.load(ROOT / "data" / "pot.stl")
    metre = pot.transformed(np.diag([1000 / 120] * 3 + [1.0]))
    objects = {"pot": ("pot sample, cut for an 80 mm cube", pot, (80.0, 80.0, 80.0)),
               "metre": ("1-metre pot", metre, None)}
    return [objects[name] for name in OBJECTS if name in names]


def _prusa_span(prusa: str, pieces, volume):
    """The xy extent of PrusaSlicer's arrangement of the pieces on its one bed (None if it failed)."""
    X, Y, _ = volume
    with tempfile.TemporaryDirectory() as tmp:
        files = []
        for k, p in enumerate(pieces):
            f = Path(tmp) / f"p{k:03d}.stl"
            slicelab.save(p, f)
            files.append(str(f))
        out = Path(tmp) / "merged.stl"
        cmd = [prusa, "--export-stl", "--merge", "--bed-shape", f"0x0,{X}x0,{X}x{Y},0x{Y}",
               "--output", str(out), *files]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
        if r.returncode != 0 or not out.exists():
            return None
        lo, hi = slicelab.load(out).bounds
        return float(hi[0] - lo[0]), float(hi[1] - lo[1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--object", action="append", choices=OBJECTS,
                    help="only this object (repeatable): the pot sample or the 1-metre pot; default both")
    args = ap.parse_args(argv)
    prusa = shutil.which("prusa-slicer") or shutil.which("prusaslicer")
    print("bench_plates: partition, then arrange the pieces onto build plates (spacing 5 mm)")
    if prusa is None:
        print("prusa-slicer is not installed (apt-get install -y prusa-slicer): no reference")
    printers = [(200.0, 200.0, 200.0), (250.0, 210.0, 210.0)]
    print(f"\n{'object':<36} {'printer (mm)':<14} {'pieces':>6} {'plates':>6} {'bound':>5} "
          f"{'1/plate':>7} {'fill %':>6} {'time s':>7}  reference")
    for name, mesh, cut_volume in _objects(args.object or OBJECTS):
        for volume in printers:
            parts = slicelab.partition(mesh, cut_volume or volume)
            pieces = list(parts.pieces)
            t0 = time.perf_counter()
            plates = arrange(pieces, volume, spacing=5.0)
            seconds = time.perf_counter() - t0
            ref = ""
            if prusa is not None:
                span = _prusa_span(prusa, pieces, volume)
                if span is None:
                    ref = "prusa-slicer failed"
                else:
                    fits = span[0] <= volume[0] + 1e-6 and span[1] <= volume[1] + 1e-6
                    ref = (f"PrusaSlicer's arrangement spans {span[0]:.0f} x {span[1]:.0f} mm "
                           f"({'one bed' if fits else 'more than one bed'})")
            size = "x".join(f"{v:g}" for v in volume)
            print(f"{name:<36} {size:<14} {len(pieces):6d} {len(plates):6d} {plates.lower_bound:5d} "
                  f"{len(pieces):7d} {100 * np.mean(plates.fill):6.1f} {seconds:7.2f}  {ref}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
