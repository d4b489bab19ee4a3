"""Exact sections: analytic areas, an independent oracle, degenerate planes, closed loops, hierarchy."""
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import slicelab
from slicelab import Mesh, section, slice_layers
from slicelab.geometry.polygons import signed_area
from slicelab.samples import box, cube_with_hole, nested_shells, pot, sphere, staircase, torus
from slicelab.geometry.planes import Frame
from slicelab.slicing.sections import layer_heights
from slicelab.geometry.topology import weld

from conftest import random_rotation

SAMPLES = ["torus", "sphere", "pot", "cube_with_hole", "nested_shells", "staircase", "overlapping_cubes"]


@pytest.fixture(scope="module")
def meshes(data_dir):
    return {name: slicelab.load(data_dir / f"{name}.stl") for name in SAMPLES}


def manifold_area(mesh: Mesh, origin, normal) -> float:
    """Independent oracle: manifold3d's slice of the mesh moved so the plane is z = 0."""
    m3 = pytest.importorskip("manifold3d")
    v, f = weld(mesh.triangles)
    solid = m3.Manifold(m3.Mesh64(vert_properties=v, tri_verts=f.astype(np.uint64)))
    fr = Frame.from_plane(origin, normal)
    rot = np.stack([fr.u, fr.v, fr.normal])
    affine = np.hstack([rot, (-rot @ fr.origin)[:, None]])
    return solid.transform(affine).slice(0.0).area()


def sphere_radius_bounds(n_lat, n_lon):
    # Every point of the UV sphere's surface lies between these radii (relative).
    return np.cos(np.pi / n_lat / 2) * np.cos(np.pi / n_lon), 1.0


# ---------------------------------------------------------------- analytic areas
@pytest.mark.parametrize("z", [-17.3, -5.0, 0.0, 3.3, 12.5, 19.0])
def test_sphere_section_within_discretisation_bound_of_circle(z):
    R, n_lat, n_lon = 20.0, 48, 96
    s = section(sphere(R, n_lat, n_lon), (0, 0, z), (0, 0, 1))
    lo, hi = sphere_radius_bounds(n_lat, n_lon)
    assert np.pi * ((R * lo) ** 2 - z * z) <= s.area <= np.pi * (R * R - z * z)
    assert len(s.loops) == 1 and not s.open_chains


def test_sphere_section_through_a_ring_is_the_inscribed_polygon():
    R, n_lat, n_lon = 20.0, 48, 96
    m = sphere(R, n_lat, n_lon)
    phi = np.linspace(-np.pi / 2, np.pi / 2, n_lat + 1)[30]
    z = R * np.sin(phi)  # the ring's vertices lie exactly in this plane
    s = section(m, (0, 0, z), (0, 0, 1))
    rho = R * np.cos(phi)
    assert s.area == pytest.approx(0.5 * n_lon * rho**2 * np.sin(2 * np.pi / n_lon), rel=1e-12)
    assert len(s.loops[0]) == n_lon


def test_torus_equatorial_section_is_an_annulus():
    R, r = 30.0, 10.0
    s = section(torus(R, r, 96, 48), (0, 0, 0), (0, 0, 1))
    exact = np.pi * ((R + r) ** 2 - (R - r) ** 2)
    c_major = np.cos(np.pi / 96)
    # Inscribed polygons: outer ring radius (R + r) on vertices, inner ring (R - r) at most.
    inner_poly = 0.5 * 96 * (R + r) ** 2 * np.sin(2 * np.pi / 96) - np.pi * (R - r) ** 2
    assert inner_poly <= s.area <= exact * 1.0 + 1e-9
    assert s.area == pytest.approx(exact, rel=2 * (1 - c_major) + 1e-3)
    assert sorted(s.loop_depth.tolist()) == [0, 1]
    outer, hole = (s.loops[i] for i in np.argsort(s.loop_depth))
    assert signed_area(outer) > 0 > signed_area(hole)


def test_box_sections_at_any_height_and_tilt():
    m = box((0, 0, 0), (2, 3, 4))
    assert section(m, (0, 0, 1.7), (0, 0, 1)).area == pytest.approx(6.0, rel=1e-14)
    assert section(m, (0, 0, 1.7), (0, 0, -1)).area == pytest.approx(6.0, rel=1e-14)
    assert section(m, (1, 1.5, 2), (1, 0, 0)).area == pytest.approx(12.0, rel=1e-14)
    # A 45 degree plane through the middle crosses the 3 x 4 side diagonally.
    assert section(m, (1, 1.5, 2), (0, 1, 1)).area == pytest.approx(2 * 3 * np.sqrt(2), rel=1e-12)


