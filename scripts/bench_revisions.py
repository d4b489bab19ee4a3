"""`slicelab slice` of this tree against another revision, runs alternating: is a change faster, and is its G-code the same?

This machine's speed drifts by 10-30 % from minute to minute, so two benchmark runs made one
after the other say little about a change of a few per cent. Here the command as users run it
(`python -m slicelab slice` with the `scripts/bench_slice.py` settings, defaults otherwise) runs
from this working tree and from a checkout of REV (a temporary git worktree, its compiled
kernels built once before timing), the two taking turns `--repeat` times per part, and the
minimum and median wall times of each are printed with their ratio. The two G-code files are
compared byte for byte, so a speed-up that changed the output says so. No reference tool:
`scripts/bench_slice.py` compares with PrusaSlicer. Cost: twice a `slicelab slice` per part and
repeat.

``--defects K`` runs instead PrusaSlicer's test parts and the first K meshes (under 4 MB) of each
kind in `../shared/meshes/defects`, with ``--repair``: a change that should not move the output is
checked on real defective inputs too (a refusal counts as the same when both trees refuse with
the same message).

``--preview`` has both trees draw their previews too (an SVG per layer, compared byte for byte
and said apart from the G-code, and a PNG).

    python scripts/bench_revisions.py REV [--repeat 3] [--mesh FILE ...] [--defects K] [--preview]
"""
from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
from bench_slice import LAYER, PARTS, PERIMETERS, SAME_SPEEDS, SOLID, WIDTH, INFILL  # noqa: E402


#: The kernels of a tree compiled once, as `make` does after installing: built ahead of time where the
#: tree can (`slicelab.geometry.compiled`), else compiled by numba into its disk cache.
_BUILD = """
try:
    from slicelab.geometry.compiled import build
except ImportError:
    from slicelab.geometry.kernels import warm as build
build()
"""


def slice_command(mesh: Path, out: Path, scale: float | None, support: bool) -> list[str]:
    """The command line of `scripts/bench_slice.py` for one part (skirt off, a bed large enough)."""
    cmd = [sys.executable, "-m", "slicelab", "slice", str(mesh), "-o", str(out), "--layer-height", str(LAYER),
           "--line-width", str(WIDTH), "--perimeters", str(PERIMETERS), "--infill-density", str(INFILL),
           "--top-layers", str(SOLID), "--bottom-layers", str(SOLID), "--skirt-loops", "0",
           "--bed-size", "1000x1000", "--max-height", "1000"] + SAME_SPEEDS
    if scale is not None:
        import slicelab
        lo, hi = slicelab.load(mesh).bounds
        cmd += ["--scale", f"{scale / float(max(hi - lo)):.6f}"]
    return cmd + (["--support", "auto"] if support else [])


def timed(cmd: list[str], tree: Path, refusals: bool = False) -> tuple[float, str | None]:
    """Wall time of a command run with `tree`'s slicelab first on the path, and its one-line error if it
    refused the input (exit status 2, allowed with `refusals`)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(tree)
    t = time.perf_counter()
    r = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True)
    if r.returncode and not (refusals and r.returncode == 2):
        raise SystemExit(f"{tree}: {' '.join(cmd[3:5])} failed:\n{r.stderr[-2000:]}")
    return time.perf_counter() - t, (r.stderr.strip().splitlines() or [""])[-1] if r.returncode else None


def defect_parts(k: int) -> list:
    """PrusaSlicer's test parts and the first `k` meshes under 4 MB of each kind of defect."""
    shared = ROOT.parent / "shared" / "meshes"
    files = sorted((shared / "prusaslicer").glob("*.stl"))
    for kind in sorted(d for d in (shared / "defects").glob("*") if d.is_dir()):
        files += sorted(f for f in kind.rglob("*.stl") if f.stat().st_size < 4 << 20)[:k]
    return [(f"{f.parent.name}/{f.stem}", f, None, False) for f in files]


