"""Benchmark sections: every layer of a 1M-facet torus, and one section of a 5M-facet pot.

    .venv/bin/python scripts/bench_sections.py
    .venv/bin/python scripts/bench_sections.py --docs   # also the docs' table (docs/performance/tables/)

1. ``slicelab.slice_layers(mesh, 0.2)`` of data/large/torus_1m.stl (100 layers,
   chained into loops with the hole hierarchy) beside trimesh's
   ``Trimesh.section_multiplane`` (segments turned into Path2D objects, loops
   left for later) and ``trimesh.intersections.mesh_multiplane`` (bare
   segments) on the same planes. Both meshes are loaded beforehand and their
   load is *not* counted (trimesh's load time is printed for information).
   As a sanity check the total layer area is compared with trimesh's: per
   layer, the closed paths of ``section_multiplane`` become shapely polygons
   combined by symmetric difference (even-odd, so holes are subtracted).
2. Load + one horizontal section at mid-height of data/large/pot_5m.stl, with
   slicelab (``load`` + ``section``) and with trimesh (``load`` + ``section``),
   each in a fresh child process whose peak memory is recorded.

Part 1 takes the median of three runs per tool, part 2 one run (machine shared, so noisy). Targets: slice_layers at
least 10x faster than section_multiplane and 4x faster than mesh_multiplane;
load + one section of 5M facets in at most 2.5 s; peak memory of that run
under 2 GB.
"""
from __future__ import annotations

import argparse
import sys
import time
from functools import reduce
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import benchlib  # noqa: E402

LAYER = 0.2
POT_Z = 60.0
TARGET_VS_SECTION_MULTIPLANE = 10.0
TARGET_VS_MESH_MULTIPLANE = 4.0
TARGET_POT_SECONDS = 2.5
TARGET_POT_PEAK_MB = 2048.0


def _trimesh_layer_areas(paths) -> list[float]:
    import shapely
    areas = []
    for p in paths:
        if p is None:
            areas.append(0.0)
            continue
        rings = [shapely.Polygon(q.exterior) for q in p.polygons_closed if q is not None]
        areas.append(reduce(lambda a, b: a.symmetric_difference(b), rings).area if rings else 0.0)
    return areas


def child_layers(path: str) -> None:
    import numpy as np
    import trimesh

    import slicelab
    from slicelab.slicing.sections import layer_heights

    mesh = slicelab.load(path)
    t0 = time.perf_counter()
    tm = trimesh.load(path)
    tm_load = time.perf_counter() - t0
    z = layer_heights(mesh, LAYER)
    origin, normal = [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]

    def median_of_3(run):
        # Each tool runs three times in turn and keeps its median: first-call costs (imports,
        # cached mesh properties, fresh memory) count for nobody.
        times, result = [], None
        for _ in range(3):
            t0 = time.perf_counter()
            result = run()
            times.append(time.perf_counter() - t0)
        return float(np.median(times)), result

    ours, layers = median_of_3(lambda: slicelab.slice_layers(mesh, LAYER))
    t_smp, paths = median_of_3(lambda: tm.section_multiplane(origin, normal, z))
    t_mmp, (lines, _, _) = median_of_3(lambda: trimesh.intersections.mesh_multiplane(tm, origin, normal, z))

    our_areas = np.array([s.area for s in layers])
    tm_areas = np.array(_trimesh_layer_areas(paths))
    benchlib.child_report(
        ours, facets=len(mesh), planes=len(z), trimesh_load=tm_load,
        section_multiplane=t_smp, mesh_multiplane=t_mmp,
        segments=int(sum(len(s.segments) for s in layers)), loops=int(sum(len(s.loops) for s in layers)),
        open_chains=int(sum(len(s.open_chains) for s in layers)),
        trimesh_segments=int(sum(len(x) for x in lines)),
        area=float(our_areas.sum()), trimesh_area=float(tm_areas.sum()),
        max_layer_rel_diff=float(np.max(np.abs(our_areas - tm_areas) / np.maximum(tm_areas, 1e-300))))


def child_pot_ours(path: str) -> None:
    import slicelab
    t0 = time.perf_counter()
    mesh = slicelab.load(path)
    t1 = time.perf_counter()
    s = slicelab.section(mesh, (0.0, 0.0, POT_Z), (0.0, 0.0, 1.0))
    t2 = time.perf_counter()
    benchlib.child_report(t2 - t0, load=t1 - t0, section=t2 - t1, facets=len(mesh), area=s.area,
                          loops=len(s.loops), open_chains=len(s.open_chains))


def child_pot_trimesh(path: str) -> None:
    import trimesh
    t0 = time.perf_counter()
    tm = trimesh.load(path)
    t1 = time.perf_counter()
    p = tm.section(plane_origin=[0.0, 0.0, POT_Z], plane_normal=[0.0, 0.0, 1.0])
    t2 = time.perf_counter()
    planar, _ = p.to_2D()
    area = _trimesh_layer_areas([planar])[0]
    benchlib.child_report(t2 - t0, load=t1 - t0, section=t2 - t1, facets=len(tm.faces), area=area)


