"""Installing slicelab as a user does: ``pip install`` into a fresh venv, then the first and the second
``slicelab slice`` of a 20 mm cube, beside the repository's ``make`` build.

Everything happens in a temporary folder, removed at the end (``--keep`` keeps it): a clone of the
repository's last commit (``--worktree``: the files of the work tree instead, changes included), a
fresh venv per row, the cube (``slicelab.samples.box``, 12 facets) and the G-code. The rows:

- ``pip install`` of the clone: the wheel built with its compiled kernels (setup.py), as a user
  gets it where numba and a C compiler are at hand;
- ``pip install`` with ``SLICELAB_BUILD_KERNELS=0``: a pure wheel, the kernels compiled by numba
  on first use (the line saying so is shown) and cached in the user's cache folder;
- each of the two again as another user (``nobody``, where this runs as root and ``setpriv`` is
  at hand) who cannot write the installation: a read-only site-packages, numba's cache in that
  user's own cache folder;
- ``make``: the repository's own .venv, ``make .venv/.kernels`` timed (nothing to do when it is up
  to date: the install time of make's build is then not measured), then the same two runs.

Each slice runs as a command from a cold process; a row's runs start with an empty user cache
(``XDG_CACHE_HOME`` in the temporary folder), pip with the user's own download cache. Prints one
table with the seconds, what ``slicelab --version`` says of the kernels, and the first run's ratio
to make's.

Usage: ``python scripts/bench_install.py [--worktree] [--skip-jit] [--skip-make] [--keep]``
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from benchlib import ROOT, docs_output, machine_facts  # noqa: E402

NOBODY = 65534


def timed(cmd: list, *, env: dict | None = None, cwd: Path | None = None, check: bool = True):
    """Run `cmd`; its wall-clock seconds and the finished process (stdout and stderr as text)."""
    t0 = time.perf_counter()
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, env=env, cwd=cwd)
    seconds = time.perf_counter() - t0
    if check and r.returncode != 0:
        sys.exit(f"bench_install: {' '.join(map(str, cmd))} failed ({r.returncode}):\n{r.stdout[-2000:]}\n{r.stderr[-3000:]}")
    return seconds, r


def source_tree(tmp: Path, worktree: bool) -> Path:
    """The repository as a user would fetch it: a clone of HEAD, or the work tree's files."""
    src = tmp / "src"
    if not worktree:
        timed(["git", "clone", "-q", "--no-hardlinks", ROOT, src])
        return src
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    for name in filter(None, files.decode().split("\0")):
        if (ROOT / name).is_file():
            (src / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, src / name)
    return src


def user_env(home: Path) -> dict:
    """The environment of a user whose cache folder is `home`/cache, empty at first."""
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "SLICELAB_JIT", "PYTHONPATH")}
    env["XDG_CACHE_HOME"] = str(home / "cache")
    return env


def as_nobody(cmd: list) -> list | None:
    """`cmd` run as the user nobody (root and setpriv needed), else None."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0 or not shutil.which("setpriv"):
        return None
    return ["setpriv", f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups", *cmd]


def slice_runs(bin_dir: Path, cube: Path, home: Path, *, nobody: bool = False) -> dict:
    """The first and the second ``slicelab slice`` of the cube, and what --version says before."""
    home.mkdir(parents=True, exist_ok=True)
    env = user_env(home)
    env["HOME"] = str(home)
    wrap = (lambda c: as_nobody(c)) if nobody else (lambda c: c)
    if nobody:
        os.chown(home, NOBODY, NOBODY)
    _, version = timed(wrap([bin_dir / "slicelab", "--version"]), env=env, cwd=home)
    out = {"kernels": kernels_said(version.stdout)}
    for turn in ("first", "second"):
        seconds, r = timed(wrap([bin_dir / "slicelab", "slice", cube, "-o", home / f"{turn}.gcode"]), env=env, cwd=home)
        out[turn] = seconds
        if turn == "first":
            out["said"] = [line for line in r.stderr.splitlines() if line.startswith("slicelab: compiling")]
    return out


def kernels_said(version: str) -> str:
    """--version's account of the kernels, shortened for the table."""
    m = re.search(r"\(compiled kernels: (.*)\)\s*$", version.strip())
    text = m.group(1) if m else version.strip()
    if text.startswith("built ahead of time"):
        return "built ahead of time"
    cached = re.search(r"\(([^()]*cached[^()]*)\)", text)
    return f"numba's ({cached.group(1)})" if cached else text[:60]


