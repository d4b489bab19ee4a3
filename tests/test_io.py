"""STL reading and writing: formats, round trips, and every kind of bad input."""
import struct
import os
import subprocess
import sys
import tracemalloc

import numpy as np
import pytest

import slicelab
from slicelab import Mesh, MeshFileError, load, save
from slicelab.mesh.io import atomic_path
from slicelab.samples import box, torus

TRI = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 0, 0], [0, 1, 0], [0, 0, 1]]], float)


def binary_stl(triangles, normals=None, header=b"slicelab test", count=None) -> bytes:
    t = np.asarray(triangles, np.float32).reshape(-1, 3, 3)
    n = np.zeros((len(t), 3), np.float32) if normals is None else np.asarray(normals, np.float32)
    body = b"".join(n[i].tobytes() + t[i].tobytes() + b"\0\0" for i in range(len(t)))
    return header.ljust(80, b" ")[:80] + struct.pack("<I", len(t) if count is None else count) + body


def ascii_facet(tri, sep=" ", nl="\n", normal=(0, 0, 1)):
    v = "".join(f"{sep}vertex{sep}{float(p[0])!r}{sep}{float(p[1])!r}{sep}{float(p[2])!r}{nl}" for p in tri)
    return (f"facet{sep}normal {normal[0]} {normal[1]} {normal[2]}{nl}{sep}outer{sep}loop{nl}{v}"
            f"{sep}endloop{nl}endfacet{nl}")


def test_binary_round_trip_keeps_float32_coordinates(tmp_path):
    m = torus(30, 10, 16, 8)
    save(m, tmp_path / "t.stl")
    back = load(tmp_path / "t.stl")
    assert len(back) == len(m)
    np.testing.assert_array_equal(back.triangles, m.triangles.astype(np.float32).astype(np.float64))
    np.testing.assert_allclose(back.file_normals, m.normals, atol=1e-6)


def test_ascii_round_trip(tmp_path):
    m = box((0, 0, 0), (1.5, 2.25, 3))
    save(m, tmp_path / "b.stl", ascii=True)
    assert (tmp_path / "b.stl").read_bytes().startswith(b"solid")
    back = load(tmp_path / "b.stl")
    np.testing.assert_array_equal(back.triangles, m.triangles)
    assert slicelab.check(back).volume == pytest.approx(1.5 * 2.25 * 3, rel=1e-12)


def test_binary_whose_header_begins_with_solid(tmp_path):
    p = tmp_path / "solid_header.stl"
    p.write_bytes(binary_stl(TRI, header=b"solid but actually binary"))
    m = load(p)
    np.testing.assert_array_equal(m.triangles, TRI)


def test_ascii_odd_spacing_crlf_and_several_solids(tmp_path):
    text = ("solid first\r\n" + ascii_facet(TRI[0], sep="  \t ", nl="\r\n") + "endsolid first\r\n"
            + "\r\n  solid   second\r\n" + ascii_facet(TRI[1], sep="   ", nl="\r\n") + "endsolid second\r\n")
    p = tmp_path / "odd.stl"
    p.write_bytes(text.encode())
    m = load(p)
    np.testing.assert_array_equal(m.triangles, TRI)
    np.testing.assert_array_equal(m.file_normals, [[0, 0, 1], [0, 0, 1]])


def test_normals_come_from_the_winding_not_the_file(tmp_path):
    p = tmp_path / "n.stl"
    p.write_bytes(binary_stl(TRI, normals=[[0, 0, -1], [5, 0, 0]]))
    m = load(p)
    np.testing.assert_allclose(m.normals, [[0, 0, 1], [1, 0, 0]])
    np.testing.assert_allclose(m.file_normals, [[0, 0, -1], [5, 0, 0]])


def _bad_files(tmp_path):
    cases = {}
    cases["missing"] = (tmp_path / "nope.stl", "no such file")
    d = tmp_path / "adir.stl"
    d.mkdir()
    cases["directory"] = (d, "directory")
    (tmp_path / "empty.stl").write_bytes(b"")
    cases["empty"] = (tmp_path / "empty.stl", "empty")
    full = binary_stl(np.tile(TRI, (5, 1, 1)))
    (tmp_path / "trunc.stl").write_bytes(full[:-7])
    cases["truncated"] = (tmp_path / "trunc.stl", "truncated")
    (tmp_path / "billions.stl").write_bytes(binary_stl(TRI, count=4_000_000_000))
    cases["billions"] = (tmp_path / "billions.stl", "claims 4000000000 triangles")
    (tmp_path / "garbage.stl").write_text("solid x\nfacet normal 0 0 1\nthis is not stl\nendsolid x\n")
    cases["garbage"] = (tmp_path / "garbage.stl", "malformed ASCII")
    lines = ascii_facet(TRI[0]).splitlines(keepends=True)
    two_vertices = "".join(lines[:4] + lines[5:])  # drop the third vertex line
    assert two_vertices.count("vertex") == 2
    (tmp_path / "missing_vertex.stl").write_text("solid x\n" + two_vertices + "endsolid x\n")
    cases["missing vertex"] = (tmp_path / "missing_vertex.stl", "malformed ASCII")
    (tmp_path / "noend.stl").write_text("solid x\n" + ascii_facet(TRI[0]))
    cases["no endsolid"] = (tmp_path / "noend.stl", "endsolid")
    nan = TRI.copy()
    nan[1, 2, 0] = np.nan
    (tmp_path / "nan.stl").write_bytes(binary_stl(nan))
    cases["nan"] = (tmp_path / "nan.stl", "NaN or infinite")
    inf = TRI.copy()
    inf[0, 0, 2] = np.inf
    (tmp_path / "inf.stl").write_text("solid x\n" + ascii_facet(inf[0]).replace("inf", "inf") + "endsolid x\n")
    cases["inf ascii"] = (tmp_path / "inf.stl", "NaN or infinite")
    (tmp_path / "zero.stl").write_bytes(binary_stl(np.zeros((0, 3, 3))))
    cases["zero facets binary"] = (tmp_path / "zero.stl", "no facets")
    (tmp_path / "zero_ascii.stl").write_text("solid nothing\nendsolid nothing\n")
    cases["zero facets ascii"] = (tmp_path / "zero_ascii.stl", "no facets")
    (tmp_path / "picture.stl").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 3)
    cases["png"] = (tmp_path / "picture.stl", "PNG")
    (tmp_path / "tiny.stl").write_bytes(b"abc")
    cases["tiny"] = (tmp_path / "tiny.stl", "not an STL")
    os.mkfifo(tmp_path / "pipe.stl")  # reading it would block for ever
    cases["fifo"] = (tmp_path / "pipe.stl", "not a regular file")
    return cases


