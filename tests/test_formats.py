"""PLY, OBJ and 3MF read as the same mesh as STL; hostile and bad files refused in one line; units."""
from __future__ import annotations

import meshio
import numpy as np
import pytest

import slicelab
from slicelab import MeshFileError, check, load, save
from slicelab.geometry import weld
from slicelab.samples import box, pot, torus


def _write(mesh, path, **kw):
    v, f = weld(mesh.triangles)
    meshio.write(str(path), meshio.Mesh(v, [("triangle", f.astype(np.int32))]), **kw)


@pytest.mark.parametrize("name, kw", [("t.ply", {"binary": True}), ("t_ascii.ply", {"binary": False}),
                                      ("t.obj", {})])
def test_scan_formats_read_as_the_same_mesh_as_stl(tmp_path, name, kw):
    m = torus(30, 10, 48, 24)
    save(m, tmp_path / "t.stl")
    _write(slicelab.load(tmp_path / "t.stl"), tmp_path / name, **kw)  # the float32 mesh the STL holds
    a, b = load(tmp_path / "t.stl"), load(tmp_path / name)
    np.testing.assert_allclose(b.triangles, a.triangles, rtol=0, atol=1e-12 if "ascii" not in name else 1e-5)
    ra, rb = check(a), check(b)
    assert rb.watertight and rb.n_shells == 1 and rb.volume == pytest.approx(ra.volume, rel=1e-6)


def test_quads_and_polygons_become_triangles(tmp_path):
    obj = tmp_path / "cube.obj"
    v = "\n".join(f"v {x} {y} {z}" for x in (0, 1) for y in (0, 1) for z in (0, 1))
    # The unit cube as six quads, wound outward (vertex k = 4x + 2y + z + 1).
    faces = ["f 1 2 4 3", "f 5 7 8 6", "f 1 5 6 2", "f 3 4 8 7", "f 1 3 7 5", "f 2 6 8 4"]
    obj.write_text(v + "\n" + "\n".join(faces) + "\n")
    r = check(load(obj))
    assert r.n_facets == 12 and r.watertight and r.volume == pytest.approx(1.0)


def test_units_and_scale_turn_coordinates_into_millimetres(tmp_path):
    m = pot(12, 18)
    save(slicelab.Mesh(m.triangles / 1000), tmp_path / "pot_m.stl")   # a file in metres
    mm = load(tmp_path / "pot_m.stl", units="m")
    assert np.ptp(mm.triangles[..., 2]) == pytest.approx(np.ptp(m.triangles[..., 2]), rel=1e-6)
    assert np.ptp(load(tmp_path / "pot_m.stl", scale=10).triangles[..., 2]) == pytest.approx(1.2, rel=1e-6)
    with pytest.raises(ValueError, match="units"):
        load(tmp_path / "pot_m.stl", units="furlong")


