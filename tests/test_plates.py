"""Build plates: no overlap, inside the volume, rigid placements, cut faces down, known optima, one G-code."""
from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pytest
import shapely

import slicelab
from slicelab import check
from slicelab.samples import box, concat, pot
from slicelab.mesh.written import as_float32
from slicelab.slicing import arrange, flat_faces, footprint


def _placed(plates, pieces):
    for plate in plates.plates:
        yield plate, [pieces[i].transformed(m) for i, m in zip(plate.pieces, plate.matrices)]


def assert_valid(plates, pieces, volume, spacing):
    X, Y, Z = volume
    seen = []
    for plate, placed in _placed(plates, pieces):
        outlines = []
        for i, m, piece in zip(plate.pieces, plate.matrices, placed):
            seen.append(i)
            R = m[:3, :3]
            np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)        # a rigid motion
            assert np.linalg.det(R) == pytest.approx(1.0)
            lo, hi = piece.bounds
            assert np.all(lo >= -1e-6) and np.all(hi <= np.array([X, Y, Z]) + 1e-6), (lo, hi)
            assert abs(lo[2]) <= 1e-9                                        # on the bed
            # Turned, near-coincident corners of a cut's slivers may round together: the file mends that.
            a, b = check(pieces[i]), check(as_float32(piece)[0])
            assert b.volume == pytest.approx(a.volume, rel=1e-6) and b.watertight == a.watertight
            outlines.append(shapely.buffer(footprint(piece), spacing / 2 - 0.3))  # 0.3: the footprint's raster
        for j in range(len(outlines)):
            for k in range(j):
                assert outlines[j].intersection(outlines[k]).area < 1e-6, (plate.pieces[j], plate.pieces[k])
    assert sorted(seen) == list(range(len(pieces)))


@pytest.mark.parametrize("pieces, volume, spacing, best", [
    ([box((0, 0, 0), (100, 50, 10))] * 8, (200, 200, 100), 0.0, 1),    # an exact tiling
    ([box((0, 0, 0), (60, 60, 10))] * 10, (200, 200, 100), 5.0, 2),    # 3 x 3 fit a plate, the tenth does not
    ([box((0, 0, 0), (150, 30, 20))] * 4, (160, 160, 100), 5.0, 1),
], ids=["tiling", "squares", "bars"])
def test_rectangles_reach_the_known_optimum(pieces, volume, spacing, best):
    plates = arrange(pieces, volume, spacing=spacing)
    assert len(plates) == best
    assert_valid(plates, pieces, volume, spacing)


def test_an_l_shaped_piece_lets_a_small_one_sit_in_its_corner():
    ell = concat(box((0, 0, 0), (150, 40, 10)), box((0, 40, 0), (40, 150, 10)))
    square = box((0, 0, 0), (100, 100, 10))
    plates = arrange([ell, square], (160, 160, 100), spacing=5)
    assert len(plates) == 1   # their bounding boxes (150 and 100 wide) could not share the plate
    assert_valid(plates, [ell, square], (160, 160, 100), 5)


def test_partition_pieces_are_packed_with_their_cut_faces_down():
    parts = slicelab.partition(pot(24, 36), (80, 80, 80))
    pieces = list(parts.pieces)
    plates = arrange(pieces, (200, 200, 200), spacing=5)
    assert len(plates) < len(pieces) and len(plates) >= plates.lower_bound
    assert_valid(plates, pieces, (200, 200, 200), 5)
    for _, placed in _placed(plates, pieces):
        for piece in placed:
            faces = flat_faces(piece)
            assert faces["-z"] > 0 and faces["-z"] == pytest.approx(max(faces.values()))


def test_a_piece_taller_than_the_volume_is_refused():
    with pytest.raises(ValueError, match="does not fit the 100 x 100 x 100 mm build volume"):
        arrange([box((0, 0, 0), (20, 150, 120))], (100, 100, 100))


def test_one_gcode_prints_every_piece_of_a_plate():
    from slicelab.gcode import gcode_lines
    pieces = [box((0, 0, 0), (20, 10, 2)), box((0, 0, 0), (15, 15, 2)), box((0, 0, 0), (8, 30, 2))]
    plates = arrange(pieces, (80, 80, 50), spacing=5)
    assert len(plates) == 1
    plate = plates.plate_mesh(0, pieces)
    assert check(plate).n_shells == 3
    pp = slicelab.plan(plate, slicelab.PrintSettings(pixel_size=0.1), workers=1)
    regions = [shapely.buffer(footprint(p).envelope, 0.45) for _, placed in _placed(plates, pieces) for p in placed]
    text = "".join(gcode_lines(pp))
    x = y = None
    hits = np.zeros(3, int)
    kind = None
    for line in text.splitlines():  # the extrusion moves, read back
        if line.startswith(";TYPE:"):
            kind = line[6:]
        m = re.match(r"G1 X([-\d.]+) Y([-\d.]+)( E[\d.]+)?", line)
        if m and kind not in ("Skirt", "Brim", "Skirt/Brim"):  # around the pieces by design
            x, y = float(m.group(1)) - pp.offset[0], float(m.group(2)) - pp.offset[1]
            if m.group(3):
                inside = [r.contains(shapely.Point(x, y)) for r in regions]
                assert any(inside), (x, y)
                hits[int(np.argmax(inside))] += 1
    assert np.all(hits > 0)  # every piece is printed


def test_cli_arrange_and_partition_plates(tmp_path, data_dir):
    for k, size in enumerate([(40, 30, 10), (50, 20, 15), (25, 25, 25)]):
        slicelab.save(box((0, 0, 0), size), tmp_path / f"p{k}.stl")
    out = tmp_path / "plates"
    r = subprocess.run([sys.executable, "-m", "slicelab", "arrange", *[str(tmp_path / f"p{k}.stl") for k in range(3)],
                        "--volume", "120x120x100", "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    info = json.loads((out / "plates.json").read_text())
    assert info["plates_used"] == 1 and info["plates"][0]["piece_files"] == ["p0.stl", "p1.stl", "p2.stl"] or \
        sorted(info["plates"][0]["piece_files"]) == ["p0.stl", "p1.stl", "p2.stl"]
    plate = slicelab.load(out / "plate_01.stl")
    rep = check(plate)
    assert rep.watertight and rep.n_shells == 3
    lo, hi = plate.bounds
    assert np.all(lo >= -1e-4) and np.all(hi <= np.array([120, 120, 100]) + 1e-4)
    assert (out / "plate_01.png").stat().st_size > 1000
    r = subprocess.run([sys.executable, "-m", "slicelab", "partition", str(data_dir / "pot.stl"), "--volume",
                        "80x80x80", "--plates", "--no-preview", "-o", str(tmp_path / "parts")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    info = json.loads((tmp_path / "parts" / "plates.json").read_text())
    assert info["plates_used"] <= info["pieces"] and sorted(tmp_path.glob("parts/plate_*.stl"))
