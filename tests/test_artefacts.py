"""Scanned artefacts: axis alignment, profiles, measurements against the pot's true dimensions, drawings."""
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.spatial import cKDTree

import slicelab
from slicelab import Mesh, samples
from slicelab.artefacts import align, clip_ring, pappus_volume, profile, rotation_to_z
from slicelab.mesh.validation import check
from slicelab.cli import main
from slicelab.geometry.topology import weld

from conftest import random_rotation

DIMS = samples.pot_dimensions()
POT = samples.POT
SVG = "{http://www.w3.org/2000/svg}"


def noisy(mesh: Mesh, sigma: float, seed: int) -> Mesh:
    """Scanner noise: every shared vertex moved at random (the surface stays closed)."""
    v, f = weld(mesh.triangles)
    v = v + np.random.default_rng(seed).normal(scale=sigma, size=v.shape)
    return Mesh.from_vertices_faces(v, f)


def without_sherd(mesh: Mesh, centre, radius: float) -> Mesh:
    """A missing sherd: every facet whose centroid lies within `radius` of `centre` removed."""
    c = mesh.triangles.mean(axis=1)
    return Mesh(mesh.triangles[np.linalg.norm(c - np.asarray(centre), axis=1) > radius])


@pytest.fixture(scope="module")
def pot():
    return samples.pot()  # 60 x 72: 17k facets, the same as data/pot.stl


@pytest.fixture(scope="module")
def scans(pot):
    """The pot as scans come in: each case moved by a random rotation and translation."""
    cases = {
        "clean": pot,
        "noise 0.1 mm": noisy(pot, 0.1, 1),
        "noise 0.3 mm": noisy(pot, 0.3, 2),
        "missing sherd": without_sherd(pot, (62.0, 0.0, 75.0), 20.0),
        "sherd and noise": without_sherd(noisy(pot, 0.2, 3), (0.0, -55.0, 40.0), 25.0),
    }
    rng = np.random.default_rng(2024)
    out = {}
    for name, mesh in cases.items():
        motion = random_rotation(rng)
        motion[:3, 3] = rng.uniform(-300, 300, 3)
        out[name] = (mesh.transformed(motion), motion)
    return out


def true_axis(motion):
    return motion[:3, :3] @ [0.0, 0.0, 1.0]


def angle_deg(a, b) -> float:
    """Angle between two directions, sign included (a flipped axis is 180 degrees off)."""
    c = float(np.dot(a, b) / np.linalg.norm(a) / np.linalg.norm(b))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


@pytest.mark.parametrize("case", ["clean", "noise 0.1 mm", "noise 0.3 mm", "missing sherd", "sherd and noise"])
def test_align_recovers_axis_rim_up_and_base_at_zero(scans, case):
    mesh, motion = scans[case]
    a = align(mesh)
    assert angle_deg(a.axis, true_axis(motion)) <= 0.5
    assert a.up_from == "base"
    lo, hi = a.mesh.bounds
    assert lo[2] == 0.0
    assert hi[2] == pytest.approx(POT["height"], abs=2.0)
    # The axis passes through the origin: the true base centre (moved) lands there.
    base_centre = (motion @ [0.0, 0.0, 0.0, 1.0])[:3]
    moved = a.matrix @ np.append(base_centre, 1.0)
    assert np.hypot(moved[0], moved[1]) < 0.5
    # The matrix is a rigid motion and really produced the moved mesh.
    assert np.allclose(a.matrix[:3, :3] @ a.matrix[:3, :3].T, np.eye(3), atol=1e-12)
    assert np.allclose(mesh.transformed(a.matrix).triangles, a.mesh.triangles, atol=1e-9)
    assert a.is_revolution