def pip_row(tmp: Path, src: Path, name: str, cube: Path, *, build_kernels: bool) -> list:
    """A fresh venv, ``pip install`` of `src`, then the runs (and again as nobody)."""
    venv = tmp / name
    timed([sys.executable, "-m", "venv", venv])
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PIP_REQUIRE_VIRTUALENV")}
    if not build_kernels:
        env["SLICELAB_BUILD_KERNELS"] = "0"
    seconds, r = timed([venv / "bin" / "python", "-m", "pip", "install", "-q", src], env=env, cwd=tmp)
    label = "pip install (wheel with its kernels)" if build_kernels else "pip install, SLICELAB_BUILD_KERNELS=0"
    rows = [(label, seconds, slice_runs(venv / "bin", cube, tmp / f"home-{name}"))]
    if as_nobody(["true"]) is not None:
        rows.append(("  the same, read-only, as nobody", None,
                     slice_runs(venv / "bin", cube, tmp / f"home-{name}-nobody", nobody=True)))
    return rows


def make_row(cube: Path, tmp: Path) -> list:
    """The repository's own .venv after ``make .venv/.kernels`` (timed), then the runs."""
    seconds, r = timed(["make", "-C", ROOT, ".venv/.kernels"])
    nothing = "Nothing to be done" in r.stdout or "is up to date" in r.stdout
    label = "make (the repository's .venv" + (", already built)" if nothing else ")")
    return [(label, None if nothing else seconds, slice_runs(ROOT / ".venv" / "bin", cube, tmp / "home-make"))]


def table(rows: list) -> str:
    """The rows as text, with each first run's ratio to make's."""
    make = next((runs["first"] for label, _, runs in rows if label.startswith("make")), None)
    head = f"{'how installed':<46} {'install s':>9} {'first s':>8} {'second s':>8} {'first/make':>10}  kernels (--version)"
    lines = [head, "-" * len(head)]
    for label, install, runs in rows:
        ratio = f"{runs['first'] / make:.1f}x" if make else "-"
        lines.append(f"{label:<46} {'-' if install is None else f'{install:.1f}':>9} {runs['first']:>8.2f} "
                     f"{runs['second']:>8.2f} {ratio:>10}  {runs['kernels']}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--worktree", action="store_true", help="install the work tree's files, not a clone of HEAD")
    parser.add_argument("--skip-jit", action="store_true", help="leave out the pure wheel (numba on first use)")
    parser.add_argument("--skip-make", action="store_true", help="leave out the repository's make build")
    parser.add_argument("--keep", action="store_true", help="keep the temporary folder (its path is printed)")
    parser.add_argument("--docs", action="store_true", help="also write the table to docs/performance/tables/")
    args = parser.parse_args(argv)

    tmp = Path(tempfile.mkdtemp(prefix="bench_install_"))
    tmp.chmod(0o755)  # (read by the user nobody in the read-only rows)
    try:
        with docs_output("bench_install", args.docs):
            print("bench_install: slicelab installed from a fresh venv, then `slicelab slice` of a 20 mm cube twice")
            src = source_tree(tmp, args.worktree)
            commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                                    text=True).stdout.strip()
            print(f"source: {'the work tree' if args.worktree else 'a clone'} of {ROOT} at {commit}")
            cube = tmp / "cube.stl"
            timed([sys.executable, "-c", "import sys, slicelab; from slicelab.samples import box; "
                   "slicelab.save(box((0, 0, 0), (20, 20, 20)), sys.argv[1])", cube])
            cube.chmod(0o644)
            rows = pip_row(tmp, src, "venv-built", cube, build_kernels=True)
            if not args.skip_jit:
                rows += pip_row(tmp, src, "venv-jit", cube, build_kernels=False)
            if not args.skip_make:
                rows += make_row(cube, tmp)
            print(table(rows))
            said = next((runs["said"][0] for _, _, runs in rows if runs.get("said")), None)
            print(f"said on the first run that compiled: {said}" if said else
                  "said on stderr on a first run: nothing (no run compiled)")
            facts = machine_facts()
            print(f"machine: {facts['machine']}; {facts['date']}")
    finally:
        if args.keep:
            print(f"kept {tmp}")
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
