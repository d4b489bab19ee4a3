"""Benchmark depth segmentation: split the 5M-facet pot through its axis, end to end.

    .venv/bin/python scripts/bench_split.py

The diary of cutting a scanned pot split a 4.85 M-facet scan in 86 s (pattern e only). Here,
in fresh child processes, on data/large/pot_5m.stl (5,005,000 facets) and the
vertical plane through the pot's axis (origin 0,0,60, normal 0,-1,0: the
front and back halves of the vessel, the profile as the section):

1. slicelab, in process: ``load`` + ``split`` + ``save`` front.stl and
   rear.stl + ``Section.to_svg``, timed inside the child (imports not counted),
   with the stages printed;
2. slicelab, the real command as a user runs it, ``python -m slicelab split``
   with its defaults (the preview PNG included), and again with
   ``--no-preview``, timed from outside as wall-clock time of the whole
   process (interpreter start-up and imports included); the difference is the
   preview's share;
3. trimesh: ``trimesh.load`` + ``Trimesh.slice_plane`` on both sides (no
   files written), timed inside its child.

Sanity check: the areas of both sides against trimesh's. Times are from one
run on a shared machine (noisy). Targets: end to end <= 3 s, >= 5x faster
than trimesh, peak memory under 3 GB.
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import benchlib  # noqa: E402

ORIGIN = (0.0, 0.0, 60.0)
NORMAL = (0.0, -1.0, 0.0)
TARGET_SECONDS = 3.0
TARGET_RATIO = 5.0
TARGET_PEAK_MB = 3 * 1024.0
TARGET_PREVIEW = 0.5


def _area(triangles) -> float:
    import numpy as np
    t = np.asarray(triangles, dtype=np.float64)
    return float(0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum())


def child_ours(path: str) -> None:
    import slicelab
    with tempfile.TemporaryDirectory(dir=benchlib.ROOT / "data" / "large") as out:
        out = Path(out)
        t0 = time.perf_counter()
        mesh = slicelab.load(path)
        t1 = time.perf_counter()
        s = slicelab.split(mesh, ORIGIN, NORMAL)
        t2 = time.perf_counter()
        slicelab.save(s.front, out / "front.stl")
        slicelab.save(s.rear, out / "rear.stl")
        t3 = time.perf_counter()
        s.section.to_svg(out / "section.svg")
        t4 = time.perf_counter()
        sizes = {p.name: p.stat().st_size for p in out.iterdir()}
    benchlib.child_report(t4 - t0, load=t1 - t0, split=t2 - t1, write_stl=t3 - t2, write_svg=t4 - t3,
                          facets=len(mesh), n_front=s.n_front, n_cut=s.n_cut, n_rear=s.n_rear,
                          front=len(s.front), rear=len(s.rear), segments=len(s.section.segments),
                          loops=len(s.section.loops), section_area=s.section.area,
                          front_area=_area(s.front.triangles), rear_area=_area(s.rear.triangles),
                          bytes=sizes)


def child_trimesh(path: str) -> None:
    import numpy as np
    import trimesh
    t0 = time.perf_counter()
    tm = trimesh.load(path)
    t1 = time.perf_counter()
    front = tm.slice_plane(ORIGIN, NORMAL)
    rear = tm.slice_plane(ORIGIN, -np.asarray(NORMAL))
    t2 = time.perf_counter()
    benchlib.child_report(t2 - t0, load=t1 - t0, slice=t2 - t1, facets=len(tm.faces),
                          front=len(front.faces), rear=len(rear.faces),
                          front_area=float(front.area), rear_area=float(rear.area))


def _cli_peak(path: Path, *extra: str) -> tuple[float, float, str]:
    """Wall-clock time and peak memory of the real command, run as a user would."""
    with tempfile.TemporaryDirectory(dir=benchlib.ROOT / "data" / "large") as out:
        return benchlib.run_command("split", path, "--origin", ",".join(map(str, ORIGIN)),
                                    "--normal", ",".join(map(str, NORMAL)), "-o", out, *extra)


def main() -> int:
    if len(sys.argv) > 2 and sys.argv[1] == benchlib.CHILD_FLAG:
        {"ours": child_ours, "trimesh": child_trimesh}[sys.argv[2]](*sys.argv[3:])
        return 0
    # No options: `--help` prints the docstring before data/large/ is written or anything is timed.
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    benchlib.ensure_large_data()
    script = str(Path(__file__).resolve())
    pot = benchlib.LARGE / "pot_5m.stl"
    print("bench_split: depth segmentation of the 5M pot, slicelab vs trimesh "
          "(one run each; warm page cache)")
    print(benchlib.NOISE_NOTE)
    print(f"plane: origin {ORIGIN}, normal {NORMAL} (through the pot's axis)")
    benchlib.warm(pot)

    ours = benchlib.run_child(script, "ours", str(pot))
    cli_s, cli_mb, cli_out = _cli_peak(pot)
    bare_s, bare_mb, _ = _cli_peak(pot, "--no-preview")
    theirs = benchlib.run_child(script, "trimesh", str(pot))
    share = max(cli_s - bare_s, 0.0)

    print(f"\n{pot.name}: {ours['facets']:,} facets -> front {ours['n_front']:,} / cut {ours['n_cut']:,} / "
          f"rear {ours['n_rear']:,} (front.stl {ours['front']:,} facets, rear.stl {ours['rear']:,}); "
          f"section {ours['segments']:,} segments, {ours['loops']} loop(s), {ours['section_area']:.6g} mm2")
    print(f"  {'slicelab load+split+save x2+svg (in process)':46s} {ours['seconds']:6.2f} s  "
          f"(load {ours['load']:.2f}, split {ours['split']:.2f}, write STLs {ours['write_stl']:.2f}, "
          f"SVG {ours['write_svg']:.3f})  peak RSS {ours['peak_mb']:5.0f} MiB")
    print(f"  {'python -m slicelab split (defaults, wall)':46s} {cli_s:6.2f} s  "
          f"(start-up and imports included)  peak RSS {cli_mb:5.0f} MiB")
    print(f"  {'python -m slicelab split --no-preview (wall)':46s} {bare_s:6.2f} s  "
          f"peak RSS {bare_mb:5.0f} MiB; the preview PNG costs {share:.2f} s "
          f"({100 * share / cli_s:.0f} % of the default command)")
    print(f"  {'trimesh load + slice_plane both sides':46s} {theirs['seconds']:6.2f} s  "
          f"(load {theirs['load']:.2f}, slice_plane x2 {theirs['slice']:.2f})  "
          f"peak RSS {theirs['peak_mb']:5.0f} MiB")
    for line in cli_out.splitlines():
        print(f"    | {line}")
    ratio = theirs["seconds"] / ours["seconds"]
    rel = max(abs(ours["front_area"] - theirs["front_area"]) / theirs["front_area"],
              abs(ours["rear_area"] - theirs["rear_area"]) / theirs["rear_area"])
    print(f"  sanity: areas front {ours['front_area']:.6f} / rear {ours['rear_area']:.6f} mm2 vs trimesh "
          f"{theirs['front_area']:.6f} / {theirs['rear_area']:.6f}: worst relative difference {rel:.1e} "
          f"{'OK' if rel < 1e-9 else 'DISAGREE'}")
    print(f"\n  end to end <= {TARGET_SECONDS:g} s: in process {ours['seconds']:.2f} s, "
          f"command {cli_s:.2f} s  {benchlib.mark(max(ours['seconds'], cli_s) <= TARGET_SECONDS)}")
    print(f"  preview <= {TARGET_PREVIEW:g} s: {share:.2f} s  {benchlib.mark(share <= TARGET_PREVIEW)}")
    print(f"  >= {TARGET_RATIO:g}x faster than trimesh: {ratio:.1f}x  {benchlib.mark(ratio >= TARGET_RATIO)}")
    peak = max(ours["peak_mb"], cli_mb)
    print(f"  peak memory < {TARGET_PEAK_MB / 1024:g} GB: {peak:.0f} MiB  "
          f"{benchlib.mark(peak < TARGET_PEAK_MB)}")
    print(f"  (the diary: 86 s for 4.85 M facets, pattern e only; {86 / ours['seconds']:.0f}x that)")
    print(json.dumps({"bench": "split", "seconds": ours["seconds"], "command_seconds": cli_s,
                      "no_preview_seconds": bare_s, "preview_seconds": share,
                      "trimesh_seconds": theirs["seconds"], "ratio": ratio, "peak_mb": peak}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