def test_a_jug_with_a_handle_aligns_on_its_body():
    """A handle's normals miss the axis and its loops sit to one side: it must not tilt the axis."""
    rot = np.array([[1.0, 0, 0, 60], [0, 0, -1, 0], [0, 1, 0, 70], [0, 0, 0, 1]])  # a ring in the xz plane
    handle = samples.torus(22.0, 3.5, 48, 16).transformed(rot)
    jug = samples.concat(samples.pot(40, 48), handle)
    motion = random_rotation(np.random.default_rng(3))
    motion[:3, 3] = [40.0, -20.0, 10.0]
    p = profile(jug.transformed(motion), planes=12)
    assert angle_deg(p.alignment.axis, true_axis(motion)) <= 0.05  # 0.2 degrees before reweighting
    m = p.measurements
    for key in ("height", "rim_diameter", "max_diameter", "base_diameter", "capacity"):
        assert getattr(m, key) == pytest.approx(DIMS[key], rel=0.01), key


def test_aligned_pot_sections_are_circles_about_the_origin(scans):
    a = align(scans["clean"][0])
    s = slicelab.section(a.mesh, (0, 0, 60.0), (0, 0, 1))
    r = [np.hypot(*loop.T) for loop in s.loops]
    outer = max(r, key=np.mean)
    # Vertices of the 72-gon lie on the true circle; chord midpoints within cos(pi/72) of it.
    r_true = POT["R0"] + POT["A"] * math.sin(math.pi * 60.0 / POT["L"])
    assert outer.max() == pytest.approx(r_true, abs=0.01)
    assert outer.min() >= r_true * math.cos(math.pi / 72) - 0.01
    assert a.residual < 0.05 and a.relative_residual < 1e-3


def test_upside_down_pot_comes_out_rim_up(pot):
    flip = np.diag([1.0, -1.0, -1.0, 1.0])
    a = align(pot.transformed(flip))
    assert angle_deg(a.axis, [0, 0, -1]) < 0.01
    # Just above z = 0 the aligned pot is the solid base: one disc, no hole.
    s = slicelab.section(a.mesh, (0, 0, 3.0), (0, 0, 1))
    r = POT["R0"] + POT["A"] * math.sin(math.pi * 3.0 / POT["L"])
    assert len(s.loops) == 1 and s.area == pytest.approx(math.pi * r ** 2, rel=0.01)


@pytest.mark.parametrize("case", ["clean", "missing sherd", "noise 0.1 mm"])
def test_measurements_within_one_percent_of_the_true_pot(scans, case):
    p = profile(scans[case][0], planes=6)
    m = p.measurements
    for key in ("height", "rim_diameter", "max_diameter", "base_diameter", "capacity", "clay_volume"):
        assert getattr(m, key) == pytest.approx(DIMS[key], rel=0.01), key
    assert m.base_thickness == pytest.approx(DIMS["base_thickness"], rel=0.01 if case != "noise 0.1 mm" else 0.1)
    assert m.max_diameter_height == pytest.approx(DIMS["max_diameter_height"], abs=3.0)
    if case == "missing sherd":
        assert m.halves < 12  # the planes through the hole are left out, not guessed
    assert p.is_revolution


def analytic_wall_thickness():
    """Oracle: perpendicular thickness of the continuous pot, from dense samples of its true outlines."""
    H, T, B = POT["height"], POT["wall"], POT["base"]

    def r_o(z):
        return POT["R0"] + POT["A"] * np.sin(np.pi * z / POT["L"])

    zo = np.linspace(0.0, H, 20001)
    outer = np.column_stack([r_o(zo), zo])
    underside = np.column_stack([np.linspace(0.0, r_o(0.0), 5001), np.zeros(5001)])
    zi = np.linspace(B, H, 20001)
    inner = np.column_stack([r_o(zi) - T, zi])  # the interior wall, floor excluded
    d, idx = cKDTree(np.vstack([outer, underside])).query(inner)
    assert (idx < len(outer)).all()  # no wall point is nearest the underside
    seg = np.hypot(*np.diff(inner, axis=0).T)
    w = np.concatenate([[seg[0] / 2], (seg[1:] + seg[:-1]) / 2, [seg[-1] / 2]])
    return d.min(), float((d * w).sum() / w.sum()), d.max()


