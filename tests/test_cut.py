"""Watertight cuts: closed parts, exact caps, arbitrary planes, degenerate planes."""
from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import slicelab
from slicelab import Mesh, check, samples
from slicelab.geometry.topology import manifold_summary
from slicelab.slicing.cap import triangle_min_angles
from slicelab.slicing.cut import Cut, CutWarning, cut
from slicelab.slicing.split import split

from conftest import ROOT, random_rotation


def assert_closed(part: Mesh) -> None:
    """Edge-manifold with consistent winding and outward normals, by two independent counts."""
    edges = manifold_summary(part.triangles)
    assert edges.closed, edges
    r = check(part)
    assert r.watertight and r.winding_consistent and r.n_open_edges == 0
    assert r.volume > 0


def assert_cut(mesh: Mesh, origin, normal, *, rel=1e-9) -> Cut:
    parts = cut(mesh, origin, normal)
    v0 = check(mesh).volume
    for part in parts:
        if len(part):
            assert_closed(part)
    total = sum(check(p).volume for p in parts if len(p))
    assert abs(total - v0) <= rel * abs(v0)
    # The cap is the section: same area as the split's own section (same distances).
    sec = split(mesh, origin, normal).section
    assert parts.report.rear_cap.area == pytest.approx(sec.area, rel=1e-9, abs=1e-12)
    return parts


# ------------------------------------------------------------------ basics
def test_box_halves_are_exact():
    parts = cut(samples.box((0, 0, 0), (2, 3, 4)), (0, 0, 1), (0, 0, 1))
    assert isinstance(parts, Cut) and not isinstance(parts, tuple)
    rear, front = parts  # iterating gives (rear, front)
    assert rear is parts.rear and front is parts.front
    assert check(rear).volume == 6.0 and check(front).volume == 18.0
    assert rear.bounds.tolist() == [[0, 0, 0], [2, 3, 1]]
    assert front.bounds.tolist() == [[0, 0, 1], [2, 3, 4]]
    assert_closed(rear)
    assert_closed(front)
    # Rear is against the normal: flipping the normal swaps the parts.
    r2, f2 = cut(samples.box((0, 0, 0), (2, 3, 4)), (0, 0, 1), (0, 0, -1))
    assert check(r2).volume == 18.0 and check(f2).volume == 6.0


def test_cap_normals_point_out_of_each_part():
    parts = cut(samples.sphere(20, 12, 24), (1, 2, 3), (0.3, -0.4, 1.0))
    n = np.array([0.3, -0.4, 1.0]) / np.linalg.norm([0.3, -0.4, 1.0])
    for cap, sign in ((parts.report.rear_cap, 1), (parts.report.front_cap, -1)):
        t = cap.vertices
        normals = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        assert np.all(normals @ n * sign > 0)


def test_cap_vertices_are_the_cut_points_bit_for_bit_on_a_tilted_plane():
    mesh = samples.torus(30, 10, 48, 24).transformed(random_rotation(np.random.default_rng(3)))
    parts = cut(mesh, (1.5, -2.0, 0.7), (0.31, -0.52, 0.8))
    for part, cap in ((parts.rear, parts.report.rear_cap), (parts.front, parts.report.front_cap)):
        side = part.triangles[:len(part) - len(cap.triangles)].reshape(-1, 3)
        corners = {tuple(p) for p in side.tolist()}
        assert all(tuple(p) in corners for p in cap.vertices.reshape(-1, 3).tolist())
        assert_closed(part)


def test_torus_through_its_hole_gives_an_annulus_cap():
    mesh = samples.torus(30, 10, 96, 48)
    parts = assert_cut(mesh, (0, 0, 0.3), (0, 0, 1))
    cap = parts.report.rear_cap
    assert len(cap.loops) == 2  # the outer circle and the hole
    # The solid is the 48-gon profile revolved in 96 planar trapezoids: at z = 0.3 the section is
    # the ring between two regular 96-gons whose radii come from the profile's first edges.
    phi = 2 * np.pi * np.arange(49) / 48
    prof = np.c_[30 + 10 * np.cos(phi), 10 * np.sin(phi)]

    def radius(k0, k1):
        a, b = prof[k0], prof[k1]
        return a[0] + (0.3 - a[1]) / (b[1] - a[1]) * (b[0] - a[0])

    r_out, r_in = radius(0, 1), radius(24, 23)
    assert cap.area == pytest.approx(48 * np.sin(2 * np.pi / 96) * (r_out ** 2 - r_in ** 2), rel=1e-12)
    # No cap triangle in the hole: every centroid lies in the material ring.
    c = cap.vertices.mean(axis=1)
    rho = np.hypot(c[:, 0], c[:, 1])
    assert np.all((rho > r_in * np.cos(np.pi / 96)) & (rho < r_out))


