"""Where a layer's time goes: 100 layers of a part (from a quarter up, or `--first`) planned in this process, timed, then profiled.

The layers go through the planner's own per-run function (`slicelab.printing.runs.run_layers`),
runs of 20 layers with the neighbours their skins read, as a pool's worker gets them,
with `slicelab slice`'s defaults and 3 top and bottom layers. Prints the milliseconds per
layer (median of three passes, no profiler), the milliseconds per layer of each stage (one
more pass, each stage's function timed where the planner and the perimeters call it; the
stages nest: the perimeters' parts are inside `plan_layer`), then cProfile's functions by
their own time and by cumulative time. No reference tool: this says where slicelab's time goes, and
`scripts/bench_slice.py` compares the whole command with PrusaSlicer. Cost: linear in the
layers profiled.

``--costs`` prints instead how many layers the planner plans afresh and how many it takes from the
layer two below (layers that repeat), and how each layer planned afresh's time (planning the whole
part in one process, each layer's `plan_layer`) follows the terms of the planner's estimate of a layer's cost, which orders the runs of layers handed to the
workers: the least-squares fit of the time to the boundary's length and the skin's area, the
skin's weight it implies, and the costliest layers. ``--scale S`` scales the part to S mm first.

``--accuracy`` prints instead how far the perimeters of five layers (at 20, 35, 50, 65 and
80 % of the height) stray from shapely's exact offsets of the same sections (round joins,
64 segments a quarter circle), at pixel sizes 0.1, 0.15 and 0.2 mm: the largest distance
from a point of our perimeters (every 0.02 mm along them) to the exact offsets, and its 99.9th
and 99th percentiles. The reference is GEOS's offset, computed in the same run.

    python scripts/profile_layers.py [MESH] [--top 35] [--pixel-size P] [--first K] [--layers 100]
                                     [--accuracy] [--costs] [--scale S]
"""
from __future__ import annotations

import argparse
import contextlib
import cProfile
import pstats
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


#: (stage, where it is called from): each is timed where its caller looks it up.
STAGES = [("rasterize", "slicelab.printing.pipeline"), ("layer_skins", "slicelab.printing.steps.skins"),
          ("open_mask", "slicelab.printing.steps.skins"),
          ("layer_overhangs", "slicelab.printing.steps.overhangs"), ("plan_layer", "slicelab.printing.pipeline"),
          ("distance_field", "slicelab.printing.steps.perimeters"), ("level_rings", "slicelab.printing.steps.perimeters"),
          ("_opened", "slicelab.printing.steps.perimeters"), ("uncovered_blocks", "slicelab.printing.steps.perimeters"),
          ("medial_fill_blocks", "slicelab.printing.steps.perimeters"), ("split_by_mask", "slicelab.printing.steps.perimeters"),
          ("fill_pattern", "slicelab.printing.steps.filling"), ("simplify_paths", "slicelab.printing.steps.simplify")]


@contextlib.contextmanager
def timing(home, name: str, record):
    """``home.name`` timed while the block runs: ``record(args, kwargs, seconds)`` after each call
    (a stage is timed in the module its caller looks it up in)."""
    f = getattr(home, name)

    def timed(*a, **k):
        t = time.perf_counter()
        try:
            return f(*a, **k)
        finally:
            record(a, k, time.perf_counter() - t)

    setattr(home, name, timed)
    try:
        yield
    finally:
        setattr(home, name, f)


def stage_times(run, layers: int) -> list[tuple[str, float]]:
    """Milliseconds per layer spent in each stage of `STAGES` during one call of `run`."""
    import importlib
    spent = {name: 0.0 for name, _ in STAGES}
    with contextlib.ExitStack() as stack:
        for name, module in STAGES:
            mod = importlib.import_module(module)
            # The planner imports its stages inside its run function: wrap them in their own modules.
            home = mod if hasattr(mod, name) else importlib.import_module(f"slicelab.printing.{_HOME[name]}")
            stack.enter_context(timing(home, name, lambda a, k, t, _name=name: spent.__setitem__(
                _name, spent[_name] + t)))
        run()
    return [(name, 1000 * spent[name] / layers) for name, _ in STAGES]