def test_wall_thickness_matches_the_analytic_pot(pot):
    lo, mean, hi = analytic_wall_thickness()
    m = profile(pot, planes=4, align=False).measurements
    assert m.wall_thickness_min == pytest.approx(lo, rel=0.01)
    assert m.wall_thickness_mean == pytest.approx(mean, rel=0.01)
    assert m.wall_thickness_max == pytest.approx(hi, rel=0.01)
    assert hi == pytest.approx(POT["wall"], rel=1e-6)  # where the wall stands vertical


def test_capacity_is_the_cavity_volume_of_the_mesh(pot):
    """Independent of Pappus: the volume of the pot filled to the rim (a revolved outer profile,
    by the divergence theorem on its mesh) minus the volume of the clay."""
    n = 72
    prof = samples.pot_profile(60)
    outer = prof[: 62]  # axis, then the outer wall up to the rim
    filled = samples.revolve(np.vstack([outer, [[0.0, POT["height"]]]]), n)
    cavity = check(filled).volume - check(pot).volume
    m = profile(pot, planes=12, align=False).measurements
    assert m.capacity == pytest.approx(cavity, rel=0.003)
    assert m.clay_volume == pytest.approx(check(pot).volume, rel=0.003)


def test_capacity_of_a_cylindrical_cup_is_analytic():
    R, T, H, B = 40.0, 3.0, 80.0, 5.0
    cup = samples.revolve([[0, 0], [R, 0], [R, H], [R - T, H], [R - T, B], [0, B]], 512)
    m = profile(cup, planes=3).measurements
    assert m.capacity == pytest.approx(math.pi * (R - T) ** 2 * (H - B), rel=2e-4)
    assert m.clay_volume == pytest.approx(math.pi * (R ** 2 * H - (R - T) ** 2 * (H - B)), rel=2e-4)
    assert m.rim_diameter == pytest.approx(2 * R, rel=1e-4)
    assert m.base_diameter == pytest.approx(2 * R, rel=1e-4)
    assert m.wall_thickness_min == pytest.approx(T, rel=1e-3)
    assert m.wall_thickness_max == pytest.approx(T, rel=1e-3)
    assert m.base_thickness == pytest.approx(B, rel=1e-9)


def test_capacity_quadrature_is_the_generators_integral():
    # pot_dimensions integrates with quad; Pappus on a fine analytic outline must agree.
    z = np.linspace(POT["base"], POT["height"], 4001)
    r = POT["R0"] + POT["A"] * np.sin(np.pi * z / POT["L"]) - POT["wall"]
    ring = np.vstack([[[0.0, POT["base"]]], np.column_stack([r, z]), [[0.0, POT["height"]]]])
    assert pappus_volume(ring) == pytest.approx(DIMS["capacity"], rel=1e-6)
    exact = quad(lambda t: math.pi * 2.0 ** 2, 0, 3)[0]
    assert pappus_volume(np.array([[0, 0], [2, 0], [2, 3], [0, 3]], float)) == pytest.approx(exact, rel=1e-12)


def test_clip_ring_keeps_area_on_one_side():
    u = np.array([[-2, 0], [2, 0], [2, 1], [-1, 1], [-1, 3], [-2, 3]], float)  # an L across the axis
    right = clip_ring(u)
    left = clip_ring(u, keep_below=True)
    from slicelab.geometry.polygons import signed_area
    assert signed_area(right) + signed_area(left) == pytest.approx(signed_area(u), rel=1e-12)
    assert signed_area(right) == pytest.approx(2.0) and (right[:, 0] >= 0).all()


def test_box_and_torus(pot):
    box = samples.box((0, 0, 0), (30, 50, 80))
    p = profile(box, planes=6)
    assert not p.is_revolution
    a = align(samples.torus(30, 10, 48, 24).transformed(random_rotation(np.random.default_rng(5))))
    assert a.is_revolution and a.relative_residual < 0.01


