"""Per-layer cost and accuracy of the layer-raster toolpaths, and how the cost grows with a part's size.

Layers: for a layer of the torus and of the pot, at pixel sizes 0.2, 0.1, 0.05 and 0.02 mm, wall time of
`slicelab.layer_paths` (raster, exact distance field, perimeters, gap fill, zigzag filling, order),
its peak memory, the pixels held (the blocks along the boundary) against the pixels of the islands'
boxes, and beside them the accuracy of the perimeters against shapely's exact offsets
(`buffer(-d, join_style="round")`): Hausdorff distance and relative area error. Each
configuration runs in a fresh process, so peak memory (ru_maxrss minus the resident size before
the call) is its own.

Rings: a ring of constant 4 mm wall (`slicelab.samples.ring_prism`, cut at mid-height) with outer
radius 10, 20, 40, 80 and 160 mm, at the default pixel (0.2 mm): the median time of `layer_paths` over
`--repeat` runs, the pixels held, and each size's ratio to the previous one. Work that follows the
boundary doubles when the radius doubles; work over the islands' boxes would quadruple. The
exponent fitted to time ~ radius^k says which.

Skins: the same rings as a top skin, their whole area solid (filled with lines): the time of
`layer_paths` and of the solid filling's gap fill in it, by radius. The lines grow with the area,
which grows with the radius here. The gap fill draws the lines' coverage over the box of the solid
region, which grows with its square, and works on the gaps only in the blocks that hold them.

The machine may be shared: timings are medians, and still noisy.

    python scripts/bench_layers.py [--repeat 3] [--table layers|rings|skins|all]
"""
from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAYERS = [("torus", ROOT / "data" / "torus.stl", 5.0), ("pot", ROOT / "data" / "pot.stl", 60.0),
          ("torus_1m", ROOT / "data" / "large" / "torus_1m.stl", 5.0)]
PIXELS = [0.2, 0.1, 0.05, 0.02]
RADII = [10.0, 20.0, 40.0, 80.0, 160.0]
WALL = 4.0


def _rss_kb() -> int:
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return 0


def settings(p: float):
    """The settings of every measured `layer_paths` call: 0.4 mm lines, 2 perimeters, 20% infill, `p` mm
    pixels, each loop from its vertex nearest the nozzle."""
    from slicelab.printing.config.settings import PrintSettings
    return PrintSettings(line_width=0.4, n_perimeters=2, infill_density=0.2, pixel_size=p, seam_position="nearest")


def child(path: str, z: float, p: float, repeat: int) -> dict:
    import shapely
    import slicelab
    from slicelab.printing.config.settings import PrintSettings
    from slicelab.printing.pipeline import layer_paths, plan_layer
    mesh = slicelab.load(path)
    s = slicelab.section(mesh, (0, 0, z), (0, 0, 1))
    layer_paths(s, PrintSettings(pixel_size=0.1))  # warm imports
    before = _rss_kb()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        lp = layer_paths(s, settings(p))
        times.append(time.perf_counter() - t0)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
    per = plan_layer(s, settings(p)).walls
    shape = s.to_shapely()
    hd, area = [], []
    for k, level in enumerate(per.levels):
        ref = shape.buffer(-level, join_style="round", quad_segs=64)
        ours = shapely.MultiPolygon([shapely.Polygon(q.exterior, q.holes) for q in per.rings[k]])
        hd.append(shapely.hausdorff_distance(ref.boundary, ours.boundary, densify=0.02))
        area.append(abs(ours.area - ref.area) / ref.area)
    px = sum(f.grid.pixels for f in per.fields)
    box = sum(f.grid.shape[0] * f.grid.shape[1] for f in per.fields)
    return {"segments": len(s.segments), "pixels": px, "box": box, "time_s": statistics.median(times),
            "peak_mb": peak / 1024,
            "hausdorff_mm": max(hd), "area_err_pct": 100 * max(area), "paths": len(lp.sequence),
            "vertices": int(sum(len(q) for _, q, _ in lp.ordered()))}


