"""Benchmark reading and checking large STL files against numpy-stl and trimesh.

    .venv/bin/python scripts/bench_io.py              # data/large/*.stl, median of 3 runs each
    .venv/bin/python scripts/bench_io.py --repeat 1 --files torus_1m.stl
    .venv/bin/python scripts/bench_io.py --docs       # also the docs' table (docs/performance/tables/)

For every file in data/large/ (written by ``make data-large`` if missing) this
times, each in a fresh child process (see scripts/benchlib.py):

- numpy-stl ``Mesh.from_file(path)`` with its defaults (it also computes
  normals, in float32): the floor that `slicelab.load` is measured against;
- numpy-stl ``Mesh.from_file(path, calculate_normals=False)``: the bare read,
  shown for reference;
- ``slicelab.load(path)`` (float64 triangles, winding normals, file normals);
- ``slicelab.check(mesh)`` on a mesh loaded beforehand (load not counted);
- ``trimesh.load(path)`` with its defaults (which merge vertices).

Peak memory is each child's peak resident set size, interpreter included.
Targets: on the 5M-facet files `load` adds at most 50% to numpy-stl's own
``Mesh.from_file`` time, and `check` takes under 5 s.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import benchlib  # noqa: E402

LOAD_RATIO_TARGET = 1.5
CHECK_SECONDS_TARGET = 5.0


def child(kind: str, path: str) -> None:
    if kind == "numpy-stl":
        from stl import mesh as stl_mesh
        t0 = time.perf_counter()
        m = stl_mesh.Mesh.from_file(path)
        benchlib.child_report(time.perf_counter() - t0, facets=len(m.vectors))
    elif kind == "numpy-stl-raw":
        from stl import mesh as stl_mesh
        t0 = time.perf_counter()
        m = stl_mesh.Mesh.from_file(path, calculate_normals=False)
        benchlib.child_report(time.perf_counter() - t0, facets=len(m.vectors))
    elif kind == "load":
        import slicelab
        t0 = time.perf_counter()
        m = slicelab.load(path)
        benchlib.child_report(time.perf_counter() - t0, facets=len(m))
    elif kind == "check":
        import slicelab
        m = slicelab.load(path)
        t0 = time.perf_counter()
        r = slicelab.check(m)
        benchlib.child_report(time.perf_counter() - t0, facets=len(m), watertight=r.watertight,
                              shells=r.n_shells, volume=r.volume)
    elif kind == "trimesh":
        import trimesh
        t0 = time.perf_counter()
        m = trimesh.load(path)
        benchlib.child_report(time.perf_counter() - t0, facets=len(m.faces), vertices=len(m.vertices))
    else:
        raise SystemExit(f"unknown measurement {kind!r}")


KINDS = [("numpy-stl", "numpy-stl Mesh.from_file (defaults)"),
         ("numpy-stl-raw", "numpy-stl Mesh.from_file (no normals)"),
         ("load", "slicelab.load"),
         ("check", "slicelab.check (mesh loaded before)"),
         ("trimesh", "trimesh.load (defaults)")]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3, help="child runs per measurement (median time)")
    ap.add_argument("--files", nargs="+", default=list(benchlib.LARGE_FILES), help="names in data/large/")
    ap.add_argument("--docs", action="store_true",
                    help="also write what is printed, with the machine and date, for the docs' performance pages")
    args = ap.parse_args(argv)
    benchlib.ensure_large_data()
    script = str(Path(__file__).resolve())
    print(f"bench_io: slicelab.load / slicelab.check vs numpy-stl and trimesh "
          f"(median of {args.repeat} child runs; warm page cache)")
    print(benchlib.NOISE_NOTE)
    misses = []
    for name in args.files:
        path = benchlib.LARGE / name
        benchlib.warm(path)
        res = {}
        for kind, _ in KINDS:
            res[kind] = benchlib.measure(script, kind, str(path), repeat=args.repeat)
        n = res["load"]["facets"]
        print(f"\n{name}: {n:,} facets, {path.stat().st_size / 2**20:.0f} MiB"
              f"{'' if res['check'].get('watertight') else ' (not watertight)'}")
        print(f"  {'measurement':40s} {'time (s)':>9s} {'peak RSS (MiB)':>15s}   runs (s)")
        for kind, label in KINDS:
            r = res[kind]
            runs = " ".join(f"{s:.2f}" for s in r["all_seconds"])
            print(f"  {label:40s} {r['seconds']:9.2f} {r['peak_mb']:15.0f}   {runs}")
        floor = res["numpy-stl"]["seconds"]
        ratio = res["load"]["seconds"] / floor
        raw_ratio = res["load"]["seconds"] / res["numpy-stl-raw"]["seconds"]
        tm_ratio = res["trimesh"]["seconds"] / res["load"]["seconds"]
        for label, value in (("load / numpy-stl from_file (defaults)", ratio),
                             ("load / numpy-stl bare read (no normals)", raw_ratio),
                             ("trimesh.load / slicelab.load", tm_ratio)):
            print(f"  {label:40s} {value:8.2f}x")
        if n >= 4_000_000:
            ok_load = ratio <= LOAD_RATIO_TARGET
            ok_check = res["check"]["seconds"] < CHECK_SECONDS_TARGET
            print(f"  target: load <= {LOAD_RATIO_TARGET:.2f}x numpy-stl from_file: {ratio:.2f}x  "
                  f"{benchlib.mark(ok_load)}")
            print(f"  target: check < {CHECK_SECONDS_TARGET:.0f} s: {res['check']['seconds']:.2f} s  "
                  f"{benchlib.mark(ok_check)}")
            if not ok_load:
                misses.append(f"{name}: load")
            if not ok_check:
                misses.append(f"{name}: check")
    print(f"\n{'all targets met' if not misses else 'targets missed: ' + ', '.join(misses)}")
    return 0  # a missed target is reported, not an error: the numbers are noisy


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == benchlib.CHILD_FLAG:
        child(*sys.argv[2:])
    else:
        with benchlib.docs_output("bench_io", "--docs" in sys.argv[1:]):
            raise SystemExit(main())
