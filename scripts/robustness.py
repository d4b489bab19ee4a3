"""Cut every real mesh in ../shared/meshes by random planes; count the parts closed on disk.

For each file: `load` (a refusal is counted with its reason), `check`; a mesh
that is not watertight with consistent windings is given to `repair` (CAD float noise, duplicates,
windings), and one that is still open is refused for cutting with the
reason. Every watertight mesh is cut by `--planes` random planes through its
bounding box; both parts are written as STL with `write_mesh` and read back,
and a part counts as closed when the file checks watertight.

    python scripts/robustness.py [--planes 5] [--root ../shared/meshes] [--seed 0]
    python scripts/robustness.py --slice [--check] [--scales 0.5,1,2.5] [--turns 0,30] [--jobs 2]
    python scripts/robustness.py --slice --preview [--root ../shared/meshes/defects]

``--slice`` instead runs `slicelab slice` (the command line, as a user runs it, defaults and all)
on every mesh file (STL, PLY, OBJ, 3MF) at each scale of ``--scales`` and each turn about z of
``--turns`` (degrees; a turned copy is written as STL first) on a 400 mm printer, and counts what
a user would meet: printed (exit 0, G-code with layers on disk), refused (exit 2 with a one-line
error; a refusal that names ``--fill-holes`` is retried with it, as its user would), failed
(anything else, with its last line) and skipped (larger than the printer). With ``--check``, every
G-code printed is read back by ``scripts/check_gcode.py`` against the part's exact sections, and
its failures are counted and listed. With ``--preview`` the slices draw their previews too, and a
file counts as printed only with an SVG per layer of its G-code and the PNG on disk. Cost: each
file's slice, linear in its layers; ``--jobs`` slices run side by side.

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
sys.path.insert(0, str(ROOT / "scripts"))
import benchlib  # noqa: E402
from slicelab.mesh.written import write_mesh  # noqa: E402
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


#: The printer the sweep slices for (mm): a part larger at some scale is skipped at that scale.
PRINTER = 400.0
_MESH_ENDINGS = (".stl", ".ply", ".obj", ".3mf")


def _variant(path: Path, root: Path, scale: float, turn: float, tmp: Path, preview: bool, check: bool):
    """One slice of `path` at `scale` and `turn`, as a user runs it: (kind, what to say, checker failed)."""
    import shutil
    import subprocess
    work = Path(tempfile.mkdtemp(dir=tmp))
    try:
        source = path
        if turn:
            try:
                mesh = slicelab.load(path)
            except MeshFileError as exc:
                return "refused", str(exc).split(": ", 1)[-1], None
            a = np.radians(turn)
            rot = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1.0]])
            source = work / "turned.stl"
            slicelab.save(slicelab.Mesh(mesh.triangles @ rot.T), source)
        try:
            size = float(np.ptp(slicelab.load(source).bounds, axis=0).max()) * scale
        except MeshFileError as exc:
            return "refused", str(exc).split(": ", 1)[-1], None
        if size > PRINTER:
            return "skipped", f"{size:.0f} mm across", None
        out, shown = work / "part.gcode", work / "preview"
        base = [sys.executable, "-m", "slicelab", "slice", str(source), "-o", str(out), "--scale", f"{scale:g}",
                "--bed-size", f"{PRINTER:g}x{PRINTER:g}", "--max-height", f"{PRINTER:g}",
                *(["--preview", str(shown)] if preview else ["--workers", "1"])]
        flags = []
        for _ in range(2):  # as a user would: once as given, once more with the flag a refusal names
            try:
                r = subprocess.run(base + flags, capture_output=True, text=True, cwd=ROOT, timeout=900)
            except subprocess.TimeoutExpired:
                return "failed", "no answer in 900 s", None
            lines = r.stderr.strip().splitlines()
            if r.returncode == 2 and "--fill-holes" in r.stderr and not flags:
                shutil.rmtree(shown, ignore_errors=True)
                flags = ["--fill-holes"]
                continue
            break
        layers = out.read_text().count(";LAYER_CHANGE") if r.returncode == 0 and out.exists() else 0
        if preview and layers:
            drawn = len(list(shown.glob("layer_*.svg")))
            if drawn != layers or not (shown / "preview.png").exists():
                return "failed", f"{drawn} layer SVGs for {layers} layers" + (
                    "" if (shown / "preview.png").exists() else ", no preview.png"), None
        if r.returncode == 0 and layers:
            say = " ".join(flags)
            failed = None
            if check:
                import check_gcode
                rep = check_gcode.check_gcode(out, source, scale=scale)
                failed = [c for c in rep.checks if c.status == "fail"]
                if failed:
                    say += "; checker: " + "; ".join(f"{c.name} {c.failed} of {c.checked}"
                                                     + (f" (line {c.worst[0][0]}: {c.worst[0][2]})" if c.worst
                                                        else "") for c in failed)
            return "printed", say.strip("; "), failed
        errors = [x for x in lines if "error:" in x]
        if r.returncode == 2 and len(lines) == 1 and len(errors) == 1 and not out.exists():
            return "refused", lines[-1].split(": ", 2)[-1].replace(f"{source}: ", ""), None
        return "failed", f"exit {r.returncode}: " + (lines[-1] if lines else "") + \
            (f" ({len(lines)} lines on stderr)" if len(lines) > 1 else ""), None
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _slice_all(files: list, root: Path, *, scales=(1.0,), turns=(0.0,), preview: bool = False,
               check: bool = False, jobs: int = 1) -> int:
    """`slicelab slice` on every file at every scale and turn: printed, refused in one line, failed,
    skipped; with `check`, each printed G-code read back by `scripts/check_gcode.py`."""
    from concurrent.futures import ThreadPoolExecutor
    sys.path.insert(0, str(ROOT / "scripts"))
    counts = {"printed": 0, "refused": 0, "failed": 0, "skipped": 0, "checker failures": 0}
    failures, refusals, wrong = [], {}, []
    runs = [(path, sc, tu) for path in files for sc in scales for tu in turns]
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(max(1, jobs)) as pool:
        done = pool.map(lambda run: (run, _variant(run[0], root, run[1], run[2], Path(tmp), preview, check)), runs)
        for (path, sc, tu), (kind, say, failed) in done:  # over runs, in order
            label = f"{path.relative_to(root)} x{sc:g} {tu:g}deg"
            counts[kind] += 1
            if kind == "refused":
                cause = say.split(":")[0].split(" (")[0]
                refusals[cause] = refusals.get(cause, 0) + 1
            elif kind == "failed":
                failures.append(f"{label}: {say}")
            if failed:
                counts["checker failures"] += 1
                wrong.append(f"{label}: {say}")
            print(f"{label}: {kind}" + (f": {say}" if say else ""), flush=True)
    print()
    print(f"robustness --slice: {len(files)} files x {len(scales)} scales x {len(turns)} turns = {len(runs)} runs "
          f"in {time.perf_counter() - t0:.0f} s")
    print("| printed | refused in one line | failed | skipped (over 400 mm) | checker failures |")
    print("|---|---|---|---|---|")
    print(f"| {counts['printed']} | {counts['refused']} | {counts['failed']} | {counts['skipped']} | "
          f"{counts['checker failures'] if check else 'not checked'} |")
    for cause, n in sorted(refusals.items(), key=lambda kv: -kv[1]):
        print(f"robustness --slice: refused {n} x {cause}")
    for line in failures:
        print("robustness --slice: failed: " + line)
    for line in wrong:
        print("robustness --slice: checker: " + line)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=ROOT.parent / "shared" / "meshes")
    ap.add_argument("--planes", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--max-facets", type=int, default=2_000_000, help="skip larger files")
    ap.add_argument("--slice", action="store_true", help="slice every file instead of cutting")
    ap.add_argument("--check", action="store_true", help="with --slice: read every G-code back with check_gcode.py")
    ap.add_argument("--scales", default="0.5,1,2.5", help="with --slice: scales, comma-separated")
    ap.add_argument("--turns", default="0,30", help="with --slice: turns about z (degrees), comma-separated")
    ap.add_argument("--jobs", type=int, default=2, help="with --slice: slices side by side")
    ap.add_argument("--preview", action="store_true", help="with --slice: previews drawn and counted")
    ap.add_argument("--keep", type=Path, default=None,
                    help="save the float64 triangles of each part not closed on disk here (.npy)")
    ap.add_argument("--docs", action="store_true",
                    help="also write what is printed, with the machine and date, for the docs' performance pages")
    args = ap.parse_args(argv)
    if not args.root.is_dir():
        print(f"robustness: {args.root} is not there; nothing to do")
        return 0
    rng = np.random.default_rng(args.seed)
    if args.slice:
        files = sorted(p for p in args.root.rglob("*") if p.is_file() and p.suffix.lower() in _MESH_ENDINGS)
        return _slice_all(files, args.root, scales=[float(v) for v in args.scales.split(",")],
                          turns=[float(v) for v in args.turns.split(",")], preview=args.preview, check=args.check,
                          jobs=args.jobs)
    files = sorted(p for p in args.root.rglob("*") if p.is_file() and p.suffix.lower() == ".stl")
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
    with benchlib.docs_output("robustness", "--docs" in sys.argv[1:]):
        raise SystemExit(main())