def main() -> int:
    # One option, --docs (read in __main__); `--help` prints the docstring before data/large/ is
    # written or anything is timed.
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--docs", action="store_true",
                    help="also write what is printed, with the machine and date, for the docs' performance pages")
    ap.parse_args()
    benchlib.ensure_large_data()
    script = str(Path(__file__).resolve())
    torus = benchlib.LARGE / "torus_1m.stl"
    pot = benchlib.LARGE / "pot_5m.stl"
    print("bench_sections: slicelab sections vs trimesh (part 1: median of 3 runs per tool; part 2: one run; warm page cache)")
    print(benchlib.NOISE_NOTE)

    benchlib.warm(torus)
    r = benchlib.run_child(script, "layers", str(torus))
    print(f"\n1. every {LAYER} mm layer of {torus.name}: {r['facets']:,} facets, {r['planes']} planes, "
          f"both meshes loaded beforehand (load not counted; trimesh.load took {r['trimesh_load']:.2f} s)")
    v_smp = r["section_multiplane"] / r["seconds"]
    v_mmp = r["mesh_multiplane"] / r["seconds"]
    print(f"  {'slicelab.slice_layers (segments, loops, holes)':52s} {r['seconds']:7.2f} s")
    print(f"  {'trimesh Trimesh.section_multiplane (Path2D)':52s} {r['section_multiplane']:7.2f} s"
          f"   ratio {v_smp:5.1f}x")
    print(f"  {'trimesh.intersections.mesh_multiplane (segments)':52s} {r['mesh_multiplane']:7.2f} s"
          f"   ratio {v_mmp:5.1f}x")
    print(f"  peak RSS of this child (both meshes, all three results): {r['peak_mb']:.0f} MiB")
    print(f"  ours: {r['segments']:,} segments in {r['loops']} loops, {r['open_chains']} open chains; "
          f"trimesh: {r['trimesh_segments']:,} segments")
    rel = abs(r["area"] - r["trimesh_area"]) / r["trimesh_area"]
    ok_area = rel < 1e-9 and r["max_layer_rel_diff"] < 1e-9
    print(f"  sanity: total layer area {r['area']:.6f} mm2 (ours) vs {r['trimesh_area']:.6f} mm2 "
          f"(trimesh + shapely): relative difference {rel:.1e}, worst layer {r['max_layer_rel_diff']:.1e}"
          f"  {'OK' if ok_area else 'DISAGREE'}")

    benchlib.warm(pot)
    ours = benchlib.run_child(script, "pot-ours", str(pot))
    theirs = benchlib.run_child(script, "pot-trimesh", str(pot))
    print(f"\n2. load + one horizontal section at z = {POT_Z:g} of {pot.name}: {ours['facets']:,} facets "
          f"(each in a fresh process)")
    for label, x in (("slicelab.load + slicelab.section", ours), ("trimesh.load + Trimesh.section", theirs)):
        print(f"  {label:34s} {x['seconds']:7.2f} s  (load {x['load']:.2f} s + section {x['section']:.3f} s)"
              f"  peak RSS {x['peak_mb']:6.0f} MiB")
    v_pot = theirs["seconds"] / ours["seconds"]
    print(f"  ratio (trimesh / slicelab): {v_pot:.1f}x; areas {ours['area']:.6f} vs {theirs['area']:.6f} mm2 "
          f"({ours['loops']} loops, {ours['open_chains']} open chains)")

    targets = [
        (f"slice_layers >= {TARGET_VS_SECTION_MULTIPLANE:g}x faster than section_multiplane: {v_smp:.1f}x",
         v_smp >= TARGET_VS_SECTION_MULTIPLANE),
        (f"slice_layers >= {TARGET_VS_MESH_MULTIPLANE:g}x faster than mesh_multiplane: {v_mmp:.1f}x",
         v_mmp >= TARGET_VS_MESH_MULTIPLANE),
        (f"load + one section of 5M facets <= {TARGET_POT_SECONDS:g} s: {ours['seconds']:.2f} s",
         ours["seconds"] <= TARGET_POT_SECONDS),
        (f"peak memory of the 5M run < 2 GB: {ours['peak_mb']:.0f} MiB", ours["peak_mb"] < TARGET_POT_PEAK_MB),
    ]
    print("\ntargets:")
    for text, ok in targets:
        print(f"  {benchlib.mark(ok)}  {text}")
    return 0  # a missed target is reported, not an error: the numbers are noisy


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == benchlib.CHILD_FLAG:
        {"layers": child_layers, "pot-ours": child_pot_ours,
         "pot-trimesh": child_pot_trimesh}[sys.argv[2]](*sys.argv[3:])
    else:
        with benchlib.docs_output("bench_sections", "--docs" in sys.argv[1:]):
            raise SystemExit(main())
