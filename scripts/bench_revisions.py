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

    python scripts/bench_revisions.py REV [--repeat 3] [--mesh FILE ...]
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


def timed(cmd: list[str], tree: Path) -> float:
    """Wall time of a command run with `tree`'s slicelab first on the path."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(tree)
    t = time.perf_counter()
    r = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True)
    if r.returncode:
        raise SystemExit(f"{tree}: {' '.join(cmd[3:5])} failed:\n{r.stderr[-2000:]}")
    return time.perf_counter() - t


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rev", help="the revision to compare with (a commit, a tag, HEAD~3, ...)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--mesh", type=Path, action="append", help="a part to run instead of the set (repeatable)")
    args = ap.parse_args(argv)
    parts = [(m.name, m, None, False) for m in args.mesh] if args.mesh else PARTS
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
            for name, tree in trees.items():  # untimed: bytecode and caches, as a user's second run
                timed(slice_command(mesh, outs[name], scale, support), tree)
            for _ in range(args.repeat):
                for name, tree in trees.items():
                    runs[name].append(timed(slice_command(mesh, outs[name], scale, support), tree))
            same = outs["this tree"].read_bytes() == outs[args.rev].read_bytes()
            med = {name: statistics.median(ts) for name, ts in runs.items()}
            print(f"{label:<16}" + "".join(f"{name}: {min(ts):6.2f} / {med[name]:6.2f}   " for name, ts in runs.items())
                  + f"ratio {med['this tree'] / med[args.rev]:.2f}   G-code {'same' if same else 'DIFFERS'}")
    finally:
        subprocess.run(["git", "worktree", "remove", "--force", str(other)], cwd=ROOT, capture_output=True)
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