#: Modules of the stages the planner imports when it runs.
_HOME = {"rasterize": "raster", "layer_skins": "skins", "layer_overhangs": "overhangs", "plan_layer": "pipeline"}


def accuracy(mesh, sizes=(0.1, 0.15, 0.2)) -> None:
    """The perimeters' distance to shapely's exact offsets of five sections, by pixel size."""
    import numpy as np
    import shapely

    import slicelab
    from slicelab.slicing.sections import slice_layers
    lo, hi = mesh.bounds
    secs = slice_layers(mesh, heights=lo[2] + (hi[2] - lo[2]) * np.array([0.2, 0.35, 0.5, 0.65, 0.8]))
    print("pixel mm   largest mm  99.9 %   99 %   (perimeters' points to the exact offsets at 0.2 and 0.6 mm)")
    for p in sizes:  # over pixel sizes
        d = []
        for sec in secs:  # over layers
            geom = sec.to_shapely()
            lp = slicelab.layer_paths(sec, slicelab.PrintSettings(pixel_size=p))
            exact = shapely.union(geom.buffer(-0.2, quad_segs=64).boundary, geom.buffer(-0.6, quad_segs=64).boundary)
            lines = [shapely.LineString(r) for r in lp.external_contour_segments + lp.internal_contour_segments
                     if len(r) > 1]
            pts = np.concatenate([shapely.line_interpolate_point(q, np.arange(0, q.length, 0.02)) for q in lines])
            d.append(shapely.distance(pts, exact))
        d = np.concatenate(d)
        print(f"{p:8.2f} {d.max():12.4f} {np.percentile(d, 99.9):8.4f} {np.percentile(d, 99):6.4f}")


def costs(mesh, s) -> None:
    """Each layer's time (its `plan_layer`, where its skins are filled) against the terms of the
    planner's estimate of its cost, which orders the runs handed to the workers: the least-squares
    fit of time = a x boundary + b x skin + c, and the skin's weight b / a."""
    import numpy as np

    from slicelab.slicing.sections import slice_layers
    from slicelab.printing import _schedule as schedule
    from slicelab.printing import pipeline, planner
    spent = {}
    with timing(pipeline, "plan_layer", lambda a, k, t: spent.__setitem__(a[2].index, 1000 * t)):
        planner.plan(mesh, s, workers=1)  # imports, compiled kernels
        spent.clear()
        planner.plan(mesh, s, workers=1)
    lo, hi = mesh.bounds
    bounds = planner.layer_bounds(float(hi[2] - lo[2]), s.layer_height, s.first_layer_height)
    length, skin = schedule.layer_costs(slice_layers(mesh, heights=lo[2] + bounds.mean(axis=1)), s)
    # Layers that repeat take the toolpaths of the layer two below (no plan_layer call): only the
    # layers planned afresh are fitted.
    afresh = np.array(sorted(spent), dtype=np.int64)
    n = len(length)
    length, skin = length[afresh], skin[afresh]
    ms = np.array([spent[k] for k in afresh.tolist()])
    x = np.c_[length, skin, np.ones(len(ms))]
    (a, b, c), *_ = np.linalg.lstsq(x, ms, rcond=None)
    r2 = 1 - float(((ms - x @ (a, b, c)) ** 2).sum() / max(((ms - ms.mean()) ** 2).sum(), 1e-300))
    print(f"{n} layers: {len(afresh)} planned afresh, {n - len(afresh)} taken from the layer two below "
          f"or from the start of an earlier run (layers that repeat); {ms.sum() / 1000:.2f} s in plan_layer, "
          "one process")
    print(f"ms per layer = {a:.5f} x boundary mm + {b:.6f} x skin mm^2 + {c:.2f} (R^2 {r2:.2f}); skin weight "
          f"b / a = {b / a:.2f} (the planner uses {schedule.SKIN_COST})")
    print("costliest layers:   ms   boundary mm   skin mm^2")
    for i in np.argsort(ms)[::-1][:8]:
        print(f"  {afresh[i]:>6} {ms[i]:10.2f} {length[i]:12.1f} {skin[i]:11.1f}")