@pytest.mark.parametrize("name, text, reason", [
    ("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "OBJ"),
    ("points.obj", "v 0 0 0\nv 1 0 0\n", "no faces"),
    ("truncated.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n", "PLY"),
    ("garbage.ply", "ply\nthis is not a header\n", "PLY"),
])
def test_bad_scan_files_are_refused_with_a_reason(tmp_path, name, text, reason):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(MeshFileError) as err:
        load(path)
    assert str(path) in str(err.value) and reason in str(err.value) and "\n" not in str(err.value)


def test_batch_takes_a_folder_mixing_formats(tmp_path):
    from slicelab.tasks import run_batch
    folder = tmp_path / "scans"
    m = torus(30, 10, 24, 12)
    save(m, folder / "a.stl")
    back = load(folder / "a.stl")
    _write(back, folder / "b.ply", binary=True)
    _write(back, folder / "c.obj")
    result = run_batch(folder, tmp_path / "out", "inspect", workers=1, progress=False)
    assert sorted(r["file"] for r in result.reports) == ["a.stl", "b.ply", "c.obj"]
    assert all(r["status"] == "ok" for r in result.reports), [r["reasons"] for r in result.reports]
    vols = [r["results"]["volume"] for r in result.reports]
    assert max(vols) == pytest.approx(min(vols), rel=1e-9)


def test_a_file_in_metres_warns_and_units_m_gives_millimetres(tmp_path, data_dir):
    import json
    import subprocess
    import sys
    m = load(data_dir / "pot.stl")
    save(slicelab.Mesh(m.triangles / 1000), tmp_path / "pot_m.stl")

    def profile(*extra):
        out = tmp_path / f"p{len(extra)}"
        r = subprocess.run([sys.executable, "-m", "slicelab", "profile", str(tmp_path / "pot_m.stl"), "-o",
                            str(out / "p.svg"), "--json", str(out / "p.json"), *extra],
                           capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        return r, json.loads((out / "p.json").read_text())

    r, bare = profile()
    assert "written in metres? (--units m" in r.stderr
    r, mm = profile("--units", "m")
    assert "units" not in r.stderr
    truth = slicelab.profile(m).measurements
    assert mm["measurements"]["height"] == pytest.approx(truth.height, rel=1e-5)
    assert bare["measurements"]["height"] == pytest.approx(truth.height / 1000, rel=1e-5)


# --- Hostile and ordinary files: each loads as the mesh it holds or is refused in one line ---------------

def _refused(path, *reasons):
    with pytest.raises(MeshFileError) as err:
        load(path)
    msg = str(err.value)
    assert str(path) in msg and "\n" not in msg and all(r in msg for r in reasons), msg
    return msg


def _ply(v, f, fmt="binary_little_endian", vtype="float", count="uchar", index="int", name="vertex_indices",
         extra_header=""):
    """A PLY file written by hand: any format, types and index property name."""
    order = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(fmt)
    head = (f"ply\nformat {fmt} 1.0\ncomment by hand\nelement vertex {len(v)}\nproperty {vtype} x\n"
            f"property {vtype} y\nproperty {vtype} z\nelement face {len(f)}\n"
            f"property list {count} {index} {name}\n{extra_header}end_header\n").encode()
    if order is None:
        body = "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in v.tolist())
        body += "".join(f"{len(r)} " + " ".join(map(str, r)) + "\n" for r in f.tolist())
        return head + body.encode()
    kinds = {"float": "f4", "double": "f8", "float64": "f8", "uchar": "u1", "uint8": "u1", "char": "i1",
             "ushort": "u2", "int": "i4", "uint": "u4"}
    rows = np.zeros(len(f), [("n", order + kinds[count]), ("i", order + kinds[index], (f.shape[1],))])
    rows["n"], rows["i"] = f.shape[1], f
    return head + np.asarray(v, order + kinds[vtype]).tobytes() + rows.tobytes()


def _welded(mesh):
    v, f = weld(mesh.triangles)
    return np.asarray(v, np.float64), np.asarray(f, np.int64)


@pytest.mark.parametrize("fmt, kw", [
    ("binary_big_endian", {}), ("binary_little_endian", {"vtype": "double", "count": "uint8", "index": "uint"}),
    ("binary_little_endian", {"vtype": "float64", "count": "char", "name": "vertex_index"}),
    ("binary_little_endian", {"count": "ushort", "extra_header": "element edge 0\nproperty int vertex1\n"}),
    ("ascii", {"vtype": "double"}), ("ascii", {"index": "int16"})])
def test_ply_types_and_layouts_read_as_written(tmp_path, fmt, kw):
    # Names meshio's tables lack or misread (char, float64, ushort, int16, 'vertex_index') reach it renamed;
    # an element after the faces is left out.
    v, f = _welded(torus(30, 10, 24, 12))
    path = tmp_path / "t.ply"
    path.write_bytes(_ply(v, f, fmt, **kw))
    exact = np.asarray(v, np.float32 if kw.get("vtype", "float") == "float" else np.float64)
    np.testing.assert_array_equal(load(path).triangles, exact[f])


def _hostile_plys(folder):
    """Files meant to hang or crash a reader, each with a word its refusal must say."""
    v, f = _welded(box())
    good = _ply(v, f)
    header = good[:good.index(b"end_header\n") + len(b"end_header\n")]
    rng = np.random.default_rng(3)
    cases = {
        "only_ply.ply": (b"ply\n", "ends early"),
        "no_end.ply": (b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", "ends early"),
        "no_format.ply": (b"ply\nelement vertex 0\nend_header\n", "format"),
        "not_ply.ply": (b"solid x\nendsolid x\n", "'ply'"),
        "binary_header.ply": (b"ply\n" + bytes(range(256)) + b"\nend_header\n", "ASCII"),
        "binary_junk.ply": (b"ply\n" + bytes(range(256)) * 300, "64 KiB"),
        "endless_comments.ply": (b"ply\nformat ascii 1.0\n" + b"comment x\n" * 10000, "64 KiB"),
        "negative_count.ply": (b"ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "element"),
        "trillion.ply": (header.replace(b"vertex 8", b"vertex 1000000000000") + good[len(header):], "claims"),
        "trillion_faces.ply": (header.replace(b"face 12", b"face 1000000000000") + good[len(header):], "claims"),
        "half_vertices.ply": (good[:len(header) + 40], "claims"),
        "half_faces.ply": (good[:-30], "faces"),
        "garbage_body.ply": (header + rng.integers(0, 256, len(good) - len(header), np.uint8).tobytes(), "PLY"),
        "counts_255.ply": (header + bytes(96) + b"\xff" * 200, "PLY"),
        "ascii_short.ply": (_ply(v, f, "ascii").replace(b"vertex 8", b"vertex 9"), "PLY"),
        "ascii_truncated.ply": (_ply(v, f, "ascii")[:-20], "PLY"),
        # numpy's genfromtxt (in meshio) reads words as NaN: refused as such.
        "ascii_words.ply": (_ply(v, f, "ascii").replace(b"\n1.0 0.0 0.0\n", b"\nx y z\n", 1), "NaN"),
        "int_coordinates.ply": (good.replace(b"float x", b"uchar x"), "'uchar'"),
        "short_type.ply": (good.replace(b"int vertex", b"short vertex"), "'short'"),
        "face_colours.ply": (good.replace(b"end_header", b"property uchar red\nend_header"), "besides"),
        "edges_first.ply": (good.replace(b"element face", b"element edge 0\nelement face"), "'edge'"),
        "two_corners.ply": (_ply(v, f[:, :2], "ascii"), "fewer than three"),
        "two_corners_binary.ply": (_ply(v, f[:, :2]), "claims"),
        "index_beyond.ply": (_ply(v, f + 5), "does not exist"),
        "empty.ply": (b"", "empty"),
    }
    for name, (data, _) in cases.items():
        (folder / name).write_bytes(data)
    return {name: reason for name, (_, reason) in cases.items()}


def _outcomes(folder):
    """What loading each file of `folder` gives ('loaded', the refusal, or 'CRASH ...'), in a child process
    under a timeout: a reader that loops again fails the test instead of hanging the suite."""
    import json
    import subprocess
    import sys
    script = ("import json, sys, pathlib, slicelab\nout = {}\n"
              "for p in sorted(pathlib.Path(sys.argv[1]).iterdir()):\n"
              "    try:\n        slicelab.load(p); out[p.name] = 'loaded'\n"
              "    except slicelab.MeshFileError as e:\n        out[p.name] = str(e)\n"
              "    except BaseException as e:\n        out[p.name] = 'CRASH ' + type(e).__name__ + ': ' + str(e)\n"
              "print(json.dumps(out))\n")
    r = subprocess.run([sys.executable, "-W", "error::RuntimeWarning", "-c", script, str(folder)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_hostile_ply_files_are_refused_quickly(tmp_path):
    reasons = _hostile_plys(tmp_path)
    got = _outcomes(tmp_path)
    for name, reason in reasons.items():
        msg = got[name]
        assert msg.startswith(str(tmp_path / name)) and reason in msg and "\n" not in msg, (name, msg)


def test_mangled_files_load_or_are_refused_in_one_line(tmp_path):
    # Bytes changed, cut, repeated or inserted at random in a PLY, an OBJ and a 3MF's model: each file
    # must load or be refused with one MeshFileError, quickly, without another exception or a warning.
    rng = np.random.default_rng(7)
    mesh = torus(30, 10, 12, 6)
    v, f = _welded(mesh)
    n = len(v)
    seeds = {"ply": _ply(v, f), "ascii.ply": _ply(v, f, "ascii"),
             "obj": ("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v.tolist())
                     + "".join(f"f {a + 1}/1 {b - n} {c + 1}//2\n" for a, b, c in f.tolist())).encode(),
             "3mf": _model(_mesh_xml(mesh, 1) + '<object id="2"><components><component objectid="1" transform="1 0 0 '
                           '0 1 0 0 0 1 5 5 5"/></components></object>', [(2, _motion(10, (0, 1, 0), (1, 2, 3)))]).encode()}
    inserts = [b"-", b"99999999999999999999999", b"\n", b'"', b"<", b"/>", b" ", b"e39", b"nan", b"&#49;", b"<!--"]
    for k in range(60):
        for ending, seed in seeds.items():
            data = bytearray(seed)
            for _ in range(rng.integers(1, 5)):
                at, op = int(rng.integers(0, len(data))), rng.integers(0, 4)
                if op == 0:
                    data[at] = int(rng.integers(0, 256))
                elif op == 1:
                    data[at:at] = inserts[rng.integers(len(inserts))]
                elif op == 2:
                    del data[at:at + int(rng.integers(1, 40))]
                else:
                    data = data[:at]
            path = tmp_path / f"m{k}.{ending}"
            if ending == "3mf":
                _write_3mf(path, bytes(data))
            else:
                path.write_bytes(bytes(data))
    got = _outcomes(tmp_path)
    assert len(got) == 240 and not [m for m in got.values() if m.startswith("CRASH") or "\n" in m]
    assert sum(m != "loaded" for m in got.values()) > 150  # most mangled files are refused


def test_obj_relative_indices_and_corner_forms_give_the_same_mesh(tmp_path):
    v, f = _welded(torus(30, 10, 24, 12))
    verts = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v.tolist())
    (tmp_path / "pos.obj").write_text(verts + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f.tolist()))
    n = len(v)
    (tmp_path / "neg.obj").write_text(verts + "".join(f"f {a - n} {b - n} {c - n}\n" for a, b, c in f.tolist()))
    (tmp_path / "slashes.obj").write_text(
        verts + "vt 0 0\nvn 0 0 1\n" + "".join(f"f {a + 1}/1/1 {b - n}//1 {c + 1}/1\n" for a, b, c in f.tolist()))
    a = load(tmp_path / "pos.obj")
    np.testing.assert_array_equal(a.triangles, v[f])
    for name in ("neg.obj", "slashes.obj"):
        np.testing.assert_array_equal(load(tmp_path / name).triangles, a.triangles)


def test_obj_relative_index_counts_back_from_its_own_line(tmp_path):
    # Each face names the three vertices just before it, not the file's last three.
    path = tmp_path / "two.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 5\nv 1 0 5\nv 0 1 5\nf -3 -2 -1\n")
    t = load(path).triangles
    assert t[:, :, 2].tolist() == [[0, 0, 0], [5, 5, 5]]


def test_obj_in_every_spacing_mixing_triangles_and_quads(tmp_path):
    # The unit cube: two quads, the rest as triangles, with tabs, CRLF, indentation, comments, a continuation.
    v = "".join(f"  v\t{x} {y} {z}  # corner\r\n" for x in (0, 1) for y in (0, 1) for z in (0, 1))
    quads = ["f 1 2 4 3", "f 5 7 8 6"]
    tris = ["f 1 5 6", "f 1 6 2", "f 3 4 8", "f 3 8 7", "f 1 3 7", "f 1 7 5", "f 2 6 8", "f 2 8 4"]
    faces = [q.replace(" ", "/1/1 ").replace("f/1/1", "f") + "/1/1" for q in quads] + tris
    faces[-1] = "f 2 \\\n 8 4"
    path = tmp_path / "cube.obj"
    path.write_text("# cube\nvt 0 0\nvn 0 0 1\no cube\ng side\n" + v + "\r\n".join(faces) + "\r\n")
    r = check(load(path))
    assert r.n_facets == 12 and r.watertight and r.volume == pytest.approx(1.0)


@pytest.mark.parametrize("faces, reason", [
    ("f 1 2 99999999999999999999999\n", "out of range"),
    ("f 1 2 3\nf 1 2 3 99999999999999999999999\n", "out of range"),
    ("f 1 2 3 4\nf 1 2 -99999999999999999999999\n", "out of range"),
    ("f 0 1 2\n", "index 0"),
    ("f 1 2 4\n", "vertex 4 of 3"),
    ("f -4 -2 -1\n", "before the first vertex"),
    ("f 1 2\n", "fewer than three"),
    ("f 1/1 2/2 /3 3/3\n", "without its vertex number"),
    ("f 1 2 x\n", "'x' is not a number"),
    ("f 1 2 3 # a triangle\nf 1 2 3 x\n", "'x' is not a number"),
    ("f\n", "holds no numbers"),
    ("f # nothing\n", "holds no numbers"),
])
def test_bad_obj_faces_are_refused(tmp_path, faces, reason):
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n" + faces)
    _refused(path, "OBJ", reason)


@pytest.mark.parametrize("name, text, reason", [
    ("far.obj", "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "beyond single precision"),
    ("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "NaN or infinite"),
    ("inf.obj", "v 0 -inf 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "NaN or infinite"),
    ("short.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "fewer than three coordinates"),
])
def test_obj_coordinates_beyond_float32_or_not_finite_are_refused(tmp_path, name, text, reason):
    (tmp_path / name).write_text(text)
    _refused(tmp_path / name, reason)


@pytest.mark.parametrize("fmt, value, reason", [
    ("ascii", 1e39, "beyond single precision"), ("binary_little_endian", -1e39, "beyond single precision"),
    ("binary_big_endian", np.nan, "NaN or infinite"), ("ascii", np.inf, "NaN or infinite")])
def test_ply_coordinates_beyond_float32_or_not_finite_are_refused(tmp_path, fmt, value, reason):
    v, f = _welded(box())
    v[3, 1] = value
    (tmp_path / "far.ply").write_bytes(_ply(v, f, fmt, vtype="double"))
    _refused(tmp_path / "far.ply", reason)


def test_scaling_beyond_float32_is_refused(tmp_path):
    v, f = _welded(box())
    (tmp_path / "big.ply").write_bytes(_ply(v * 1e36, f, vtype="double"))
    assert check(load(tmp_path / "big.ply")).watertight
    with pytest.raises(MeshFileError, match="beyond single precision"):
        load(tmp_path / "big.ply", units="m")


# --- 3MF -----------------------------------------------------------------------------------------------

_CORE = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
_PROD = "http://schemas.microsoft.com/3dmanufacturing/production/2015/06"
_RELS = ('<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/'
         '2006/relationships"><Relationship Target="/{target}" Id="rel0" '
         'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>')


def _mesh_xml(mesh, oid, attrs=""):
    v, f = _welded(mesh)
    verts = "".join(f'<vertex x="{x!r}" y="{y!r}" z="{z!r}"/>\n' for x, y, z in v.tolist())
    tris = "".join(f'<triangle v1="{a}" v2="{b}" v3="{c}"{attrs}/>\n' for a, b, c in f.tolist())
    return (f'<object id="{oid}" type="model"><mesh><vertices>\n{verts}</vertices><triangles>\n{tris}'
            f'</triangles></mesh></object>\n')


def _transform(m):
    """The 12 numbers of a 4 x 4 column-vector matrix, in 3MF's row-vector order."""
    return " ".join(repr(float(x)) for x in np.asarray(m, float)[:3, :4].T.ravel())


def _model(resources, items, unit="millimeter", head=""):
    build = "".join(f'<item objectid="{oid}"' + (f' transform="{_transform(m)}"' if m is not None else "") + "/>"
                    for oid, m in items)
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<model unit="{unit}" xml:lang="en-US" xmlns="{_CORE}" '
            f'xmlns:p="{_PROD}"{head}>\n<resources>\n{resources}</resources>\n<build>{build}</build>\n</model>\n')


def _write_3mf(path, model, parts=None, rels=True, name="3D/3dmodel.model"):
    import zipfile
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml", '<?xml version="1.0"?><Types xmlns="http://schemas.openxmlformats.org/'
                   'package/2006/content-types"><Default Extension="model" ContentType="application/'
                   'vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>')
        if rels:
            z.writestr("_rels/.rels", _RELS.format(target=name))
        if model is not None:
            z.writestr(name, model)
        for part, text in (parts or {}).items():
            z.writestr(part, text)
    return path


def _motion(angle_deg, axis, shift, scale=1.0):
    from scipy.spatial.transform import Rotation
    m = np.eye(4)
    m[:3, :3] = Rotation.from_rotvec(np.radians(angle_deg) * np.asarray(axis, float)).as_matrix() * scale
    m[:3, 3] = shift
    return m


def _corners(lo, hi, m):
    c = np.array([[x, y, z, 1] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    return (c @ np.asarray(m).T)[:, :3]


def test_3mf_build_item_transform_places_the_mesh(tmp_path):
    m = _motion(30, (0, 0, 1), (100, 50, 5))
    path = _write_3mf(tmp_path / "box.3mf", _model(_mesh_xml(box((0, 0, 0), (10, 20, 30)), 1), [(1, m)]))
    mesh = load(path)
    r = check(mesh)
    assert r.watertight and r.volume == pytest.approx(6000, rel=1e-12)
    expect = _corners((0, 0, 0), (10, 20, 30), m)
    np.testing.assert_allclose(mesh.triangles.reshape(-1, 3).min(0), expect.min(0), atol=1e-12)
    np.testing.assert_allclose(mesh.triangles.reshape(-1, 3).max(0), expect.max(0), atol=1e-12)


def test_3mf_components_nested_and_mirrored(tmp_path):
    # Object 3 holds object 2 twice (once mirrored) and object 1; object 2 holds object 1 moved and scaled.
    s = _motion(0, (0, 0, 1), (50, 0, 0), scale=2.0)
    mirror = np.diag([-1.0, 1, 1, 1]) @ _motion(0, (0, 0, 1), (0, 100, 0))
    item = _motion(90, (1, 0, 0), (0, 0, 7))
    resources = (_mesh_xml(box((0, 0, 0), (1, 2, 3)), 1)
                 + f'<object id="2" type="model"><components><component objectid="1" transform="{_transform(s)}"/>'
                 f'</components></object>\n<object id="3" type="model"><components><component objectid="2"/>'
                 f'<component objectid="2" transform="{_transform(mirror)}"/><component objectid="1"/></components>'
                 f'</object>\n')
    mesh = load(_write_3mf(tmp_path / "parts.3mf", _model(resources, [(3, item)])))
    r = check(mesh)
    assert r.n_shells == 3 and r.watertight and r.n_misoriented_edges == 0
    assert r.volume == pytest.approx(6 * 8 + 6 * 8 + 6, rel=1e-12)
    expect = np.concatenate([_corners((0, 0, 0), (1, 2, 3), item @ t) for t in (s, mirror @ s, np.eye(4))])
    np.testing.assert_allclose(np.sort(np.unique(mesh.triangles.reshape(-1, 3).round(9), axis=0), axis=0),
                               np.sort(np.unique(expect.round(9), axis=0), axis=0))


@pytest.mark.parametrize("unit, mm", [("micron", 0.001), ("centimeter", 10.0), ("inch", 25.4), ("foot", 304.8),
                                      ("meter", 1000.0), ("millimeter", 1.0)])
def test_3mf_units_become_millimetres(tmp_path, unit, mm):
    path = _write_3mf(tmp_path / "u.3mf", _model(_mesh_xml(box((0, 0, 0), (1, 2, 3)), 7), [(7, None)], unit=unit))
    assert check(load(path)).volume == pytest.approx(6 * mm ** 3, rel=1e-12)


def test_3mf_written_otherwise_reads_the_same(tmp_path):
    # Other attribute orders and quotes, comments, entities and painted triangles: the same mesh.
    mesh = torus(30, 10, 24, 12)
    plain = load(_write_3mf(tmp_path / "plain.3mf", _model(_mesh_xml(mesh, 1), [(1, None)])))
    painted = _model(_mesh_xml(mesh, 1, ' slic3rpe:mmu_segmentation="4"'), [(1, None)],
                     head=' xmlns:slic3rpe="http://schemas.slic3r.org/3mf/2017/06"')
    v, f = _welded(mesh)
    odd = "".join(f"<vertex z='{z!r}' x=\"{x!r}\"  y=\"{y!r}\" />" for x, y, z in v.tolist())
    odd = odd.replace("<vertex", "<!-- a comment --><vertex", 1).replace('x="0.0"', 'x="&#48;.0"')
    odd_model = _model(_mesh_xml(mesh, 1), [(1, None)])
    odd_model = odd_model[:odd_model.index("<vertices>") + 10] + odd + odd_model[odd_model.index("</vertices>"):]
    prefixed = _model(_mesh_xml(mesh, 1), [(1, None)]).replace("<", "<m:").replace("<m:/", "</m:")
    prefixed = prefixed.replace("<m:?xml", "<?xml").replace(f'xmlns="{_CORE}"', f'xmlns:m="{_CORE}"')
    for name, text in [("painted", painted), ("odd", odd_model), ("prefixed", prefixed)]:
        got = load(_write_3mf(tmp_path / f"{name}.3mf", text))
        np.testing.assert_array_equal(got.triangles, plain.triangles, err_msg=name)
    np.testing.assert_array_equal(plain.triangles, v[f])


def test_3mf_other_model_parts_and_a_zip_without_the_ending(tmp_path):
    # Components in another part (the production extension's p:path, as Bambu Studio writes), no _rels.
    part = _model(_mesh_xml(box((0, 0, 0), (2, 2, 2)), 5), [])
    root = _model('<object id="1" type="model"><components><component p:path="/3D/Objects/o.model" objectid="5" '
                  f'transform="{_transform(_motion(0, (0, 0, 1), (10, 0, 0)))}"/></components></object>\n', [(1, None)],
                  head=' requiredextensions="p"')
    path = _write_3mf(tmp_path / "project", root, {"3D/Objects/o.model": part}, rels=False)
    mesh = load(path)
    assert check(mesh).volume == pytest.approx(8.0) and mesh.triangles[..., 0].min() == pytest.approx(10.0)


def test_3mf_as_trimesh_writes_it(tmp_path):
    pytest.importorskip("lxml")  # trimesh's 3MF export needs it
    import trimesh
    m = trimesh.creation.box((10, 20, 30))
    m.apply_translation((5, 5, 5))
    (tmp_path / "t.3mf").write_bytes(m.export(file_type="3mf"))
    r = check(load(tmp_path / "t.3mf"))
    assert r.watertight and r.volume == pytest.approx(6000)


def test_3mf_from_the_command_line(tmp_path):
    import subprocess
    import sys
    path = _write_3mf(tmp_path / "box.3mf", _model(_mesh_xml(box((0, 0, 0), (10, 20, 30)), 1), [(1, None)]))
    r = subprocess.run([sys.executable, "-m", "slicelab", "inspect", str(path)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    assert "10 x 20 x 30" in r.stdout and "watertight        yes" in r.stdout


def _bad_3mfs(folder):
    import zipfile
    good = _model(_mesh_xml(box(), 1), [(1, None)])
    cycle = ('<object id="1"><components><component objectid="2"/></components></object>'
             '<object id="2"><components><component objectid="3"/></components></object>'
             '<object id="3"><components><component objectid="1"/></components></object>')
    doubling = "".join(f'<object id="{k}"><components><component objectid="{k - 1}"/><component objectid="{k - 1}"/>'
                       f'</components></object>' for k in range(2, 40))
    cases = {
        "not_zip.3mf": ("solid x\nendsolid x\n", "not a ZIP"),
        "no_model.3mf": (None, "no part '3D/3dmodel.model'"),
        "malformed.3mf": (good.replace("</resources>", "</resource>"), "malformed XML"),
        "unclosed.3mf": (good[:good.index("</vertices>")], "malformed XML"),
        "not_model.3mf": ("<?xml version='1.0'?><html/>", "not a 3MF model"),
        "index.3mf": (good.replace('v3="2"', 'v3="8"', 1), "names vertex 8 of 8"),
        "negative_index.3mf": (good.replace('v3="2"', 'v3="-1"', 1), "names vertex -1"),
        "huge_index.3mf": (good.replace('v3="2"', 'v3="99999999999999999999999"', 1), "triangles of object 1"),
        "word.3mf": (good.replace('x="1.0"', 'x="one"', 1), "vertices of object 1"),
        "missing_attribute.3mf": (good.replace(' y="0.0"', "", 1), "lacks one of x, y, z"),
        "cycle.3mf": (_model(_mesh_xml(box(), 9) + cycle, [(1, None)]), "cycle (objects 1 -> 2 -> 3 -> 1)"),
        "self.3mf": (_model('<object id="1"><components><component objectid="1"/></components></object>',
                            [(1, None)]), "cycle"),
        "doubling.3mf": (_model(_mesh_xml(box(), 1) + doubling, [(39, None)]), "repeats its components"),
        "no_object.3mf": (_model(_mesh_xml(box(), 1), [(4, None)]), "no object 4"),
        "no_build.3mf": (_model(_mesh_xml(box(), 1), []), "no build items"),
        "unit.3mf": (good.replace('unit="millimeter"', 'unit="furlong"'), "'furlong'"),
        "transform.3mf": (good.replace('<item objectid="1"', '<item objectid="1" transform="1 0 0 1"'), "transform"),
        "nan_transform.3mf": (good.replace('<item objectid="1"', '<item objectid="1" transform="1 0 0 0 1 0 0 0 1 '
                                                                 'nan 0 0"'), "transform"),
        "dtd.3mf": (good.replace("<model", '<!DOCTYPE m [<!ENTITY a "aaaa">]><model', 1), "DTD"),
        "extension.3mf": (good.replace("<model", '<model requiredextensions="b" xmlns:b="http://schemas.microsoft.com/'
                                               '3dmanufacturing/beamlattice/2017/02"', 1), "beamlattice"),
        "other.3mf": (good.replace('type="model"', 'type="other"'), "'other'"),
        "far.3mf": (good.replace('x="1.0"', 'x="1e39"'), "beyond single precision"),
        "path.3mf": (good.replace('<item objectid="1"', '<item p:path="/3D/missing.model" objectid="1"'),
                     "no part '3D/missing.model'"),
    }
    for name, (text, _) in cases.items():
        if name == "not_zip.3mf":
            (folder / name).write_text(text)
        else:
            _write_3mf(folder / name, text)
    # A zip bomb: 64 MiB of spaces deflate to some 64 KiB.
    with zipfile.ZipFile(folder / "bomb.3mf", "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("3D/3dmodel.model", good.replace("<build>", " " * (64 << 20) + "<build>"))
    cases["bomb.3mf"] = (None, "zip bomb")
    # A declared size that lies: 4 GiB in both headers, a small deflated body.
    data = bytearray((folder / "no_build.3mf").read_bytes())
    name = b"3D/3dmodel.model"
    for sig, offset in ((b"PK\x03\x04", 22), (b"PK\x01\x02", 24)):
        at = data.index(sig, 0)
        while data[at + (30 if sig == b"PK\x03\x04" else 46):][:len(name)] != name:
            at = data.index(sig, at + 4)
        data[at + offset:at + offset + 4] = (0xFFFFFFF0).to_bytes(4, "little")
    (folder / "liar.3mf").write_bytes(bytes(data))
    cases["liar.3mf"] = (None, "zip bomb")
    return {name: reason for name, (_, reason) in cases.items()}


def test_bad_3mf_files_are_refused_in_one_line(tmp_path):
    for name, reason in _bad_3mfs(tmp_path).items():
        _refused(tmp_path / name, reason)


def test_a_zip_that_is_not_a_3mf_says_so(tmp_path):
    import zipfile
    with zipfile.ZipFile(tmp_path / "photos.stl", "w") as z:
        z.writestr("a.txt", "hello")
    _refused(tmp_path / "photos.stl", "a ZIP archive, not a 3MF")
