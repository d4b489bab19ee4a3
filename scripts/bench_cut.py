"""Benchmark watertight cuts: slicelab.cut beside trimesh and manifold3d on the 1M torus and the 5M pot.

    .venv/bin/python scripts/bench_cut.py

Each measurement runs once, in a fresh child process (scripts/benchlib.py),
on a mesh loaded beforehand with ``slicelab.load`` (loading is not counted).
Every tool starts from the same triangle soup and ends with both closed parts
as triangle soups, so each is counted *with its mesh building*:

1. slicelab: ``cut(mesh, origin, normal)`` -> ``Cut`` (its ``rear`` and ``front`` Meshes);
2. trimesh: ``Trimesh(vertices, faces)`` (merges vertices) and
   ``slice_plane(..., cap=True)`` on both sides, ``.triangles`` of each;
3. manifold3d: exact weld (``slicelab.geometry.topology.weld``), ``Mesh64`` ->
   ``Manifold``, ``split_by_plane``, ``to_mesh64`` of both parts.

Each tool's parts are then checked with ``slicelab.check`` (exact welding):
watertight (no open or non-manifold edge) with consistent winding, and their
volumes added up. Planes: the torus by a tilted plane, the pot by z = 60,
which holds a whole ring of 7,500 vertex corners (a degenerate cut).

Then the command as a user runs it, ``python -m slicelab cut FILE --origin
.. --normal .. -o DIR`` with its defaults (the exploded preview included,
both parts written as STL and checked as written), and again with
``--no-preview``: wall-clock time with start-up and imports, the preview's
share, and whether both files read back watertight.

Targets: faster than trimesh, within 2x of manifold3d, always
watertight where trimesh is not; the preview a small share of the command.
One run each on a shared machine: noisy. Every step is linear in the facets.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import benchlib  # noqa: E402

CASES = [
    ("torus_1m.stl", (0.0, 0.0, 1.234), (0.3, 0.2, 1.0)),
    ("pot_5m.stl", (0.0, 0.0, 60.0), (0.0, 0.0, 1.0)),
]
TOOLS = ("slicelab", "trimesh", "manifold3d")


def _verdict(parts) -> dict:
    import numpy as np

    from slicelab import Mesh, check
    out = {"facets": [], "volumes": [], "watertight": []}
    for t in parts:
        r = check(Mesh(np.asarray(t, dtype=np.float64).reshape(-1, 3, 3)))
        out["facets"].append(r.n_facets)
        out["volumes"].append(r.volume)
        out["watertight"].append(bool(r.watertight and r.winding_consistent and r.n_facets > 0))
    return out


def child(tool: str, path: str, origin: str, normal: str) -> None:
    import numpy as np

    import slicelab
    o = np.array([float(v) for v in origin.split(",")])
    n = np.array([float(v) for v in normal.split(",")])
    mesh = slicelab.load(path)
    soup = mesh.triangles
    if tool == "slicelab":
        import warnings
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = slicelab.cut(mesh, o, n)
        seconds = time.perf_counter() - t0
        parts = (result.rear.triangles, result.front.triangles)
    elif tool == "trimesh":
        import trimesh
        t0 = time.perf_counter()
        tm = trimesh.Trimesh(vertices=soup.reshape(-1, 3), faces=np.arange(3 * len(soup)).reshape(-1, 3))
        try:
            rear = tm.slice_plane(o, -n, cap=True)
            front = tm.slice_plane(o, n, cap=True)
        except Exception as exc:  # a failure is a result too
            benchlib.child_report(time.perf_counter() - t0, tool=tool, input_facets=len(soup),
                                  input_volume=slicelab.check(mesh).volume,
                                  error=f"{type(exc).__name__}: {str(exc).splitlines()[0][:120]}")
            return
        parts = (rear.triangles, front.triangles)
        seconds = time.perf_counter() - t0
    else:
        import manifold3d as mf

        from slicelab.geometry.topology import weld
        t0 = time.perf_counter()
        v, f = weld(soup)
        solid = mf.Manifold(mf.Mesh64(vert_properties=v, tri_verts=f.astype(np.uint64)))
        u = n / np.linalg.norm(n)
        ahead, behind = solid.split_by_plane(u, float(u @ o))
        parts = []
        for part in (behind, ahead):
            m = part.to_mesh64()
            parts.append(np.asarray(m.vert_properties)[:, :3][np.asarray(m.tri_verts)])
        seconds = time.perf_counter() - t0
    benchlib.child_report(seconds, tool=tool, input_facets=len(soup), input_volume=slicelab.check(mesh).volume,
                          **_verdict(parts))


def main() -> int:
    if len(sys.argv) > 2 and sys.argv[1] == benchlib.CHILD_FLAG:
        child(*sys.argv[2:])
        return 0
    # No options: `--help` prints the docstring before data/large/ is written or anything is timed.
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    benchlib.ensure_large_data()
    script = str(Path(__file__).resolve())
    print("bench_cut: watertight cut into two capped parts; slicelab vs trimesh slice_plane(cap=True) on both "
          "sides vs manifold3d split_by_plane (each with its mesh building; one run each, warm page cache)")
    print(getattr(benchlib, "NOISE_NOTE", "shared 2-core machine: times are noisy"))
    ok = True
    for name, origin, normal in CASES:
        path = benchlib.LARGE / name
        benchlib.warm(path)
        res = {t: benchlib.run_child(script, t, str(path), ",".join(map(str, origin)), ",".join(map(str, normal)))
               for t in TOOLS}
        ours = res["slicelab"]
        print(f"\n{name}: {ours['input_facets']:,} facets, plane origin {origin} normal {normal}")
        print(f"  {'tool':<11} {'time (s)':>9} {'x ours':>7} {'peak MB':>8}  {'rear facets':>11} {'front facets':>12}"
              f"  watertight   volume error")
        for t in TOOLS:
            r = res[t]
            if "error" in r:
                print(f"  {t:<11} {r['seconds']:9.3f} {'':>7} {r['peak_mb']:8.0f}  failed: {r['error']}")
                r["watertight"] = [False, False]
                continue
            err = (sum(r["volumes"]) - r["input_volume"]) / abs(r["input_volume"])
            wt = "/".join("yes" if w else "NO" for w in r["watertight"])
            print(f"  {t:<11} {r['seconds']:9.3f} {r['seconds'] / ours['seconds']:7.2f} {r['peak_mb']:8.0f}  "
                  f"{r['facets'][0]:11,d} {r['facets'][1]:12,d}  {wt:<10} {err:+.1e}")
        # A tool that failed is slower than one that finished.
        faster = ours["seconds"] < res["trimesh"]["seconds"] or "error" in res["trimesh"]
        within = ours["seconds"] <= 2 * res["manifold3d"]["seconds"]
        tight = all(ours["watertight"])
        print(f"  faster than trimesh: {benchlib.mark(faster)} ({res['trimesh']['seconds'] / ours['seconds']:.1f}x); "
              f"within 2x of manifold3d: {benchlib.mark(within)} "
              f"(ours / manifold3d = {ours['seconds'] / res['manifold3d']['seconds']:.2f}); "
              f"our parts watertight: {benchlib.mark(tight)}; "
              f"trimesh's: {'/'.join('yes' if w else 'NO' for w in res['trimesh']['watertight'])}")
        ok &= faster and within and tight
        ok &= _command(path, origin, normal)
    return 0 if ok else 1


def _command(path, origin, normal) -> bool:
    """The default command and the one without preview; the parts read back from disk."""
    import tempfile

    import slicelab
    runs = {}
    for label, extra in (("defaults", ()), ("--no-preview", ("--no-preview",))):
        with tempfile.TemporaryDirectory(dir=benchlib.LARGE) as out:
            seconds, peak, _ = benchlib.run_command("cut", path, "--origin", ",".join(map(str, origin)),
                                                    "--normal", ",".join(map(str, normal)), "-o", out, *extra)
            tight = all(slicelab.check(slicelab.load(Path(out) / f"{n}.stl")).watertight for n in ("rear", "front"))
        runs[label] = (seconds, peak, tight)
    (s0, p0, t0), (s1, _, t1) = runs["defaults"], runs["--no-preview"]
    share = max(s0 - s1, 0.0)
    print(f"  python -m slicelab cut (defaults): {s0:.2f} s wall, peak {p0:.0f} MiB; --no-preview {s1:.2f} s; "
          f"the preview costs {share:.2f} s ({100 * share / s0:.0f} %); both files watertight as read back: "
          f"{benchlib.mark(t0 and t1)}")
    return t0 and t1


if __name__ == "__main__":
    raise SystemExit(main())