BAD = ["missing", "directory", "empty", "truncated", "billions", "garbage", "missing vertex",
       "no endsolid", "nan", "inf ascii", "zero facets binary", "zero facets ascii", "png", "tiny", "fifo"]


@pytest.mark.parametrize("case", BAD)
def test_bad_input_raises_one_clear_error(tmp_path, case):
    path, reason = _bad_files(tmp_path)[case]
    with pytest.raises(MeshFileError) as err:
        load(path)
    msg = str(err.value)
    assert isinstance(err.value, ValueError)
    assert str(path) in msg and reason in msg and "\n" not in msg


@pytest.mark.parametrize("case", BAD)
def test_cli_reports_bad_input_in_one_line_with_status_2(tmp_path, case):
    path, reason = _bad_files(tmp_path)[case]
    r = subprocess.run([sys.executable, "-m", "slicelab", "inspect", str(path)], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and reason in lines[0] and "Traceback" not in r.stderr


def test_a_huge_claimed_count_allocates_nothing(tmp_path):
    p = tmp_path / "claim.stl"
    p.write_bytes(binary_stl(TRI, count=2**32 - 1))
    tracemalloc.start()
    with pytest.raises(MeshFileError):
        load(p)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 1_000_000


def test_failed_write_leaves_no_file(tmp_path):
    target = tmp_path / "out.stl"
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            tmp.write_bytes(b"half")
            raise RuntimeError("disk full")
    assert not target.exists() and list(tmp_path.iterdir()) == []


def test_atomic_open_steps_over_a_temporary_name_taken_and_gives_ordinary_permissions(tmp_path):
    # A temporary name a crashed process of the same pid left behind is not written into; the file
    # gets the mode open() gives (0666 less the umask), as before its rename; a failed write or a
    # mode that is not writing leaves nothing.
    import os

    from slicelab.files import atomic as files
    serial = next(files._SERIAL) + 1
    left = tmp_path / f".a.svg.{os.getpid()}.{serial}.part"
    left.write_text("left by a crash")
    umask = os.umask(0o027)
    try:
        with files.atomic_open(tmp_path / "a.svg", "w", encoding="utf-8") as fh:
            fh.write("<svg/>")
    finally:
        os.umask(umask)
    assert (tmp_path / "a.svg").read_text() == "<svg/>" and left.read_text() == "left by a crash"
    assert (tmp_path / "a.svg").stat().st_mode & 0o777 == 0o640
    with pytest.raises(ValueError, match="not a writing mode"):
        with files.atomic_open(tmp_path / "b.svg", "r"):
            pass
    with pytest.raises(RuntimeError):
        with files.atomic_open(tmp_path / "c.svg", "wb") as fh:
            fh.write(b"half")
            raise RuntimeError("disk full")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([left.name, "a.svg"])


def test_save_replaces_atomically_and_leaves_no_temporary(tmp_path):
    save(box(), tmp_path / "a.stl")
    save(box((0, 0, 0), (2, 2, 2)), tmp_path / "a.stl")
    assert [p.name for p in tmp_path.iterdir()] == ["a.stl"]
    assert slicelab.check(load(tmp_path / "a.stl")).volume == pytest.approx(8.0)


def test_mesh_constructors_agree_and_accept_trimesh():
    trimesh = pytest.importorskip("trimesh")
    t = trimesh.creation.icosphere(subdivisions=2)
    a = Mesh.from_vertices_faces(t.vertices, t.faces)
    b = Mesh.from_triangles(t.triangles)
    np.testing.assert_array_equal(a.triangles, b.triangles)
    np.testing.assert_allclose(a.normals, t.face_normals, atol=1e-12)
    assert slicelab.check(a).volume == pytest.approx(t.volume, rel=1e-12)


def test_mesh_rejects_bad_shapes_and_indices():
    with pytest.raises(ValueError):
        Mesh(np.zeros((3, 3)))
    with pytest.raises(ValueError):
        Mesh.from_vertices_faces(np.zeros((3, 3)), [[0, 1, 3]])


def test_transformed_moves_and_mirrors_with_outward_normals():
    m = box((0, 0, 0), (1, 2, 3))
    rot = np.eye(4)
    rot[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    rot[:3, 3] = [10, 0, 0]
    r = m.transformed(rot)
    np.testing.assert_allclose(r.bounds, [[8, 0, 0], [10, 1, 3]])
    mirror = np.diag([-1.0, 1, 1, 1])
    mm = m.transformed(mirror)
    assert slicelab.check(mm).volume == pytest.approx(6.0)
    assert slicelab.check(mm).n_flipped_normals == 0
    assert np.all(m.triangles.flags.writeable is False for _ in [0])