def test_nested_shells_cap_has_a_hole_with_an_island():
    parts = assert_cut(samples.nested_shells(), (0, 0, 20), (0, 0, 1))
    cap = parts.report.rear_cap
    assert cap.area == 40 * 40 - 24 * 24 + 10 * 10
    c = cap.vertices.mean(axis=1)[:, :2]
    in_hole = np.all((c > 8) & (c < 32), axis=1) & ~np.all((c > 15) & (c < 25), axis=1)
    assert not in_hole.any()  # nothing is capped where the cavity is
    # The cap joins the outer wall to the cavity's wall; the island stays a shell of its own.
    assert check(parts.rear).n_shells == 2 and check(parts.front).n_shells == 2


@pytest.mark.parametrize("z", [0.4, 0.8, 1.6, 3.2])
def test_planes_through_the_staircase_treads(z):
    mesh = samples.staircase(8, 2.0, 10.0, 0.2, 2)
    heights = 0.4 * np.arange(1, 9)  # step s is 2 x 10 mm and (s + 1) 0.4 mm tall
    rear_volume = float(np.minimum(heights, z).sum() * 20)
    for normal in ((0, 0, 1), (0, 0, -1)):
        parts = cut(mesh, (0, 0, z), normal)
        below = parts.rear if normal[2] > 0 else parts.front
        assert check(below).volume == pytest.approx(rear_volume, abs=1e-9)
        for p in parts:
            if len(p):
                assert_closed(p)
        if 0 < z < 3.2:
            assert parts.report.n_in_plane > 0  # tread facets lie in the plane: dropped, capped over


def test_in_plane_facets_give_each_side_its_own_cap():
    # z = 8 is the cavity floor of the nested shells: below it a solid square, above it a frame.
    parts = cut(samples.nested_shells(), (0, 0, 8), (0, 0, 1))
    assert parts.report.rear_cap.area == 1600.0
    assert parts.report.front_cap.area == 1600.0 - 576.0
    for p in parts:
        assert_closed(p)


@pytest.mark.parametrize("kind", ["vertex", "edge", "face"])
def test_planes_through_vertices_edges_and_faces(kind):
    rng = np.random.default_rng({"vertex": 1, "edge": 2, "face": 3}[kind])
    for mesh in (samples.cube_with_hole(20, 5, 16), samples.pot(10, 16), samples.sphere(20, 8, 16)):
        m = mesh.transformed(random_rotation(rng))
        for _ in range(6):
            f = m.triangles[rng.integers(len(m))]
            if kind == "vertex":
                origin, normal = f[0], rng.normal(size=3)
            elif kind == "edge":
                origin, normal = (f[0] + f[1]) / 2, np.cross(f[1] - f[0], rng.normal(size=3))
            else:
                origin, normal = f[0], np.cross(f[1] - f[0], f[2] - f[0])
            assert_cut(m, origin, normal)


def test_axis_planes_through_vertex_rings():
    # The pot's vertex rings lie at these heights; x = 0 holds whole meridians of the torus.
    assert_cut(samples.pot(60, 72), (0, 0, 60), (0, 0, 1))
    assert_cut(samples.torus(30, 10, 24, 12), (0, 0, 0), (1, 0, 0))
    assert_cut(samples.torus(30, 10, 24, 12), (0, 0, 0), (1, 1, 0))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2 ** 32 - 1), which=st.sampled_from(["torus", "pot", "cube_with_hole", "nested"]),
       t=st.floats(0.05, 0.95), axis_aligned=st.booleans())
def test_random_planes_and_rotations(seed, which, t, axis_aligned):
    rng = np.random.default_rng(seed)
    mesh = {"torus": lambda: samples.torus(30, 10, 24, 12), "pot": lambda: samples.pot(10, 16),
            "cube_with_hole": lambda: samples.cube_with_hole(20, 5, 16), "nested": samples.nested_shells}[which]()
    mesh = mesh.transformed(random_rotation(rng))
    lo, hi = mesh.bounds
    normal = np.eye(3)[rng.integers(3)] if axis_aligned else rng.normal(size=3)
    origin = lo + t * (hi - lo)
    assert_cut(mesh, origin, normal)


