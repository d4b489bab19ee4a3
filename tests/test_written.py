"""What is written is what is reported: cut, split and partition outputs read back from disk."""
from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import slicelab
from slicelab import Mesh, check
from slicelab.geometry import weld
from slicelab.samples import pot, torus
from slicelab.tasks import run_job


@pytest.fixture(scope="module")
def scan_like():
    """A pot of about 100 k facets whose vertices carry 0.05 mm of noise (still one closed shell)."""
    v, f = weld(pot(80, 320).triangles)
    rng = np.random.default_rng(3)
    m = Mesh.from_vertices_faces(v + rng.normal(0, 0.05, v.shape), f)
    assert len(m) > 90_000 and check(m).watertight
    return m


def _tight_on_disk(path) -> bool:
    r = check(slicelab.load(path))
    return r.watertight and r.winding_consistent


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                  HealthCheck.function_scoped_fixture])
@given(seed=st.integers(0, 2 ** 32 - 1))
def test_cut_parts_of_a_scan_are_watertight_on_disk(seed, scan_like, tmp_path_factory):
    rng = np.random.default_rng(seed)
    lo, hi = scan_like.bounds
    origin = lo + rng.uniform(0.2, 0.8, 3) * (hi - lo)
    normal = rng.normal(size=3)
    out = tmp_path_factory.mktemp("cut")
    r = run_job("cut", "scan.stl", {"plane": (origin, normal), "preview": False}, out, mesh=scan_like)
    for name in ("rear", "front"):
        if name in r.results:
            assert _tight_on_disk(out / f"{name}.stl")
            assert r.results[name]["watertight"]


def test_split_pieces_written_are_what_the_split_made(tmp_path):
    m = torus(30, 10, 96, 48)
    r = run_job("split", "torus.stl", {"plane": ((0, 0, 0), (0.2, 0.3, 1)), "preview": False}, tmp_path, mesh=m)
    sp = r.value[2]
    for side in ("front", "rear"):
        back = slicelab.load(tmp_path / f"{side}.stl")
        assert len(back) == len(getattr(sp, side)) - r.results[f"{side}_collapsed_in_float32"]


def test_stair_partition_of_a_scan_fits_and_is_watertight_on_disk(scan_like, tmp_path):
    r = run_job("partition", "scan.stl", {"volume": (70, 70, 70), "joint": "stair", "step": (8, 12),
                                          "preview": False}, tmp_path, mesh=scan_like)
    report = json.loads((tmp_path / "parts.json").read_text())
    assert len(report["pieces"]) >= 4
    total = 0.0
    for info in report["pieces"]:
        piece = slicelab.load(tmp_path / info["file"])
        assert _tight_on_disk(tmp_path / info["file"]) and info["watertight"]
        lo, hi = piece.bounds
        assert np.all(lo >= -1e-4) and np.all(hi <= 70 + 1e-4), (info["file"], lo, hi)
        total += check(piece).volume
    assert total == pytest.approx(check(scan_like).volume, rel=1e-5)
    assert r.results["watertight"]


# ------------------------------------------------------------------ vertices float32 merges
_TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def _tetrahedra_a_gap_apart(gap: float, corner=(10.0, 3.0, 1.0)) -> Mesh:
    """Two tetrahedra sharing a corner whose edges from it end `gap` apart (two closed shells)."""
    c = np.array(corner)
    one = np.array([[0, 0, 0], c, [0, 10, 0], [0, 0, 10]], float)
    two = np.array([[0, 0, 0], c + (gap, 0, 0), [0, -10, 0], [0, 0, -10]], float)
    return Mesh(np.concatenate([one[_TET_FACES], two[_TET_FACES]]))


@pytest.mark.parametrize("gap, corner", [(1e-9, (10.0, 3.0, 1.0)), (4e-7, (10.0, 3.0, 1.0)),
                                         (1e-5, (500.0, 300.0, 100.0))])
def test_vertices_that_float32_merges_stay_apart_in_the_file(gap, corner, tmp_path):
    from slicelab.mesh.written import as_float32, write_mesh
    m = _tetrahedra_a_gap_apart(gap, corner)
    assert check(m).watertight and check(m).n_shells == 2
    rounded = check(as_float32(m)[0])
    assert rounded.n_nonmanifold_edges == 1 and not rounded.watertight  # rounding alone loses it
    w = write_mesh(m, tmp_path / "two.stl")
    back = slicelab.load(tmp_path / "two.stl")
    r = check(back)
    assert r.watertight and r.winding_consistent and r.n_shells == 2 and r == w.report
    assert w.n_moved == 1 and w.n_collapsed == 0 and r.n_vertices == check(m).n_vertices
    # The moved corner is one float32 step from its place; the volume is the mesh's.
    step = np.spacing(np.float32(max(abs(x) for x in corner)))
    assert np.abs(back.triangles - m.triangles).max() <= 1.5 * step
    assert r.volume == pytest.approx(check(m).volume, rel=1e-6)


def test_cut_points_float32_merges_stay_apart_in_the_written_parts(tmp_path):
    # The plane crosses both near edges: their cut points lie ~1e-9 apart, one float32 point.
    m = _tetrahedra_a_gap_apart(1e-9)
    origin, normal = (5.0, 0.0, 0.0), (1.0, 0.2, 0.1)
    parts = slicelab.cut(m, origin, normal)
    from slicelab.mesh.written import as_float32
    assert any(check(p).watertight and not check(as_float32(p)[0]).watertight for p in parts)
    r = run_job("cut", "two.stl", {"plane": (origin, normal), "preview": False}, tmp_path, mesh=m)
    for name in ("rear", "front"):
        assert _tight_on_disk(tmp_path / f"{name}.stl") and r.results[name]["watertight"]


@pytest.mark.parametrize("checked", [False, True], ids=["unchecked", "checked"])
def test_the_file_holds_the_float32_facets_and_their_winding_normals(checked, tmp_path):
    from slicelab.mesh.written import write_mesh
    from slicelab.geometry.triangles import winding_normals
    from slicelab.mesh.io import STL_RECORD
    # A torus with a sliver whose two corners are one float32 point: that facet is left out.
    t = torus(30, 10, 48, 24).triangles
    sliver = np.array([[[100, 0, 0], [100 + 1e-6, 0, 0], [100.5, 1, 0]]])
    m = Mesh(np.concatenate([t[:100], sliver, t[100:]]))
    w = write_mesh(m, tmp_path / "t.stl", checked=checked)
    raw = (tmp_path / "t.stl").read_bytes()
    assert raw[:80] == b"slicelab t".ljust(80) and int.from_bytes(raw[80:84], "little") == len(t)
    rec = np.frombuffer(raw, STL_RECORD, offset=84)
    expected = np.concatenate([t[:100], t[100:]]).astype(np.float32)
    assert len(raw) == 84 + 50 * len(t) and w.n_collapsed == 1
    assert np.array_equal(rec["vertices"], expected) and not rec["attr"].any()
    assert np.array_equal(rec["normal"], winding_normals(expected).astype(np.float32))
    back = slicelab.load(tmp_path / "t.stl")
    assert np.array_equal(back.triangles, expected.astype(np.float64))
    if checked:
        assert w.report == check(back) and w.report.watertight  # without the stray sliver: the torus
