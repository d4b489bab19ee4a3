"""Every script in scripts/ runs to the end in its cheapest mode, against the package as it is now,
and prints what its docstring promises.

Each runs as a user runs it: ``python scripts/NAME.py ...`` in a fresh process from the repository's
root. A benchmark's numbers are not checked (they are timings on a shared machine), only that its
tables and headings come out. The benchmarks over data/large/ (``make data-large``: 5M-facet
files, minutes a run) are held to ``--help`` and to their per-measurement child (``--child``, the
calls into slicelab) on a small sample; bench_io.py, the one with a cheap mode over data/large/,
runs it when the files are there and is skipped otherwise.
"""
from __future__ import annotations

import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "scripts"
#: What scripts/benchlib.py's ensure_large_data writes (with make_data.py --large) when any is missing.
LARGE_FILES = ("torus_1m.stl", "torus_5m.stl", "pot_5m.stl")
#: Scripts tested elsewhere or not scripts: the reason.
NOT_HERE = {"benchlib.py": "helpers of the benchmarks, run by them",
            "bench_artefacts.py": "owned and tested with the artefacts work",
            "bench_revisions.py": "compares git revisions: owned with them",
            "robustness.py": "a sweep of every mesh file: owned with it"}


@dataclass(frozen=True)
class Run:
    """One command: ``python scripts/<script> ARGS`` (``python ARGS`` with `module`), ``{tmp}`` in
    an argument being the test's folder; every pattern of `expect` must match a line of its output
    (multiline regular expressions) and every glob of `files` a file under ``{tmp}``."""

    args: tuple
    expect: tuple = ()
    files: tuple = ()
    module: bool = False
    needs_large: bool = False


def _child_json(*keys: str) -> tuple:
    """A benchmark child's last line: its JSON result, with these keys."""
    return (r'^\{.*"seconds": ',) + tuple(rf'"{k}": ' for k in keys)


