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
--arrange 1` on the same pieces and bed: PrusaSlicer has one bed, so the
comparison is how many pieces it fits on it against slicelab's first plate.
"""
from __future__ import annotations

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
from slicelab.geometry import shells, weld  # noqa: E402
from slicelab.slicing import arrange  # noqa: E402


def _objects():
    pot = slicelab.load(ROOT / "data" / "pot.stl")
    metre = pot.transformed(np.diag([1000 / 120] * 3 + [1.0]))
    return [("pot sample, cut for an 80 mm cube", pot, (80.0, 80.0, 80.0)), ("1-metre pot", metre, None)]


def _prusa_count(prusa: str, pieces, volume) -> int | None:
    """How many pieces PrusaSlicer's arrange puts inside its one bed."""
    X, Y, _ = volume
    with tempfile.TemporaryDirectory() as tmp:
        files = []
        for k, p in enumerate(pieces):
            f = Path(tmp) / f"p{k:03d}.stl"
            slicelab.save(p, f)
            files.append(str(f))
        out = Path(tmp) / "merged.stl"
        cmd = [prusa, "--export-stl", "--merge", "--arrange", "1", "--bed-shape", f"0x0,{X}x0,{X}x{Y},0x{Y}",
               "--output", str(out), *files]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        if r.returncode != 0 or not out.exists():
            return None
        merged = slicelab.load(out)
        v, f = weld(merged.triangles)
        n, label = shells(f)
        inside = 0
        for s in range(n):  # over bodies
            pts = v[f[label == s]].reshape(-1, 3)
            inside += bool(np.all(pts[:, 0] >= -1e-3) and np.all(pts[:, 0] <= X + 1e-3)
                           and np.all(pts[:, 1] >= -1e-3) and np.all(pts[:, 1] <= Y + 1e-3))
        return inside


def main() -> int:
    prusa = shutil.which("prusa-slicer") or shutil.which("prusaslicer")
    print("bench_plates: partition, then arrange the pieces onto build plates (spacing 5 mm)")
    if prusa is None:
        print("prusa-slicer is not installed (apt-get install -y prusa-slicer): no reference")
    printers = [(200.0, 200.0, 200.0), (250.0, 210.0, 210.0)]
    print(f"\n{'object':<36} {'printer (mm)':<14} {'pieces':>6} {'plates':>6} {'bound':>5} "
          f"{'1/plate':>7} {'fill %':>6} {'time s':>7}  reference")
    for name, mesh, cut_volume in _objects():
        for volume in printers:
            parts = slicelab.partition(mesh, cut_volume or volume)
            pieces = list(parts.pieces)
            t0 = time.perf_counter()
            plates = arrange(pieces, volume, spacing=5.0)
            seconds = time.perf_counter() - t0
            ref = ""
            if prusa is not None:
                count = _prusa_count(prusa, pieces, volume)
                first = len(plates.plates[0].pieces)
                ref = ("prusa-slicer --arrange failed" if count is None else
                       f"PrusaSlicer fits {count} on its bed, slicelab's first plate {first}")
            size = "x".join(f"{v:g}" for v in volume)
            print(f"{name:<36} {size:<14} {len(pieces):6d} {len(plates):6d} {plates.lower_bound:5d} "
                  f"{len(pieces):7d} {100 * np.mean(plates.fill):6.1f} {seconds:7.2f}  {ref}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
