"""Per-layer cost and accuracy of the layer-raster toolpaths (issue 5).

For a layer of the torus and of the pot, at pixel sizes 0.1, 0.05 and 0.02 mm: wall time of
`slicelab.layer_paths` (raster, exact distance field, perimeters, gap fill, zigzag filling, order),
its peak memory, and beside them the accuracy of the perimeters against shapely's exact offsets
(`buffer(-d, join_style="round")`): Hausdorff distance and relative area error.

Each configuration runs in a fresh process, so peak memory (ru_maxrss minus the resident size
before the call) is its own. The machine is shared: timings are noisy.

    python scripts/bench_layers.py [--repeat 3]
"""
from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAYERS = [("torus", ROOT / "data" / "torus.stl", 5.0), ("pot", ROOT / "data" / "pot.stl", 60.0),
          ("torus_1m", ROOT / "data" / "large" / "torus_1m.stl", 5.0)]
PIXELS = [0.1, 0.05, 0.02]


def _rss_kb() -> int:
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return 0


def child(path: str, z: float, p: float, repeat: int) -> dict:
    import shapely
    import slicelab
    mesh = slicelab.load(path)
    s = slicelab.section(mesh, (0, 0, z), (0, 0, 1))
    slicelab.layer_paths(s, pixel_size=0.1)  # warm imports
    before = _rss_kb()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        lp = slicelab.layer_paths(s, 0.4, 2, 0.2, pixel_size=p)
        times.append(time.perf_counter() - t0)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
    per = lp.perimeters
    shape = s.to_shapely()
    hd, area = [], []
    for k, level in enumerate(per.levels):
        ref = shape.buffer(-level, join_style="round", quad_segs=64)
        ours = shapely.MultiPolygon([shapely.Polygon(q.exterior, q.holes) for q in per.rings[k]])
        hd.append(shapely.hausdorff_distance(ref.boundary, ours.boundary, densify=0.02))
        area.append(abs(ours.area - ref.area) / ref.area)
    px = sum(f.grid.mask.size for f in per.fields)
    return {"segments": len(s.segments), "pixels": px, "time_s": min(times), "peak_mb": peak / 1024,
            "hausdorff_mm": max(hd), "area_err_pct": 100 * max(area), "paths": len(lp.sequence),
            "vertices": int(sum(len(q) for _, q, _ in lp.ordered()))}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--child", nargs=3, metavar=("PATH", "Z", "P"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child(args.child[0], float(args.child[1]), float(args.child[2]), args.repeat)))
        return 0
    print("layer_paths per layer (w=0.4 mm, 2 perimeters, 20% infill); shared 2-core machine, noisy timings")
    print(f"{'layer':<10}{'segments':>9}{'pixel':>7}{'Mpx':>7}{'time s':>8}{'peak MB':>9}"
          f"{'Hausdorff mm':>14}{'area err %':>12}{'paths':>7}")
    for name, path, z in LAYERS:
        if not path.exists():
            print(f"{name:<10} (missing {path.relative_to(ROOT)}: make data-large)")
            continue
        for p in PIXELS:
            out = subprocess.run([sys.executable, __file__, "--repeat", str(args.repeat), "--child", str(path),
                                  str(z), str(p)], capture_output=True, text=True)
            if out.returncode:
                print(out.stderr[-2000:])
                return 1
            r = json.loads(out.stdout.strip().splitlines()[-1])
            print(f"{name:<10}{r['segments']:>9}{p:>7}{r['pixels'] / 1e6:>7.2f}{r['time_s']:>8.3f}"
                  f"{r['peak_mb']:>9.0f}{r['hausdorff_mm']:>14.4f}{r['area_err_pct']:>12.4f}{r['paths']:>7}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