def test_svg_drawing_has_its_layers_at_true_scale(pot, tmp_path):
    p = profile(pot, planes=4, align=False, name="pot & co")
    for side, sign in (("left", -1), ("right", 1)):
        path = tmp_path / f"{side}.svg"
        p.to_svg(path, side=side, spread=True)
        root = ET.parse(path).getroot()
        groups = {g.get("id"): g for g in root.iter(f"{SVG}g")}
        assert set(groups) == {"axis", "section", "exterior", "rim", "spread", "scale", "label"}
        w = float(root.get("width").removesuffix("mm"))
        vb = [float(v) for v in root.get("viewBox").split()]
        assert w == pytest.approx(vb[2]) and float(root.get("height").removesuffix("mm")) == pytest.approx(vb[3])
        axis_x = float(groups["axis"].find(f"{SVG}polyline").get("points").split()[0].split(",")[0])
        d = groups["section"].find(f"{SVG}path").get("d")
        xy = np.array([[float(c) for c in tok.lstrip("ML").split(",")] for tok in d.split() if tok != "Z"])
        r = sign * (xy[:, 0] - axis_x)
        assert r.min() >= -1e-3  # the section lies on its side of the axis
        assert r.max() == pytest.approx(p.drawn.polygon[:, 0].max(), abs=1e-3)  # 1:1 in mm
        assert xy[:, 1].max() - xy[:, 1].min() == pytest.approx(POT["height"], abs=1e-3)
        ext = groups["exterior"].find(f"{SVG}polyline").get("points").split()
        ex = np.array([float(t.split(",")[0]) for t in ext]) - axis_x
        assert (sign * ex <= 1e-3).all()  # the exterior outline is on the other side
        assert "pot &amp; co" in path.read_text()
        assert len(groups["scale"].findall(f"{SVG}rect")) == 5


def test_png_is_drawn_at_the_requested_scale(pot, tmp_path):
    import matplotlib.image as mpimg
    from slicelab.artefacts import layout
    p = profile(pot, planes=2, align=False)
    p.to_png(tmp_path / "p.png", dpi=60)
    img = mpimg.imread(tmp_path / "p.png")
    x0, y0, x1, y1 = layout(p)["page"]
    assert img.shape[1] == pytest.approx((x1 - x0) / 25.4 * 60, abs=1.5)
    assert img.shape[0] == pytest.approx((y1 - y0) / 25.4 * 60, abs=1.5)
    assert img[..., :3].min() < 0.1  # something black was drawn


def test_bad_inputs(pot):
    with pytest.raises(ValueError):
        align(Mesh(pot.triangles[:2]))
    with pytest.raises(ValueError):
        profile(pot, planes=0)
    with pytest.raises(ValueError):
        p = profile(pot, planes=2, align=False)
        p.to_svg("unused.svg", side="middle")
    with pytest.raises(ValueError, match="closed section"):
        profile(Mesh(pot.triangles[pot.triangles[..., 2].max(axis=1) > 50]), planes=2, align=False)


def test_rotation_to_z():
    rng = np.random.default_rng(3)
    for d in [*rng.normal(size=(5, 3)), [0, 0, 1], [0, 0, -1], [1e-17, 0, -1]]:
        R = rotation_to_z(d)
        assert np.allclose(R @ (np.asarray(d) / np.linalg.norm(d)), [0, 0, 1], atol=1e-12)
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-12) and np.linalg.det(R) == pytest.approx(1.0)


def test_cli_profile(tmp_path, data_dir, capsys):
    out = tmp_path / "pot.svg"
    assert main(["profile", str(data_dir / "pot.stl"), "-o", str(out), "--png", str(tmp_path / "pot.png"),
                 "--json", str(tmp_path / "pot.json"), "--planes", "3", "--side", "right"]) == 0
    assert out.exists() and (tmp_path / "pot.png").exists()
    assert "rim diameter" in capsys.readouterr().out
    import json
    data = json.loads((tmp_path / "pot.json").read_text())
    assert data["measurements"]["rim_diameter"] == pytest.approx(DIMS["rim_diameter"], rel=0.01)
    bad = tmp_path / "bad.stl"
    bad.write_bytes(b"solid x\nfacet normal 0 0 1\n")
    assert main(["profile", str(bad), "-o", str(tmp_path / "b.svg")]) == 2
    assert main(["profile", str(data_dir / "pot.stl"), "-o", str(tmp_path / "c.svg"), "--planes", "0"]) == 2
    assert "error" in capsys.readouterr().err
