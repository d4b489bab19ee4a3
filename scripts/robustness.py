"""Cut every real mesh in ../shared/meshes by random planes; count the parts closed on disk.

For each file: `load` (a refusal is counted with its reason), `check`; a mesh
that is not watertight with consistent windings is given to `repair` (CAD float noise, duplicates,
windings), and one that is still open is refused for cutting with the
reason. Every watertight mesh is cut by `--planes` random planes through its
bounding box; both parts are written as STL with `write_mesh` and read back,
and a part counts as closed when the file checks watertight.

    python scripts/robustness.py [--planes 5] [--root ../shared/meshes] [--seed 0]
    python scripts/robustness.py --slice [--preview] [--root ../shared/meshes/defects]

``--slice`` instead runs `slicelab slice FILE --fill-holes` (the command line, one process, a
bed large enough for every file) on every mesh and counts what a user would meet: printed (exit 0,
G-code with layers on disk), refused (exit 2 with a one-line error) and failed (anything else,
with its last line). With ``--preview`` the slices run on all cores with their previews, and a
file counts as printed only with an SVG per layer of its G-code and the PNG on disk. Cost: each
file's slice, linear in its layers.

Prints one line per file, the totals, and one line per part not closed on
disk with its cause: not closed in memory already (the cut) or lost in the
float32 rounding (the writing). Cost grows with the total facet
count times the planes (each cut is linear in the facets).
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import slicelab  # noqa: E402
from slicelab.export import write_mesh  # noqa: E402
from slicelab.mesh import MeshFileError  # noqa: E402


def _cause(part, on_disk, out) -> str:
    """Why a part is not closed on disk: not closed in memory already (the cut), or lost in float32."""
    in_memory = slicelab.check(part)
    edges = (f"{on_disk.n_open_edges} open, {on_disk.n_nonmanifold_edges} non-manifold edges on disk "
             f"({out.n_collapsed} facets collapsed, {out.n_moved} vertices moved in float32)")
    if not in_memory.watertight:
        return (f"not closed in memory already ({in_memory.n_open_edges} open, "
                f"{in_memory.n_nonmanifold_edges} non-manifold edges: the cut, not the writing); " + edges)
    return "watertight in memory, not in float32 (the writing): " + edges


def _slice_all(files: list, root: Path, preview: bool = False) -> int:
    """`slicelab slice --fill-holes` on every file: printed, refused in one line, or failed (with
    `preview`, on all cores with its previews: printed only with an SVG per layer and the PNG)."""
    import shutil
    import subprocess
    counts = {"printed": 0, "refused": 0, "failed": 0}
    failures, refusals = [], {}
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for path in files:  # over files
            rel = path.relative_to(root)
            out, shown = Path(tmp) / "part.gcode", Path(tmp) / "preview"
            out.unlink(missing_ok=True)
            shutil.rmtree(shown, ignore_errors=True)
            extra = ["--preview", str(shown)] if preview else ["--workers", "1"]
            r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(path), "-o", str(out), "--fill-holes",
                                "--bed-size", "2000x2000", "--max-height", "2000", *extra],
                               capture_output=True, text=True, cwd=ROOT)
            lines = r.stderr.strip().splitlines()
            layers = out.read_text().count(";LAYER_CHANGE") if r.returncode == 0 and out.exists() else 0
            drawn = len(list(shown.glob("layer_*.svg"))) if preview else layers
            if layers and (drawn != layers or (preview and not (shown / "preview.png").exists())):
                lines = [f"{drawn} layer SVGs for {layers} layers" + ("" if (shown / "preview.png").exists()
                                                                       else ", no preview.png")]
                r.returncode = -1
            if r.returncode == 0 and layers:
                kind, say = "printed", next((x for x in r.stdout.splitlines() if x.startswith("repair:")), "")
            elif r.returncode == 2 and len([x for x in lines if "error:" in x]) == 1 and not out.exists():
                kind, say = "refused", lines[-1].split(": ", 3)[-1]
                cause = say.split(":")[0].split(" (")[0]
                refusals[cause] = refusals.get(cause, 0) + 1
            else:
                kind, say = "failed", f"exit {r.returncode}: " + (lines[-1] if lines else "")
                failures.append(f"{rel}: {say}")
            counts[kind] += 1
            print(f"{rel}: {kind}" + (f": {say}" if say else ""))
    print()
    print(f"robustness --slice: {len(files)} files in {time.perf_counter() - t0:.1f} s; {counts['printed']} printed, "
          f"{counts['refused']} refused in one line, {counts['failed']} failed")
    for cause, n in sorted(refusals.items()):
        print(f"robustness --slice: refused {n} x {cause}")
    for line in failures:
        print("robustness --slice: failed: " + line)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=ROOT.parent / "shared" / "meshes")
    ap.add_argument("--planes", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--max-facets", type=int, default=2_000_000, help="skip larger files")
    ap.add_argument("--slice", action="store_true", help="slice every file (--fill-holes) instead of cutting")
    ap.add_argument("--preview", action="store_true", help="with --slice: on all cores, previews drawn and counted")
    ap.add_argument("--keep", type=Path, default=None,
                    help="save the float64 triangles of each part not closed on disk here (.npy)")
    args = ap.parse_args(argv)
    if not args.root.is_dir():
        print(f"robustness: {args.root} is not there; nothing to do")
        return 0
    rng = np.random.default_rng(args.seed)
    files = sorted(p for p in args.root.rglob("*") if p.is_file() and p.suffix.lower() == ".stl")
    if args.slice:
        return _slice_all(files, args.root, args.preview)
    totals = dict(files=0, refused=0, repaired=0, open_input=0, cuts=0, parts=0, closed=0, noted=0)
    reasons: dict[str, int] = {}
    failures: list[str] = []
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for path in files:  # over files
            totals["files"] += 1
            rel = path.relative_to(args.root)
            try:
                mesh = slicelab.load(path)
            except MeshFileError as exc:
                totals["refused"] += 1
                why = str(exc).split(": ", 1)[-1]
                reasons[why.split(" (")[0]] = reasons.get(why.split(" (")[0], 0) + 1
                print(f"{rel}: refused: {why}")
                continue
            if len(mesh) > args.max_facets:
                print(f"{rel}: skipped ({len(mesh)} facets)")
                continue
            report = slicelab.check(mesh)
            state = "watertight"
            if not (report.watertight and report.winding_consistent):
                fixed = slicelab.repair(mesh)
                after = slicelab.check(fixed.mesh)
                if after.watertight and after.winding_consistent:
                    totals["repaired"] += 1
                    mesh, state = fixed.mesh, "repaired (" + "; ".join(fixed.report.changes()) + ")"
                else:
                    totals["open_input"] += 1
                    print(f"{rel}: not cut: {after.n_open_edges} open, {after.n_nonmanifold_edges} non-manifold "
                          f"and {after.n_misoriented_edges} misoriented edges remain after repair")
                    continue
            lo, hi = mesh.bounds
            closed = parts = noted = 0
            for k in range(args.planes):  # over planes
                normal = rng.normal(size=3)
                origin = lo + rng.uniform(0.2, 0.8, 3) * (hi - lo)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = slicelab.cut(mesh, origin, normal)
                noted += any(c.notes for c in (res.report.rear_cap, res.report.front_cap))
                for side, part in (("rear", res.rear), ("front", res.front)):
                    if len(part) == 0:
                        continue
                    parts += 1
                    out = write_mesh(part, Path(tmp) / f"{side}.stl")
                    on_disk = slicelab.check(slicelab.load(out.path))
                    closed += on_disk.watertight
                    if not on_disk.watertight:
                        why = _cause(part, on_disk, out)
                        failures.append(f"{rel} cut {k} {side}: {why}")
                        if args.keep is not None:
                            args.keep.mkdir(parents=True, exist_ok=True)
                            np.save(args.keep / f"{rel.as_posix().replace('/', '__')}_{k}_{side}.npy",
                                    part.triangles)
            totals["cuts"] += args.planes
            totals["parts"] += parts
            totals["closed"] += closed
            totals["noted"] += noted
            print(f"{rel}: {state}; {closed}/{parts} parts closed on disk"
                  + (f"; {noted} cuts with self-intersecting loops (closed, noted)" if noted else ""))
    print()
    print(f"robustness: {totals['files']} files in {time.perf_counter() - t0:.1f} s; "
          f"{totals['refused']} refused by load, {totals['repaired']} repaired to watertight, "
          f"{totals['open_input']} still open after repair (not cut)")
    print(f"robustness: {totals['cuts']} cuts, {totals['closed']}/{totals['parts']} parts closed on disk, "
          f"{totals['noted']} cuts through self-intersecting loops")
    for line in failures:
        print("robustness: not closed on disk: " + line)
    if reasons:
        print("robustness: refusals: " + "; ".join(f"{n} x {r}" for r, n in sorted(reasons.items())))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