CASES = {
    # Needs data/large/ but for --help and its children: ensure_large_data() would write gigabytes.
    "bench_batch.py": [
        Run(("--help",), (r"Benchmark scanned artefacts: the 5M pot end to end, and batch throughput",)),
        Run(("--child", "profile-ours", "data/pot.stl", "{tmp}"),
            _child_json("axis_error_deg", "capacity", "wall_thickness_min"), files=("pot_5m.svg", "pot_5m.png")),
    ],
    "bench_cut.py": [
        Run(("--help",), (r"Benchmark watertight cuts: slicelab\.cut beside trimesh and manifold3d",)),
        Run(("--child", "slicelab", "data/torus.stl", "0,0,1.234", "0.3,0.2,1.0"),
            _child_json("volumes") + (r'"watertight": \[true, true\]',)),
    ],
    # Its real run (fresh venvs, a wheel built with its kernels: minutes) is left to the user.
    "bench_install.py": [
        Run(("--help",), (r"Installing slicelab as a user does: ``pip install`` into a fresh venv",
                          r"--worktree")),
    ],
    "bench_io.py": [
        Run(("--child", "load", "data/torus.stl"), _child_json("facets")),
        Run(("--child", "check", "data/torus.stl"), _child_json("volume") + (r'"watertight": true',)),
        Run(("--repeat", "1", "--files", "torus_1m.stl"),
            (r"^bench_io: slicelab\.load / slicelab\.check vs numpy-stl and trimesh",
             r"^torus_1m\.stl: [\d,]+ facets", r"^  slicelab\.check \(mesh loaded before\) ",
             r"^  trimesh\.load / slicelab\.load ", r"^(all targets met|targets missed: )"), needs_large=True),
    ],
    "bench_layers.py": [
        # The cheapest table; 'layers' runs 0.02 mm pixels in children (10 s), 'rings' is as cheap.
        Run(("--table", "skins", "--repeat", "1"),
            (r"^the ring as a top skin \(all of it solid\), layer_paths at 0\.2 mm pixels",
             r"^ radius mm +time ms +x prev +gaps ms$", r"^ +160 +\d", r"^fitted exponents: time ~ radius\^")),
    ],
    "bench_plates.py": [
        Run(("--object", "pot"),
            (r"^bench_plates: partition, then arrange", r"^object +printer \(mm\) +pieces plates bound",
             r"^pot sample, cut for an 80 mm cube +200x200x200 +\d+ +\d+",
             r"^pot sample, cut for an 80 mm cube +250x210x210 +\d+ +\d+")),
    ],
    "bench_sections.py": [
        Run(("--help",), (r"Benchmark sections: every layer of a 1M-facet torus",)),
        Run(("--child", "pot-ours", "data/pot.stl"), _child_json("section", "loops") + (r'"open_chains": 0',)),
    ],
    "bench_slice.py": [
        # The smallest part, one run; PrusaSlicer beside it where installed, a note where not.
        Run(("--mesh", "data/bridge.stl", "--repeat", "1"),
            (r"^0\.2 mm layers, 0\.4 mm lines, 2 perimeters", r"^floor: a Python process importing",
             r"^=== bridge\.stl", r"^extruded \(m\) by ;TYPE:", r"^External perimeter +\d",
             r"^estimated print time: slicelab ", r"^part +ours s +Prusa s", r"^bridge\.stl +\d",
             r"^floor: .* in every slicelab run above")),
    ],
    "bench_split.py": [
        # Its child writes into data/large/ even on a small file: --help only.
        Run(("--help",), (r"Benchmark depth segmentation: split the 5M-facet pot through its axis",)),
    ],
    "check_estimate.py": [
        # The smallest part; PrusaSlicer's columns empty where it is not installed.
        Run(("--parts", "cube", "--keep", "{tmp}"),
            (r"^part +PrusaSlicer +ours, its file +ratio +ours, our file", r"^cube +", r"^G-code in "),
            files=("cube.slicelab.gcode",)),
    ],
    "check_gcode.py": [
        Run(("-m", "slicelab", "slice", "data/cube_with_hole.stl", "-o", "{tmp}/cube.gcode"), module=True),
        Run(("{tmp}/cube.gcode", "--mesh", "data/cube_with_hole.stl"),
            (r"cube\.gcode: \d+ lines, 100 layers, checked in ",)
            + tuple(rf"^  PASS {name} +\d+ checked" for name in
                    ("syntax", "heaters", "z_order", "first_layer", "inside_part", "on_bed", "retraction"))),
    ],
    "demo.py": [
        # The demo is 11 commands, a minute on 2 cores: tests/test_demo.py runs it whole. --help here.
        Run(("--help",), (r"`make demo`: run slicelab's main jobs on the bundled samples",)),
    ],
    "figures.py": [
        Run(("--out", "{tmp}"),
            tuple(rf"^06_artefacts/{name}: .*\.png \(\d" for name in
                  ("scan_before_after", "axis_error_by_case", "half_sections", "measurements_vs_truth",
                   "profile_drawing")),
            files=("06_artefacts_scan_before_after.png", "06_artefacts_profile_drawing.svg")),
    ],
    "fuzz_sections.py": [
        Run(("--planes", "14"), (r"^14 degenerate planes, 0 with open chains$",)),
    ],
    "make_data.py": [
        # Into a temporary folder: data/ is left alone.
        Run(("--out", "{tmp}"), (r"^wrote .*pot\.stl: 17568 facets", r"^wrote .*bridge\.stl: \d+ facets"),
            files=("pot.stl", "torus.stl", "mushroom.stl", "pot.json")),
    ],
    "profile_layers.py": [
        Run(("--layers", "5", "--top", "5"),
            (r"^pot\.stl: 5 layers from \d+: [\d.]+ ms per layer", r"^ms per layer by stage",
             r"^  plan_layer +[\d.]+$", r"^  distance_field +[\d.]+$", r"Ordered by: internal time",
             r"Ordered by: cumulative time")),
    ],
}


def test_every_script_has_a_case():
    scripts = {p.name for p in SCRIPTS.glob("*.py")}
    assert scripts - set(NOT_HERE) == set(CASES)


def _run(run: Run, script: str, tmp: Path) -> str:
    args = [a.replace("{tmp}", str(tmp)) for a in run.args]
    cmd = [sys.executable, *args] if run.module else [sys.executable, str(SCRIPTS / script), *args]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=900)
    shown = " ".join(cmd[1:])
    assert r.returncode == 0, f"{shown}: exit status {r.returncode}\n{r.stdout[-2000:]}\n{r.stderr[-3000:]}"
    for pattern in run.expect:
        assert re.search(pattern, r.stdout, flags=re.M), f"{shown}: no line matches {pattern!r}\n{r.stdout[-3000:]}"
    for name in run.files:
        assert list(tmp.glob(name)), f"{shown}: wrote no {name}"
    return r.stdout


@pytest.mark.parametrize("script", sorted(CASES))
def test_script_runs(script, tmp_path):
    for run in CASES[script]:
        if run.needs_large and not all((ROOT / "data" / "large" / f).exists() for f in LARGE_FILES):
            pytest.skip("needs data/large/ (make data-large)")
        _run(run, script, tmp_path)
