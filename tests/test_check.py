"""Mesh checks against meshes with known, built-in defects, and exact welding."""
import numpy as np
import pytest

import slicelab
from slicelab import Mesh, check
from slicelab.geometry import topology
from slicelab.samples import box, cube_with_hole, nested_shells, overlapping_cubes, sphere, torus


def test_clean_solids_report_no_defects():
    for m, shells in [(box(), 1), (torus(30, 10, 24, 12), 1), (cube_with_hole(n=16), 1),
                      (nested_shells(), 3), (overlapping_cubes(), 2)]:
        r = check(m)
        assert r.watertight and r.winding_consistent
        assert (r.n_open_edges, r.n_nonmanifold_edges, r.n_degenerate, r.n_flipped_normals) == (0, 0, 0, 0)
        assert r.n_shells == shells


def test_box_volume_area_and_counts_are_exact():
    r = check(box((1, 2, 3), (4, 6, 8)))
    assert r.volume == pytest.approx(60.0, rel=1e-14)
    assert r.area == pytest.approx(2 * (12 + 15 + 20), rel=1e-14)
    assert (r.n_facets, r.n_vertices) == (12, 8)
    assert r.bounds == ((1.0, 2.0, 3.0), (4.0, 6.0, 8.0))


def test_removed_facet_leaves_three_open_edges():
    t = box().triangles
    r = check(Mesh(t[1:]))
    assert r.n_open_edges == 3 and not r.watertight


def test_duplicated_facet_makes_three_nonmanifold_edges():
    t = box().triangles
    r = check(Mesh(np.concatenate([t, t[:1]])))
    assert r.n_nonmanifold_edges == 3 and not r.watertight


def test_reversed_facet_makes_three_misoriented_edges():
    t = box().triangles.copy()
    t[4] = t[4][::-1]
    r = check(Mesh(t))
    assert r.n_misoriented_edges == 3 and r.watertight and not r.winding_consistent


def test_flipped_and_zero_stored_normals():
    m = torus(30, 10, 12, 6)
    fn = m.normals.copy()
    fn[[0, 5, 7]] *= -1          # flipped: 180 degrees off
    fn[9] = 0.0                  # zero normal, as many exporters write: not flipped
    rot = np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1.0]])
    fn[11] = fn[11] @ rot.T      # 90 degrees off: not more than 90
    assert check(Mesh(m.triangles, fn)).n_flipped_normals == 3


def test_degenerate_facets_are_counted():
    t = box().triangles
    sliver = np.array([[[0, 0, 0], [1, 1, 1], [2, 2, 2]], [[0, 0, 0], [0, 0, 0], [1, 0, 0]]], float)
    assert check(Mesh(np.concatenate([t, sliver]))).n_degenerate == 2


def test_shells_and_volume_of_nested_sample():
    r = check(nested_shells())
    assert r.n_shells == 3
    assert r.volume == pytest.approx(40**3 - 24**3 + 10**3, rel=1e-12)


def test_welding_matches_numpy_unique():
    m = sphere(10, 12, 24)
    v, f = topology.weld(m.triangles)
    uniq = np.unique(m.triangles.reshape(-1, 3), axis=0)
    assert len(v) == len(uniq)
    np.testing.assert_array_equal(v[f], m.triangles)


@pytest.mark.parametrize("hash_of", ["first column", "constant"])
def test_exact_ids_survive_hash_collisions(monkeypatch, hash_of):
    rng = np.random.default_rng(1)
    rows = rng.integers(0, 7, size=(5000, 3)).astype(float)
    rows[rows == 0] = -0.0  # -0.0 must weld with 0.0

    def bad_hash(bits, out=None):
        out = np.empty(len(bits), np.uint64) if out is None else out
        out[:] = bits[:, 0] if hash_of == "first column" else 12345
        return out

    # Hashes that collide constantly: every row probes past many others, exactness must hold.
    monkeypatch.setattr(topology, "_row_hash", bad_hash)
    ids, first = topology.exact_ids(rows)
    _, expected = np.unique(rows + 0.0, axis=0, return_inverse=True)
    expected = expected.reshape(-1)
    # Same partition: ids and expected determine each other.
    assert len(set(zip(ids.tolist(), expected.tolist()))) == len(first) == expected.max() + 1
    np.testing.assert_array_equal(rows[first][ids] + 0.0, rows + 0.0)
    # `first` is each id's lowest row.
    lowest = np.full(len(first), len(rows))
    np.minimum.at(lowest, ids, np.arange(len(rows)))
    np.testing.assert_array_equal(first, lowest)