def test_a_corner_an_ulp_off_an_axis_plane_leaves_no_sliver(tmp_path):
    """The nested shells turned at random, cut by x = const a fifth of the way across: the plane
    passes through the cavity's corner in exact arithmetic, 1.8e-15 mm from it in floating point.
    The corner counts as in the plane (no pyramid of no representable size cut off it, whose pieces
    would round away), and both parts are closed with the volumes on either side."""
    rng = np.random.default_rng(9491)
    mesh = samples.nested_shells().transformed(random_rotation(rng))
    lo, hi = mesh.bounds
    normal = np.eye(3)[rng.integers(3)]
    origin = lo + 0.2 * (hi - lo)
    assert np.count_nonzero(normal) == 1
    d = (mesh.triangles - origin) @ normal
    assert 0 < np.abs(d[d != 0]).min() < 1e-14  # a corner an ulp off the plane
    parts = assert_cut(mesh, origin, normal)
    from slicelab import load
    from slicelab.mesh.written import write_mesh
    for side, part in (("rear", parts.rear), ("front", parts.front)):  # and so they are written
        written = check(load(write_mesh(part, tmp_path / f"{side}.stl").path))
        assert written.watertight and written.winding_consistent


def test_volumes_agree_with_manifold3d():
    mf = pytest.importorskip("manifold3d")
    from slicelab.geometry.topology import weld
    rng = np.random.default_rng(7)
    for mesh in (samples.torus(30, 10, 48, 24), samples.pot(20, 32), samples.cube_with_hole(20, 5, 32)):
        v, f = weld(mesh.triangles)
        solid = mf.Manifold(mf.Mesh64(vert_properties=v, tri_verts=f.astype(np.uint64)))
        lo, hi = mesh.bounds
        for _ in range(3):
            n = rng.normal(size=3)
            n /= np.linalg.norm(n)
            o = lo + rng.uniform(0.2, 0.8, 3) * (hi - lo)
            ahead, behind = solid.split_by_plane(n, float(n @ o))
            rear, front = cut(mesh, o, n)
            assert check(rear).volume == pytest.approx(behind.volume(), rel=1e-6)
            assert check(front).volume == pytest.approx(ahead.volume(), rel=1e-6)


def test_cap_is_constrained_delaunay_no_worse_than_ear_clipping():
    earcut = pytest.importorskip("mapbox_earcut")
    for mesh, origin, normal in ((samples.pot(60, 72), (0, 0, 40), (0.2, 0.1, 1.0)),
                                 (samples.cube_with_hole(20, 5, 64), (10, 10, 10), (0.1, 1.0, 0.3)),
                                 (samples.torus(30, 10, 96, 48), (0, 0, 0.3), (0, 0, 1))):
        parts = cut(mesh, origin, normal)
        cap = parts.report.rear_cap
        frame = parts.report.frame
        p2 = frame.to_2d(cap.points)
        ours = triangle_min_angles(p2, cap.triangles).min()
        # Ear clipping of the very same rings (outer + holes), with the same points.
        rings = cap.loops
        verts = np.concatenate([p2[r] for r in rings])
        ends = np.cumsum([len(r) for r in rings]).astype(np.uint32)
        tri = earcut.triangulate_float64(verts, ends).reshape(-1, 3)
        ear = triangle_min_angles(verts, tri).min()
        # Every section point is used (no T-junction): n points in p polygons with h holes
        # make n + 2 h - 2 p triangles.
        from slicelab.geometry.polygons import signed_area
        areas = np.array([signed_area(p2[r]) for r in rings])
        n_outer, n_holes = int((areas > 0).sum()), int((areas < 0).sum())
        assert len(cap.triangles) == len(verts) + 2 * n_holes - 2 * n_outer
        assert ours >= ear - 1e-9
        assert ours > 0


def test_open_mesh_caps_what_closes_and_reports_the_rest():
    torus = samples.torus(30, 10, 24, 12)
    shift = np.eye(4)
    shift[0, 3] = 80
    t = samples.sphere(5, 8, 16).transformed(shift).triangles
    crossing = np.flatnonzero((t[:, :, 2].min(axis=1) < 0.1) & (t[:, :, 2].max(axis=1) > 0.1))
    holed = Mesh(np.concatenate([torus.triangles, np.delete(t, crossing[:1], axis=0)]))  # one facet missing
    with pytest.warns(CutWarning, match="open chains"):
        parts = cut(holed, (0, 0, 0.1), (0, 0, 1))
    cap = parts.report.rear_cap
    assert not parts.report.closed and len(cap.open_chains) == 1
    # The torus closes: its annulus is capped, and it alone makes the cap's area.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ref = cut(torus, (0, 0, 0.1), (0, 0, 1)).report.rear_cap.area
    assert cap.area == pytest.approx(ref, rel=1e-12)
    assert check(parts.rear).n_open_edges > 0  # reported, not hidden