def _moves(gcode: bytes) -> bytes:
    """The file without the header's settings (``; name = value`` lines before the first layer): a
    setting added to the settings table adds a line there and changes no move."""
    head, sep, rest = gcode.partition(b";LAYER_CHANGE")
    kept = [line for line in head.split(b"\n") if not (line.startswith(b"; ") and b" = " in line)]
    return b"\n".join(kept) + sep + rest


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rev", help="the revision to compare with (a commit, a tag, HEAD~3, ...)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--mesh", type=Path, action="append", help="a part to run instead of the set (repeatable)")
    ap.add_argument("--defects", type=int, default=0, metavar="K",
                    help="PrusaSlicer's test parts and K meshes of each kind of defect instead, with --repair")
    ap.add_argument("--preview", action="store_true",
                    help="both trees draw the previews too (--preview DIR); their SVGs are compared as well")
    args = ap.parse_args(argv)
    parts = [(m.name, m, None, False) for m in args.mesh] if args.mesh else PARTS
    if args.defects:
        parts = defect_parts(args.defects)
    extra = ["--repair"] if args.defects else []
    tally = {"same": 0, "same but settings added": 0, "refused alike": 0, "DIFFERS": 0, "SVGs differ": 0}
    work = Path(tempfile.mkdtemp(prefix="bench_rev_"))
    other = work / "tree"
    subprocess.run(["git", "worktree", "add", "--detach", str(other), args.rev], cwd=ROOT, check=True,
                   capture_output=True)
    try:
        env = dict(os.environ, PYTHONPATH=str(other))
        subprocess.run([sys.executable, "-c", _BUILD], cwd=other, env=env, check=True)  # as an install does
        trees = {"this tree": ROOT, args.rev: other}
        print(f"{args.repeat} alternating runs per tree and part; wall seconds (min / median); "
              f"ratio = this tree / {args.rev} (medians)")
        for label, mesh, scale, support in parts:
            if not mesh.exists():
                print(f"{label:<16} missing ({mesh}): skipped")
                continue
            runs = {name: [] for name in trees}
            outs = {name: work / f"{i}.gcode" for i, name in enumerate(trees)}
            shown = {name: work / f"{i}_preview" for i, name in enumerate(trees)}

            def command(name):
                cmd = slice_command(mesh, outs[name], scale, support) + extra
                return cmd + (["--preview", str(shown[name])] if args.preview else [])

            refused = {}
            for name, tree in trees.items():  # untimed: bytecode and caches, as a user's second run
                outs[name].unlink(missing_ok=True)
                shutil.rmtree(shown[name], ignore_errors=True)
                refused[name] = timed(command(name), tree, True)[1]
            for _ in range(args.repeat):
                for name, tree in trees.items():
                    runs[name].append(timed(command(name), tree, True)[0])
            drawn = ""
            if any(refused.values()):
                verdict = "refused alike" if refused["this tree"] == refused[args.rev] else "DIFFERS"
            else:
                a, b = (outs[name].read_bytes() for name in trees)
                verdict = "same" if a == b else "same but settings added" if _moves(a) == _moves(b) else "DIFFERS"
                if args.preview:  # every layer's SVG too (the PNG is a picture: not compared)
                    a, b = (sorted(shown[name].glob("*.svg")) for name in trees)
                    svgs = [f.name for f in a] == [f.name for f in b] and \
                        all(x.read_bytes() == y.read_bytes() for x, y in zip(a, b))
                    drawn = ", SVGs same" if svgs else ", SVGs DIFFER"
                    tally["SVGs differ"] += not svgs
            tally[verdict] += 1
            med = {name: statistics.median(ts) if ts else float("nan") for name, ts in runs.items()}
            print(f"{label:<26}" + "".join(f"{name}: {min(ts, default=float('nan')):6.2f} / {med[name]:6.2f}   "
                                           for name, ts in runs.items())
                  + f"ratio {med['this tree'] / med[args.rev]:.2f}   G-code {verdict}{drawn}")
        print("parts: " + ", ".join(f"{v} {k}" for k, v in tally.items()))
    finally:
        subprocess.run(["git", "worktree", "remove", "--force", str(other)], cwd=ROOT, capture_output=True)
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