def test_layer_areas_integrate_to_the_volume():
    for m, h, tol in [(sphere(20, 48, 96), 0.2, 1e-4), (torus(30, 10, 96, 48), 0.1, 1e-4),
                      (box((0, 0, 0), (3, 4, 5)), 0.25, 1e-13)]:
        layers = slice_layers(m, h)
        volume = slicelab.check(m).volume
        assert sum(s.area for s in layers) * h == pytest.approx(volume, rel=tol)


def test_slice_layers_matches_single_sections_bit_for_bit(meshes):
    m = meshes["pot"]
    heights = [3.0, 60.0, 0.5, 119.9]
    for s, z in zip(slice_layers(m, heights=heights), heights):
        one = section(m, (0, 0, z), (0, 0, 1))
        assert s.z == z
        assert sorted(map(len, s.loops)) == sorted(map(len, one.loops))
        assert s.area == one.area
        np.testing.assert_array_equal(np.sort(s.segments.reshape(-1)), np.sort(one.segments.reshape(-1)))


def test_layer_heights_are_mid_layer():
    # Layers whose mid-plane lies inside the part: the fourth (1.9 .. 2.2) would cut nothing.
    z = layer_heights(box((0, 0, 1), (1, 1, 2)), 0.3)
    np.testing.assert_allclose(z, 1 + (np.arange(3) + 0.5) * 0.3)
    with pytest.raises(ValueError):
        slice_layers(box(), 0.0)
    with pytest.raises(ValueError):
        slice_layers(box(), 0.1, heights=[0.5])


# -------------------------------------------------------- oracle and random planes
@pytest.mark.parametrize("name", ["torus", "sphere", "pot", "cube_with_hole", "nested_shells"])
def test_areas_agree_with_manifold3d_at_random_planes(meshes, name):
    m = meshes[name]
    rng = np.random.default_rng(7)
    lo, hi = m.bounds
    for _ in range(4):
        n = rng.normal(size=3)
        o = rng.uniform(lo, hi)
        ours = section(m, o, n, max_gap=0)
        assert not ours.open_chains
        assert ours.area == pytest.approx(manifold_area(m, o, n), rel=1e-9, abs=1e-9)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(name=st.sampled_from(SAMPLES), seed=st.integers(0, 2**32 - 1), t=st.floats(0.02, 0.98))
def test_every_loop_closes_on_rotated_watertight_samples(meshes, name, seed, t):
    rng = np.random.default_rng(seed)
    m = meshes[name].transformed(random_rotation(rng))
    lo, hi = m.bounds
    n = rng.normal(size=3)
    o = lo + t * (hi - lo)
    s = section(m, o, n, max_gap=0)
    assert s.open_chains == []
    assert len(s.segments) == sum(len(p) for p in s.loops)
    if name != "overlapping_cubes":  # loops of the two overlapping shells cross each other
        assert s.area >= -1e-9
        for loop, d in zip(s.loops, s.loop_depth):
            assert (signed_area(loop) > 0) == (d % 2 == 0)


def test_rotation_invariance_of_section_area(meshes):
    rng = np.random.default_rng(11)
    m = meshes["pot"]
    base = section(m, (0, 0, 40), (0, 0, 1)).area
    for _ in range(3):
        rot = random_rotation(rng)
        rm = m.transformed(rot)
        o = rot[:3, :3] @ np.array([0, 0, 40.0])
        n = rot[:3, :3] @ np.array([0, 0, 1.0])
        assert section(rm, o, n).area == pytest.approx(base, rel=1e-9)


