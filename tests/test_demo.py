"""`make demo` as a fresh machine runs it: every step succeeds and what it writes reads back."""
from __future__ import annotations

import csv
import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

import slicelab

ROOT = Path(__file__).resolve().parents[1]


def test_the_demo_runs_and_its_files_read_back(tmp_path):
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "demo.py"), "--out", str(tmp_path)], cwd=ROOT,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    assert "demo step failed" not in r.stderr
    # Drawings parse as SVG; the profile's measurements are numbers of a pot's size.
    for svg in ("pot_axial.svg", "pot_z60.svg", "pot_profile.svg"):
        assert ET.parse(tmp_path / svg).getroot().tag.endswith("svg")
    profile = json.loads((tmp_path / "pot_profile.json").read_text())
    height = profile["measurements"]["height"]
    assert 100 < height < 140  # the pot sample is 120 mm tall
    # Both G-code files: layers at their heights, extrusions, and the estimates PrusaSlicer's viewer reads.
    for name, layer in (("cube_with_hole.gcode", 0.2), ("pot.gcode", 0.6)):
        text = (tmp_path / name).read_text()
        z = np.array([float(line[3:]) for line in text.splitlines() if line.startswith(";Z:")])
        assert len(z) > 10 and np.allclose(np.diff(z), layer, atol=1e-3)
        assert text.count(";TYPE:External perimeter") >= len(z)
        assert "; estimated printing time (normal mode) = " in text and "; filament used [mm] = " in text
    # The cut's parts are closed; the partition's pieces are closed and fit the 80 mm printer.
    for part in sorted((tmp_path / "torus_cut").glob("*.stl")):
        assert slicelab.check(slicelab.load(part)).watertight
    pieces = sorted((tmp_path / "pot_parts").glob("*.stl"))
    assert len(pieces) >= 4
    for piece in pieces:
        mesh = slicelab.load(piece)
        lo, hi = mesh.bounds
        assert slicelab.check(mesh).watertight and np.all(hi - lo <= 80 + 1e-6)
    # The batch's summary has a row per profiled sample, each with a status.
    with open(tmp_path / "batch_profile" / "summary.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) >= 4 and all(row["status"] in ("ok", "warn", "refused") for row in rows)