def test_an_open_edge_near_the_plane_is_not_capped():
    # A lone facet across the plane: its own edges are open, the part cannot close.
    with pytest.warns(CutWarning):
        parts = cut(Mesh([[[0, 0, -1], [1, 0, 1], [0, 1, 1]]]), (0, 0, 0), (0, 0, 1))
    assert len(parts.report.rear_cap.triangles) == 0 and len(parts.report.rear_cap.open_chains) == 1
    assert len(parts.rear) == 1 and len(parts.front) == 2


# ------------------------------------------------------------------ self-intersecting input
def _closed_on_disk(part: Mesh, path) -> float:
    """Write the part as STL, read it back: watertight with consistent windings; its volume."""
    from slicelab.mesh.written import write_mesh
    written = write_mesh(part, path)
    back = check(slicelab.load(path))
    assert back.watertight and back.winding_consistent and written.report == back
    return back.volume


def test_a_figure_eight_section_closes_both_parts_and_says_where_it_crosses(tmp_path):
    prism = samples.figure_eight_prism(10.0)   # its section crosses itself at (12, 4.8)
    res = cut(prism, (0, 0, 5), (0, 0, 1))
    assert res.report.closed
    notes = res.report.rear_cap.notes
    assert len(notes) == 1 and "crosses itself near (12, 4.8)" in notes[0]
    vols = [_closed_on_disk(p, tmp_path / f"{k}.stl") for k, p in enumerate(res)]
    assert vols == pytest.approx([300.0, 300.0], rel=1e-6)  # 60 mm2 signed, 5 mm each side


@pytest.mark.parametrize("seed", range(6))
def test_oblique_cuts_of_self_intersecting_parts_close(seed, tmp_path):
    rng = np.random.default_rng(seed)
    for mesh in (samples.figure_eight_prism(10.0), samples.overlapping_cubes()):
        normal = rng.normal(size=3)
        lo, hi = mesh.bounds
        origin = lo + rng.uniform(0.3, 0.7, 3) * (hi - lo)
        res = cut(mesh, origin, normal)
        assert res.report.closed
        total = sum(_closed_on_disk(p, tmp_path / f"{k}.stl") for k, p in enumerate(res) if len(p))
        assert total == pytest.approx(check(mesh).volume, rel=1e-5)  # float32 files


def test_bad_plane_is_a_value_error():
    with pytest.raises(ValueError):
        cut(samples.box(), (0, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError):
        cut(samples.box(), (0, np.nan, 0), (0, 0, 1))


def test_plane_missing_the_part_gives_one_empty_part():
    rear, front = cut(samples.box(), (0, 0, 5), (0, 0, 1))
    assert len(front) == 0 and check(rear).volume == 1.0


def test_package_exposes_cut():
    assert slicelab.cut is cut
    rear, front = slicelab.cut(samples.box(), (0, 0, 0.5), (0, 0, 1))
    assert check(rear).volume == 0.5


# ------------------------------------------------------------------ command line
def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "slicelab", *map(str, args)], cwd=ROOT, text=True,
                          capture_output=True)


def test_cli_cut_writes_two_watertight_parts(tmp_path, data_dir):
    out = tmp_path / "cut"
    r = run_cli("cut", data_dir / "torus.stl", "--origin", "0,0,0.3", "--normal", "0.2,0.1,1", "-o", out)
    assert r.returncode == 0, r.stderr
    assert "watertight" in r.stdout and "NOT" not in r.stdout
    parts = [slicelab.load(out / f"{n}.stl") for n in ("rear", "front")]
    for p in parts:
        assert check(p).watertight
    assert (out / "exploded.png").stat().st_size > 1000
    assert sum(check(p).volume for p in parts) == pytest.approx(check(slicelab.load(data_dir / "torus.stl")).volume,
                                                                rel=1e-6)  # float32 STL


def test_cli_cut_bad_input_exits_2(tmp_path, data_dir):
    r = run_cli("cut", data_dir / "torus.stl", "-o", tmp_path / "x")
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    r = run_cli("cut", tmp_path / "missing.stl", "--z", "1", "-o", tmp_path / "x")
    assert r.returncode == 2 and "Traceback" not in r.stderr