# ------------------------------------------------------------ degenerate planes
def test_staircase_at_its_treads_is_the_limit_from_below(meshes):
    m = meshes["staircase"]
    treads = np.unique(m.triangles[..., 2])
    layers = slice_layers(m, heights=treads)
    tops = np.unique(m.triangles[..., 2].max(axis=1))
    for z, s in zip(treads, layers):
        eps = 1e-4
        below = section(m, (0, 0, z - eps), (0, 0, 1)).area
        assert s.area == pytest.approx(below, rel=1e-12, abs=1e-12), z
        assert s.open_chains == []
        # Analytic: every step whose top is at or above z and whose bottom is below z.
        steps = np.arange(8)
        expected = 2.0 * 10.0 * np.count_nonzero((steps + 1) * 0.4 >= z - 1e-6) if z > 0 else 0.0
        assert s.area == pytest.approx(expected, rel=1e-6, abs=1e-9)
    assert tops.size > 1
    # Segments never have zero length, even with faces and edges in the plane.
    for s in layers:
        assert np.all(np.any(s.segments[:, 0] != s.segments[:, 1], axis=1))


def test_facet_cases_against_a_plane():
    z = np.array([0.0])
    tri = lambda a, b, c: Mesh(np.array([[[0, 0, a], [1, 0, b], [0, 1, c]]], float))  # noqa: E731
    cases = {
        (1, 2, 3): 0,      # no contact, above
        (-1, -2, -3): 0,   # no contact, below
        (0, 1, 2): 0,      # vertex in plane, rest above: touches, adds nothing
        (0, -1, -2): 0,    # vertex in plane, rest below: touches at a point, no zero-length segment
        (0, 0, 1): 0,      # edge in plane, facet above: adds nothing (owned by the facet below)
        (0, 0, -1): 1,     # edge in plane, facet below: owns its top edge
        (0, 0, 0): 0,      # facet in the plane: adds nothing
        (-1, 1, 0): 1,     # vertex in plane, the others on either side (pattern c)
        (-1, -1, 1): 1,    # two edges cross (pattern e)
        (-1, 1, 1): 1,
    }
    for zs, n_seg in cases.items():
        s = slice_layers(tri(*zs), heights=z, max_gap=0)[0]
        assert len(s.segments) == n_seg, zs
        if n_seg:
            assert np.linalg.norm(s.segments[0, 1] - s.segments[0, 0]) > 0


def test_segments_have_material_on_their_left():
    shapely = pytest.importorskip("shapely")
    s = section(cube_with_hole(20, 5, 32), (0, 0, 7), (0, 0, 1))
    region = s.to_shapely()
    mid = s.segments.mean(axis=1)
    d = s.segments[:, 1] - s.segments[:, 0]
    left = np.stack([-d[:, 1], d[:, 0]], 1) / np.linalg.norm(d, axis=1)[:, None]
    assert all(region.contains(shapely.Point(p)) for p in mid + 1e-3 * left)
    assert not any(region.contains(shapely.Point(p)) for p in mid - 1e-3 * left)
    assert region.area == pytest.approx(s.area, rel=1e-12)


# ---------------------------------------------------------------- hierarchy
def test_nested_shells_hierarchy_and_orientation():
    s = section(nested_shells(), (0, 0, 20), (0, 0, 1))
    order = np.argsort(s.loop_depth)
    assert s.loop_depth[order].tolist() == [0, 1, 2]
    assert [np.sign(signed_area(s.loops[i])) for i in order] == [1, -1, 1]
    assert s.loop_parent[order].tolist() == [-1, order[0], order[1]]
    polys = sorted(s.polygons, key=lambda p: p.depth)
    assert [(p.depth, len(p.holes)) for p in polys] == [(0, 1), (2, 0)]
    assert [p.area for p in polys] == [pytest.approx(40 * 40 - 24 * 24), pytest.approx(100.0)]
    assert s.area == pytest.approx(40 * 40 - 24 * 24 + 100)


def test_open_scan_chains_are_joined_within_the_gap():
    m = sphere(20, 24, 48)
    t = m.triangles
    keep = ~((t[..., 0].mean(axis=1) > 19) & (np.abs(t[..., 2].mean(axis=1)) < 2))  # a small hole at the equator
    holed = Mesh(t[keep])
    assert not slicelab.check(holed).watertight
    s_open = section(holed, (0, 0, 0.3), (0, 0, 1), max_gap=0)
    assert len(s_open.open_chains) == 1 and not s_open.loops
    gap = np.linalg.norm(s_open.open_chains[0][0] - s_open.open_chains[0][-1])
    assert section(holed, (0, 0, 0.3), (0, 0, 1), max_gap=0.9 * gap).open_chains
    s = section(holed, (0, 0, 0.3), (0, 0, 1), max_gap=1.1 * gap)
    assert len(s.loops) == 1 and not s.open_chains
    assert s.joined_gaps.tolist() == [pytest.approx(gap)]
    closed = section(m, (0, 0, 0.3), (0, 0, 1))
    assert s.area == pytest.approx(closed.area, rel=0.02)