def test_exact_ids_threaded_halves_agree_with_numpy(monkeypatch):
    # Big tables are hashed and verified by two threads; force that path on a small table.
    monkeypatch.setattr(topology, "_THREADED_ROWS", 1)
    rng = np.random.default_rng(2)
    rows = rng.integers(-3, 4, size=(20001, 2)).astype(float) / 4
    ids, first = topology.exact_ids(rows)
    _, expected = np.unique(rows + 0.0, axis=0, return_inverse=True)
    assert len(set(zip(ids.tolist(), expected.reshape(-1).tolist()))) == len(first) == expected.max() + 1
    np.testing.assert_array_equal(rows[first][ids], rows)
    ints = rng.integers(0, 50, 30000)
    ids, first = topology.exact_ids(ints)
    np.testing.assert_array_equal(ints[first][ids], ints)
    assert len(first) == len(np.unique(ints))


def test_sphere_volume_agrees_with_trimesh():
    trimesh = pytest.importorskip("trimesh")
    m = sphere(20, 24, 48)
    v, f = topology.weld(m.triangles)
    tm = trimesh.Trimesh(v, f, process=False)
    r = check(m)
    assert r.volume == pytest.approx(tm.volume, rel=1e-12)
    assert r.watertight == tm.is_watertight
    assert r.area == pytest.approx(tm.area, rel=1e-12)


def test_empty_mesh_report():
    r = check(Mesh(np.zeros((0, 3, 3))))
    assert r.n_facets == 0 and not r.watertight


def test_report_to_dict_and_text():
    r = check(box())
    d = r.to_dict()
    assert d["watertight"] is True and d["winding_consistent"] is True
    assert "watertight        yes" in str(r)


def test_sample_files_match_their_generator(tmp_path, data_dir):
    import subprocess
    import sys
    subprocess.run([sys.executable, str(data_dir.parent / "scripts" / "make_data.py"), "--out", str(tmp_path)],
                   check=True, capture_output=True)
    for p in sorted(data_dir.glob("*.stl")):
        assert (tmp_path / p.name).read_bytes() == p.read_bytes(), p.name
        assert p.stat().st_size < 1_000_000
        assert slicelab.check(slicelab.load(p)).watertight


def _touching_blocks() -> Mesh:
    """Two 10 x 10 x 2 mm blocks meeting along one vertical edge (x = y = 10): four facets use it."""
    return slicelab.samples.concat(box((0, 0, 0), (10, 10, 2)), box((10, 10, 0), (20, 20, 2)))


def test_shells_touching_along_an_edge_are_closed_by_winding_and_a_fin_is_not():
    r = check(_touching_blocks())
    assert not r.watertight and r.n_nonmanifold_edges > 0
    assert r.n_unbalanced_edges == 0 and r.closed_by_winding
    assert r.to_dict()["closed_by_winding"] is True
    assert "closed by winding number" in str(r)
    # A fin: one more facet hanging off an edge of the block (walked one way only).
    b = box((0, 0, 0), (10, 10, 2))
    fin = np.array([[[0, 0, 0], [10, 0, 0], [5, -5, 1]]], float)
    for bad in (Mesh(np.concatenate([b.triangles, fin])), Mesh(b.triangles[1:])):
        r = check(bad)
        assert r.n_unbalanced_edges > 0 and not r.closed_by_winding
    for good in (box(), torus(30, 10, 24, 12), nested_shells()):
        assert check(good).n_unbalanced_edges == 0


def test_slice_prints_shells_touching_along_an_edge_and_says_so(tmp_path):
    """Sliced by winding number, with a non_manifold warning: as much material as the two blocks
    planned one by one."""
    import subprocess
    import sys

    from slicelab.printing import PrintSettings, plan
    part = tmp_path / "touching.stl"
    slicelab.save(_touching_blocks(), part)
    out = tmp_path / "t.gcode"
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(part), "-o", str(out), "--workers", "1"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "non-manifold edges" in r.stderr and "winding number" in r.stderr
    assert out.read_text().count(";LAYER_CHANGE") == 10
    s = PrintSettings(skirt_loops=0, pixel_size=0.1)
    both = plan(slicelab.load(part), s, workers=1).extruded_volume
    one = plan(box((0, 0, 0), (10, 10, 2)), s, workers=1).extruded_volume
    assert both == pytest.approx(2 * one, rel=0.02)
