"""Partition into printable pieces, flat and stair joints."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import slicelab
from slicelab import Mesh, check, samples
from slicelab.geometry.topology import manifold_summary
from slicelab.slicing import Partition, fit_rotation
from slicelab.slicing.partition import partition
from slicelab.slicing.stair import StairCutError, stair_cut

from conftest import ROOT


def assert_closed(part: Mesh) -> None:
    assert manifold_summary(part.triangles).closed
    r = check(part)
    assert r.watertight and r.winding_consistent and r.volume > 0


def assert_fits(piece: Mesh, volume, turn: float) -> None:
    """Turned by `turn` degrees about z, the piece lies inside the build volume."""
    a = np.radians(turn)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    p = piece.triangles.reshape(-1, 3)
    xy = p[:, :2] @ rot.T
    size = np.r_[np.ptp(xy, axis=0), np.ptp(p[:, 2])]
    assert np.all(size <= np.asarray(volume) * (1 + 1e-9)), (size, volume, turn)


def assert_placed(piece: Mesh, volume, info) -> None:
    """Moved by its placement, the piece lies on the bed, inside the build volume, with its
    largest flat face down."""
    placed = piece.transformed(info.placement.matrix)
    lo, hi = placed.bounds
    tol = 1e-9 * max(volume)
    assert np.all(lo >= -tol) and np.all(hi <= np.asarray(volume) + tol), (lo, hi, volume)
    assert abs(lo[2]) <= tol
    assert tuple(hi - lo) == pytest.approx(info.size, abs=1e-9)
    assert check(placed).volume == pytest.approx(check(piece).volume, rel=1e-12)
    if info.placement.flat_area > 0:
        # The face on the bed: facets in z = 0 facing down, as large as the placement says.
        t = placed.triangles
        down = np.all(np.abs(t[:, :, 2]) <= tol, axis=1) & (placed.normals[:, 2] < -0.999)
        area = check(Mesh(t[down])).area
        assert area == pytest.approx(info.placement.flat_area, rel=1e-9)


def solid_of(mesh: Mesh):
    mf = pytest.importorskip("manifold3d")
    from slicelab.geometry.topology import weld
    v, f = weld(mesh.triangles)
    return mf.Manifold(mf.Mesh64(vert_properties=v, tri_verts=f.astype(np.uint64)))


# ------------------------------------------------------------------ stair joints
def test_stair_cut_of_a_box_is_exact():
    box = samples.box((0, 0, 0), (40, 20, 20))
    s = stair_cut(box, 0, 18.0, step=(5.0, 7.5))
    assert_closed(s.rear)
    assert_closed(s.front)
    assert check(s.rear).volume + check(s.front).volume == pytest.approx(16000.0, rel=1e-12)
    # Four bands of 5 mm along y, treads alternately at x = 18 and 25.5: the teeth interlock.
    assert s.rear.bounds[1, 0] == 25.5 and s.front.bounds[0, 0] == 18.0
    assert s.flat_area == 400.0
    assert s.glue_area == pytest.approx(400.0 + 3 * 7.5 * 20, rel=1e-12)
    # The tread faces face +x, the risers +-y, all lying on the terrace.
    n = np.cross(s.treads[:, 1] - s.treads[:, 0], s.treads[:, 2] - s.treads[:, 0])
    assert np.all(n[:, 0] > 0) and np.allclose(n[:, 1:], 0)
    assert set(np.unique(s.treads[:, :, 0])) <= {18.0, 25.5}


def test_stair_parts_do_not_overlap_and_add_up_to_the_part():
    pot = samples.pot(20, 32)
    s = stair_cut(pot, 2, 50.0, step=(8.0, 12.0), flight=2)
    whole, a, b = solid_of(pot), solid_of(s.rear), solid_of(s.front)
    assert (a ^ b).volume() == pytest.approx(0.0, abs=1e-6 * whole.volume())
    assert (a + b).volume() == pytest.approx(whole.volume(), rel=1e-9)
    assert s.glue_area >= 2 * s.flat_area


@pytest.mark.parametrize("mesh, axis, pos", [
    (samples.torus(30, 10, 48, 24), 0, 3.0),
    (samples.cube_with_hole(20, 5, 32), 1, 7.0),
    (samples.nested_shells(), 2, 19.0),
    (samples.sphere(20, 12, 24), 1, -2.5),
])
def test_stair_joint_at_least_doubles_the_glue_area(mesh, axis, pos):
    s = stair_cut(mesh, axis, pos, step=(3.0, 4.5))
    assert_closed(s.rear)
    assert_closed(s.front)
    v = check(mesh).volume
    assert check(s.rear).volume + check(s.front).volume == pytest.approx(v, rel=1e-9)
    assert s.glue_area >= 2 * s.flat_area


def test_stair_cut_of_a_turned_part():
    from conftest import random_rotation
    mesh = samples.pot(12, 20).transformed(random_rotation(np.random.default_rng(11)))
    for axis in range(3):
        lo, hi = mesh.bounds[:, axis]
        s = stair_cut(mesh, axis, lo + 0.45 * (hi - lo), step=(6.0, 9.0), flight=2)
        assert_closed(s.rear)
        assert_closed(s.front)
        assert check(s.rear).volume + check(s.front).volume == pytest.approx(check(mesh).volume, rel=1e-9)


def test_clearance_leaves_a_gap():
    box = samples.box((0, 0, 0), (40, 20, 20))
    flat = partition(box, (30, 30, 30), clearance=0.5)
    assert sum(p.volume for p in flat.report.pieces) == pytest.approx(16000 - 0.5 * 400, rel=1e-12)
    s = stair_cut(box, 0, 15.0, step=(5.0, 7.5), clearance=0.5)
    assert_closed(s.rear)
    assert_closed(s.front)
    a, b = solid_of(s.rear), solid_of(s.front)
    assert (a ^ b).volume() == pytest.approx(0.0, abs=1e-9)
    lost = 16000 - check(s.rear).volume - check(s.front).volume
    # About clearance x glue area (corners of the gap add and take a little).
    assert lost == pytest.approx(0.5 * s.glue_area, rel=0.1)


def test_bad_stair_arguments():
    with pytest.raises(ValueError):
        stair_cut(samples.box(), 3, 0.5)
    with pytest.raises(ValueError):
        stair_cut(samples.box(), 0, 0.5, step=(0, 1))
    with pytest.raises(ValueError):
        stair_cut(samples.box(), 0, 5.0)  # misses the part


def test_a_stair_that_cannot_close_raises_stair_cut_error():
    # An open box: the band planes' sections do not close.
    with pytest.raises(StairCutError, match="did not close"):
        stair_cut(Mesh(samples.box((0, 0, 0), (40, 20, 20)).triangles[1:]), 0, 18.0, step=(5.0, 7.5))
    assert issubclass(StairCutError, RuntimeError)
    assert slicelab.StairCutError is StairCutError


# ------------------------------------------------------------------ fitting
def test_fit_rotation():
    assert fit_rotation(samples.box((0, 0, 0), (250, 100, 10)), (200, 300, 100)) == 90.0
    assert fit_rotation(samples.box((0, 0, 0), (250, 100, 10)), (200, 300, 100), rotate=False) is None
    # A thin bar 260 mm long lies diagonally in a 200 x 200 bed.
    bar = samples.box((0, 0, 0), (260, 10, 10)).transformed(np.eye(4))
    turn = fit_rotation(bar, (200, 200, 100))
    assert turn is not None and 30 < turn % 90 < 60
    assert_fits(bar, (200, 200, 100), turn)
    assert fit_rotation(samples.box((0, 0, 0), (10, 10, 300)), (200, 200, 200)) is None


# ------------------------------------------------------------------ partition
def test_partition_of_a_long_box():
    parts = partition(samples.box((0, 0, 0), (300, 120, 80)), (200, 200, 200))
    assert isinstance(parts, Partition) and not isinstance(parts, list)
    assert len(parts) == len(parts.pieces) == 2 and list(parts) == list(parts.pieces)
    for piece, info in zip(parts.pieces, parts.report.pieces):
        assert_closed(piece)
        assert_placed(piece, (200, 200, 200), info)
    assert sum(check(p).volume for p in parts.pieces) == pytest.approx(300 * 120 * 80, rel=1e-12)
    assert parts.report.glue_area == pytest.approx(120 * 80, rel=1e-12)


def test_partition_of_a_one_metre_pot_with_stair_joints():
    scale = np.diag([1000 / 120] * 3 + [1.0])
    pot = samples.pot(12, 18).transformed(scale)  # 1033 x 1033 x 1000 mm
    volume = (600.0, 600.0, 600.0)
    parts = partition(pot, volume, joint="stair", step=(50.0, 100.0))
    rep = parts.report
    assert len(parts.pieces) == len(rep.pieces) >= 8  # at least 2 x 2 x 2
    for piece, info in zip(parts.pieces, rep.pieces):
        assert_closed(piece)
        assert_placed(piece, volume, info)
        assert info.watertight
        # A cut face, not the stair's terraces nor the pot's curved wall, rests on the bed.
        assert info.placement.flat_area > 0
    assert sum(check(p).volume for p in parts.pieces) == pytest.approx(check(pot).volume, rel=1e-9)
    stairs = [j for j in rep.joints if j.kind == "stair"]
    assert len(stairs) >= len(rep.joints) // 2
    assert all(j.glue_area >= 2 * j.flat_area for j in stairs)
    assert rep.glue_area > 2 * sum(j.flat_area for j in stairs)


def test_a_piece_is_laid_on_its_cut_face_and_turned_to_fit():
    # A 150 mm tall bar in a 100 mm tall volume: cut in two; each half lies on its cut face
    # (the largest flat face that is not its original bottom) only when that fits better.
    parts = partition(samples.box((0, 0, 0), (20, 30, 150)), (100, 100, 100))
    assert len(parts.pieces) == 2
    for piece, info in zip(parts.pieces, parts.report.pieces):
        assert_placed(piece, (100, 100, 100), info)
    # Lying flat, a 260 mm bar fits a 200 x 200 bed only on the diagonal.
    parts = partition(samples.box((0, 0, 0), (260, 10, 10)), (200, 200, 50))
    (info,) = parts.report.pieces
    assert 30 < info.rotation % 90 < 60 and info.placement.down in ("-z", "+z", "-y", "+y")
    assert_placed(parts.pieces[0], (200, 200, 50), info)


def test_partition_keeps_pieces_few():
    # A 3 x 1 x 1 row of build volumes needs exactly three pieces.
    parts = partition(samples.box((0, 0, 0), (590, 190, 190)), (200, 200, 200))
    assert len(parts.pieces) == 3
    # Separate bodies are printed apart, with no cut between them.
    two = Mesh(np.concatenate([samples.box((0, 0, 0), (150, 150, 150)).triangles,
                               samples.box((300, 0, 0), (450, 150, 150)).triangles]))
    parts = partition(two, (200, 200, 200))
    assert len(parts.pieces) == 2 and parts.report.joints == []


def test_partition_bad_input():
    with pytest.raises(ValueError):
        partition(samples.box(), (0, 10, 10))
    with pytest.raises(ValueError):
        partition(samples.box(), (10, 10, 10), joint="zigzag")
    with pytest.raises(ValueError):
        partition(samples.box((0, 0, 0), (50, 5, 5)), (20, 20, 20), joint="stair", step=(10, 25))
    with pytest.raises(ValueError):
        partition(samples.box(), (10, 10, 10), clearance=-1)


def test_package_exposes_partition():
    assert slicelab.partition is partition
    assert slicelab.stair_cut is stair_cut


# ------------------------------------------------------------------ command line
def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "slicelab", *map(str, args)], cwd=ROOT, text=True,
                          capture_output=True)


def test_cli_partition(tmp_path, data_dir):
    out = tmp_path / "parts"
    r = run_cli("partition", data_dir / "pot.stl", "--volume", "80x80x80", "--joint", "stair", "--step", "8,12",
                "-o", out)
    assert r.returncode == 0, r.stderr
    report = json.loads((out / "parts.json").read_text())
    files = sorted(out.glob("part_*.stl"))
    assert len(files) == len(report["pieces"]) >= 2
    total = 0.0
    for f, info in zip(files, report["pieces"]):
        assert info["file"] == f.name
        piece = slicelab.load(f)
        written = check(piece)
        # What the report says is what the file holds: watertight, and placed as printed.
        assert written.watertight and info["watertight"] and info["written"]["watertight"]
        lo, hi = piece.bounds
        assert np.all(lo >= -1e-4) and np.all(hi <= 80 + 1e-4), (f.name, lo, hi)  # float32 file
        assert abs(lo[2]) <= 1e-4
        assert tuple(hi - lo) == pytest.approx(info["size"], abs=1e-4)
        np.testing.assert_allclose(np.asarray(info["placement"]["matrix"])[3], [0, 0, 0, 1])
        total += written.volume
    assert total == pytest.approx(check(slicelab.load(data_dir / "pot.stl")).volume, rel=1e-5)  # float32 STL
    assert report["glue_area"] >= 2 * report["flat_area"]
    assert (out / "exploded.png").stat().st_size > 1000


def test_cli_partition_bad_volume_exits_2(tmp_path, data_dir):
    r = run_cli("partition", data_dir / "pot.stl", "--volume", "80x80", "-o", tmp_path / "x")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    r = run_cli("partition", data_dir / "pot.stl", "--volume", "80x80x80", "--clearance", "-1", "-o", tmp_path / "x")
    assert r.returncode == 2 and "Traceback" not in r.stderr