def test_frames_are_right_handed_and_round_trip():
    rng = np.random.default_rng(5)
    for _ in range(20):
        n = rng.normal(size=3)
        f = Frame.from_plane(rng.normal(size=3), n)
        basis = np.stack([f.u, f.v, f.normal])
        np.testing.assert_allclose(basis @ basis.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(basis) == pytest.approx(1.0)
        p2 = rng.normal(size=(5, 2))
        np.testing.assert_allclose(f.to_2d(f.to_3d(p2)), p2, atol=1e-12)
    with pytest.raises(ValueError):
        Frame.from_plane((0, 0, 0), (0, 0, 0))


def test_svg_is_true_scale_and_parses(tmp_path):
    s = section(cube_with_hole(20, 5, 32), (0, 0, 7), (0, 0, 1))
    s.to_svg(tmp_path / "s.svg")
    root = ET.parse(tmp_path / "s.svg").getroot()
    assert root.get("width").endswith("mm") and float(root.get("width")[:-2]) == pytest.approx(24.0)
    assert root.get("viewBox") == "0 0 24 24"
    g = root.find("{http://www.w3.org/2000/svg}g")
    assert g.get("fill-rule") == "evenodd" and len(g) == 1
    assert list(tmp_path.iterdir()) == [tmp_path / "s.svg"]


def test_to_3d_puts_points_back_on_the_plane():
    o, n = np.array([1.0, 2, 3]), np.array([0.2, -0.4, 1])
    s = section(torus(30, 10, 32, 16), o, n)
    p3 = s.to_3d(s.loops[0])
    np.testing.assert_allclose((p3 - o) @ (n / np.linalg.norm(n)), 0, atol=1e-9)


def test_empty_section_and_bad_plane():
    s = section(box(), (0, 0, 5), (0, 0, 1))
    assert s.area == 0 and s.loops == [] and len(s.segments) == 0
    with pytest.raises(ValueError):
        section(box(), (0, 0, np.nan), (0, 0, 1))


def test_slice_layers_gives_the_same_sections_from_the_meshs_weld_or_its_own():
    # The crossing points are keyed by vertex ids: from the mesh's weld when it is known (or most
    # facets are crossed), else from welding the crossing facets' corners alone. Both key the same
    # points alike, so the sections are the same, loop for loop.
    heights = np.linspace(-0.9, 0.9, 7)
    own = slice_layers(torus(), heights=heights)  # few planes, nothing welded: the corners alone
    mesh = torus()
    assert mesh.welded[0].shape == (len(mesh), 3)
    shared = slice_layers(mesh, heights=heights)
    for a, b in zip(own, shared):
        assert np.array_equal(a.segments, b.segments)
        assert len(a.loops) == len(b.loops) == 2
        assert all(np.array_equal(x, y) for x, y in zip(a.loops, b.loops))
    assert sum(abs(s.area) for s in own) > 0


@pytest.mark.parametrize("name", ["staircase", "nested_shells", "cube_with_hole", "torus", "sphere"])
def test_slice_layers_is_each_planes_section_segment_for_segment(meshes, name):
    # The compiled cut of every facet/plane pair gives, plane by plane, the section numpy's cut gives
    # (`section`): the same segments in the same order and the same loops, from the same first point,
    # planes through vertices (corners in the plane, facets lying in it) included.
    m = meshes[name]
    if name in ("torus", "sphere"):  # tilted: facets cross many planes at odd angles
        m = m.transformed(random_rotation(np.random.default_rng(len(name))))
    z = np.unique(m.triangles[:, :, 2])
    heights = np.concatenate([z[:: max(1, len(z) // 25)], np.linspace(z[0], z[-1], 13)[1:-1]])
    for s, h in zip(slice_layers(m, heights=heights), heights):
        one = section(m, (0, 0, h), (0, 0, 1))
        assert np.array_equal(s.segments, one.segments)
        assert len(s.loops) == len(one.loops)
        assert all(np.array_equal(a, b) for a, b in zip(s.loops, one.loops))
