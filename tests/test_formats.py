"""PLY (binary and ASCII) and OBJ read as the same mesh as STL; bad files refused; units."""
from __future__ import annotations

import meshio
import numpy as np
import pytest

import slicelab
from slicelab import MeshFileError, check, load, save
from slicelab.geometry import weld
from slicelab.samples import pot, torus


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