def main() -> None:
    import slicelab
    from slicelab.slicing.sections import slice_layers
    from slicelab.printing import planner
    from slicelab.printing.config.settings import PrintSettings
    from slicelab.printing.runs import RunJob, run_layers

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh", nargs="?", default=str(ROOT / "data" / "pot.stl"))
    ap.add_argument("--top", type=int, default=35)
    ap.add_argument("--pixel-size", type=float, default=None, help="mm (default: slicelab's)")
    ap.add_argument("--accuracy", action="store_true", help="the perimeters against shapely's offsets instead")
    ap.add_argument("--costs", action="store_true", help="every layer's time against the planner's cost terms")
    ap.add_argument("--scale", type=float, default=None, help="scale the part to this size (mm) first")
    ap.add_argument("--first", type=int, default=None, help="first layer profiled (default: a quarter up)")
    ap.add_argument("--layers", type=int, default=100, help="layers profiled, in runs of 20")
    args = ap.parse_args()
    mesh = slicelab.load(args.mesh)
    if args.scale:
        lo, hi = mesh.bounds
        mesh = slicelab.Mesh(mesh.triangles * (args.scale / float(max(hi - lo))))
    if args.accuracy:
        accuracy(mesh)
        return
    s = PrintSettings(top_layers=3, bottom_layers=3)
    if args.pixel_size:
        s = PrintSettings(top_layers=3, bottom_layers=3, pixel_size=args.pixel_size)
    if args.costs:
        costs(mesh, PrintSettings(top_layers=3, bottom_layers=3, skirt_loops=0, bed_size=(1000, 1000),
                                  max_height=1000, pixel_size=s.pixel_size))
        return
    lo, hi = mesh.bounds
    bounds = planner.layer_bounds(float(hi[2] - lo[2]), s.layer_height, s.first_layer_height)
    sections = slice_layers(mesh, heights=lo[2] + bounds.mean(axis=1))
    n = len(sections)
    first = max(n // 4, s.bottom_layers + 1) if args.first is None else args.first
    stop = min(first + args.layers, n)
    runs = [(a, min(a + 20, stop)) for a in range(first, stop, 20)]  # (the last one may be short)
    if not runs:
        raise SystemExit(f"profile_layers: no layers from {first}: the part has {n}")
    from slicelab.mesh import default_tolerance
    tol = default_tolerance(mesh)  # (layers that repeat are compared as the planner compares them)

    def plan_runs():
        for a, b in runs:
            window = {j: sections[j] for j in range(max(0, a - s.bottom_layers - 1), min(n, b + s.top_layers))}
            run_layers(RunJob(a, b, n, window, bounds[a:b, 1], s, tol))

    plan_runs()  # imports, compiled kernels
    layers = stop - first
    times = []
    for _ in range(3):
        t = time.perf_counter()
        plan_runs()
        times.append((time.perf_counter() - t) * 1000 / layers)
    print(f"{Path(args.mesh).name}: {layers} layers from {first}: {statistics.median(times):.1f} ms per layer "
          f"(median of 3, one process)")
    print("ms per layer by stage (one pass; the perimeters' stages and the infill are part of plan_layer):")
    for name, ms in stage_times(plan_runs, layers):
        print(f"  {name:<20}{ms:7.2f}")
    prof = cProfile.Profile()
    prof.enable()
    plan_runs()
    prof.disable()
    st = pstats.Stats(prof)
    st.sort_stats("tottime").print_stats(args.top)
    st.sort_stats("cumtime").print_stats(r"slicelab", args.top)


if __name__ == "__main__":
    main()