def ring_section(radius: float, wall: float = WALL, step: float = 0.5):
    """The mid-height section of a ring prism (outer radius, constant wall), edges about `step` mm."""
    import numpy as np
    import slicelab
    from slicelab.samples import ring_prism
    n = max(64, int(2 * np.pi * radius / step))
    t = 2 * np.pi * np.arange(n) / n
    unit = np.c_[np.cos(t), np.sin(t)] + (0.013, 0.021)
    return slicelab.section(ring_prism(radius * unit, (radius - wall) * unit, 0.0, 1.0), (0, 0, 0.5), (0, 0, 1))


def ring_table(repeat: int) -> None:
    """Time and pixels held per layer for rings of growing radius, and the fitted exponent."""
    import numpy as np
    from slicelab.printing.config.settings import PrintSettings
    from slicelab.printing.pipeline import layer_paths, plan_layer
    p = PrintSettings().pixel_size
    print(f"\nring of {WALL:g} mm wall, layer_paths at {p:g} mm pixels (median of {repeat} runs)")
    print(f"{'radius mm':>10}{'time ms':>10}{'x prev':>8}{'px held':>11}{'x prev':>8}{'box px':>12}")
    layer_paths(ring_section(RADII[0]), PrintSettings(pixel_size=p))  # warm imports
    times, held = [], []

    def ratio(xs):
        return f"{xs[-1] / xs[-2]:>8.2f}" if len(xs) > 1 else f"{'':>8}"

    for radius in RADII:
        s = ring_section(radius)
        runs = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            lp = layer_paths(s, settings(p))
            runs.append(time.perf_counter() - t0)
        fields = plan_layer(s, settings(p)).walls.fields
        times.append(statistics.median(runs))
        held.append(sum(f.grid.pixels for f in fields))
        box = sum(f.grid.shape[0] * f.grid.shape[1] for f in fields)
        print(f"{radius:>10g}{1000 * times[-1]:>10.1f}{ratio(times)}{held[-1]:>11d}{ratio(held)}{box:>12d}")
    k_time = np.polyfit(np.log(RADII), np.log(times), 1)[0]
    k_px = np.polyfit(np.log(RADII), np.log(held), 1)[0]
    print(f"fitted exponent: time ~ radius^{k_time:.2f}, pixels held ~ radius^{k_px:.2f} "
          "(1: follows the boundary, 2: the area)")


def skin_table(repeat: int) -> None:
    """The same rings as a top skin (their whole area solid, filled with lines): time per layer and
    the share of it in the solid filling's gap fill (`_solid_gaps`), by radius, and the exponent."""
    import numpy as np
    from slicelab.printing.config.settings import PrintSettings
    from slicelab.printing.grid.raster import rasterize
    from slicelab.printing.pipeline import LayerInputs, layer_paths
    from slicelab.printing.steps import filling
    from slicelab.printing.steps.perimeters import perimeter_band
    from profile_layers import timing  # (scripts/ is on the path when a script runs)
    p = PrintSettings().pixel_size
    band = perimeter_band(0.4, 2, 0.15, p)
    print(f"\nthe ring as a top skin (all of it solid), layer_paths at {p:g} mm pixels (median of {repeat} runs)")
    print(f"{'radius mm':>10}{'time ms':>10}{'x prev':>8}{'gaps ms':>10}")
    spent = []
    times, gap_times = [], []
    with timing(filling, "_solid_gaps", lambda a, k, t: spent.append(t)):
        for radius in RADII:
            s = ring_section(radius)
            r = rasterize(s, p, band=band)
            layer_paths(s, settings(p), LayerInputs(raster=r, solid=r.combined()))  # warm
            runs, gaps = [], []
            for _ in range(repeat):
                spent.clear()
                t0 = time.perf_counter()
                layer_paths(s, settings(p), LayerInputs(raster=r, solid=r.combined()))
                runs.append(time.perf_counter() - t0)
                gaps.append(sum(spent))
            times.append(statistics.median(runs))
            gap_times.append(statistics.median(gaps))
            prev = f"{times[-1] / times[-2]:>8.2f}" if len(times) > 1 else f"{'':>8}"
            print(f"{radius:>10g}{1000 * times[-1]:>10.1f}{prev}{1000 * statistics.median(gaps):>10.1f}")
    k = np.polyfit(np.log(RADII), np.log(times), 1)[0]
    k_gaps = np.polyfit(np.log(RADII), np.log(gap_times), 1)[0]
    print(f"fitted exponents: time ~ radius^{k:.2f}, the gap fill's ~ radius^{k_gaps:.2f} (coverage drawn over the "
          "box of the solid region, gaps worked on in their blocks)")


def pot_time(repeat: int) -> None:
    """The pot's layer at mid-height with the defaults (0.2 mm pixels), and at 0.1 and 0.05 mm: median times."""
    import slicelab
    from slicelab.printing.config.settings import PrintSettings
    from slicelab.printing.pipeline import layer_paths, plan_layer
    path = ROOT / "data" / "pot.stl"
    if not path.exists():
        return
    s = slicelab.section(slicelab.load(path), (0, 0, 60.0), (0, 0, 1))
    layer_paths(s)  # warm imports
    for p in (PrintSettings().pixel_size, 0.1, 0.05):
        runs = []
        for _ in range(max(repeat, 3)):
            t0 = time.perf_counter()
            lp = layer_paths(s, settings(p))
            runs.append(time.perf_counter() - t0)
        walls = plan_layer(s, settings(p)).walls
        held = sum(f.grid.pixels for f in walls.fields)
        box = sum(f.grid.shape[0] * f.grid.shape[1] for f in walls.fields)
        print(f"\npot layer (z = 60 mm, {p:g} mm pixels): {1000 * statistics.median(runs):.0f} ms "
              f"(median of {len(runs)}), {held} px held of {box} in the islands' boxes")


def layer_table(repeat: int) -> int:
    print("layer_paths per layer (w=0.4 mm, 2 perimeters, 20% infill); median times")
    print(f"{'layer':<10}{'segments':>9}{'pixel':>7}{'Mpx held':>9}{'Mpx box':>8}{'time s':>8}{'peak MB':>9}"
          f"{'Hausdorff mm':>14}{'area err %':>12}{'paths':>7}")
    for name, path, z in LAYERS:
        if not path.exists():
            print(f"{name:<10} (missing {path.relative_to(ROOT)}: make data-large)")
            continue
        for p in PIXELS:
            out = subprocess.run([sys.executable, __file__, "--repeat", str(repeat), "--child", str(path),
                                  str(z), str(p)], capture_output=True, text=True)
            if out.returncode:
                print(out.stderr[-2000:])
                return 1
            r = json.loads(out.stdout.strip().splitlines()[-1])
            print(f"{name:<10}{r['segments']:>9}{p:>7}{r['pixels'] / 1e6:>9.2f}{r['box'] / 1e6:>8.2f}"
                  f"{r['time_s']:>8.3f}{r['peak_mb']:>9.0f}{r['hausdorff_mm']:>14.4f}{r['area_err_pct']:>12.4f}"
                  f"{r['paths']:>7}")
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--table", choices=("layers", "rings", "skins", "all"), default="all")
    ap.add_argument("--child", nargs=3, metavar=("PATH", "Z", "P"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child(args.child[0], float(args.child[1]), float(args.child[2]), args.repeat)))
        return 0
    if args.table in ("layers", "all") and layer_table(args.repeat):
        return 1
    if args.table in ("rings", "all"):
        pot_time(args.repeat)
        ring_table(args.repeat)
    if args.table in ("skins", "all"):
        skin_table(args.repeat)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
