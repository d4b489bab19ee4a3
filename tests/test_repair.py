"""repair: CAD float noise, collapsed and duplicate facets, windings; real CAD exports when present."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import slicelab
from slicelab import Mesh, check, load, save
from slicelab.mesh import repair
from slicelab.samples import box, concat, nested_shells, torus

CAD = Path(__file__).resolve().parents[2] / "shared" / "meshes" / "trimesh" / "models"
CAD_FILES = ["angle_block.STL", "featuretype.STL", "idler_riser.STL", "octagonal_pocket.stl"]


@pytest.fixture
def rng():
    return np.random.default_rng(7)


def _noisy(mesh: Mesh, rng, scale=1e-17) -> Mesh:
    """Half the corners at each exact zero coordinate moved by CAD-like noise (as cos 90 degrees)."""
    t = mesh.triangles.copy()
    zeros = np.flatnonzero(t.reshape(-1) == 0)
    pick = zeros[rng.random(len(zeros)) < 0.5]
    t.reshape(-1)[pick] = scale * rng.uniform(0.5, 5, len(pick))
    return Mesh(t)


def _repaired(mesh: Mesh):
    """A mesh that float noise leaves open (open edges, near-coincident vertices) checked, repaired
    and checked again: (report before, repair, report after), the repair's result watertight."""
    before = check(mesh)
    assert before.n_open_edges > 0 and before.n_near_vertices > 0
    fixed = repair(mesh)
    after = check(fixed.mesh)
    assert after.watertight
    return before, fixed, after


def test_float_noise_opens_edges_that_repair_closes(rng):
    clean = torus(30, 10, 48, 24)
    # The torus has few exact zeros; a box sitting on the origin planes has many.
    m = concat(clean, box((-60, -60, -5), (-40, -40, 5)), box((0, 0, 0), (5, 5, 5)))
    noisy = _noisy(m, rng)
    before, fixed, after = _repaired(noisy)
    assert not before.watertight
    assert after.n_misoriented_edges == 0
    assert after.n_near_vertices == 0
    assert fixed.report.n_snapped_vertices > 0
    assert after.volume == pytest.approx(check(m).volume, rel=1e-12)
    assert any("near-coincident" in c for c in fixed.report.changes())


def test_single_precision_copies_of_a_vertex_are_snapped_through_an_stl_file(tmp_path, rng):
    """Copies of a vertex one float32 unit in the last place apart (as in PrusaSlicer's frog_legs.stl),
    written to an STL file and read back: open edges there, watertight after repair."""
    m = Mesh(torus(25, 8, 48, 24).triangles + (40, 30, 8))
    t = m.triangles.astype(np.float32)
    corners = t.reshape(-1, 3)
    # Some corners of some facets moved to the next float32 up in y, their copies on the
    # neighbouring facets left: open seams that exact welding sees.
    moved = np.unique(np.round(corners[rng.random(len(corners)) < 0.02], 3), axis=0)
    for v in moved:
        hit = np.flatnonzero(np.all(np.abs(corners - v) < 1e-3, axis=1))
        corners[hit[:1], 1] = np.nextafter(corners[hit[:1], 1], np.float32(np.inf))
    path = tmp_path / "ulp.stl"
    save(Mesh(t.astype(np.float64)), path)
    noisy = load(path)
    before, fixed, after = _repaired(noisy)
    assert after.n_near_vertices == 0
    assert fixed.report.n_snapped_vertices > 0
    assert after.volume == pytest.approx(check(m).volume, rel=1e-5)


def test_a_clean_mesh_is_returned_unchanged():
    m = torus(30, 10, 24, 12)
    fixed = repair(m)
    assert fixed.mesh is m and not fixed.report.changed and fixed.report.changes() == []


def test_flipped_facets_are_reversed_and_inside_out_shells_turned(rng):
    m = nested_shells()
    t = m.triangles.copy()
    flip = rng.random(len(t)) < 0.3
    t[flip] = t[flip][:, ::-1]
    bad = Mesh(t)
    assert check(bad).n_misoriented_edges > 0
    fixed = repair(bad)
    r = check(fixed.mesh)
    assert r.n_misoriented_edges == 0 and r.watertight
    assert r.volume == pytest.approx(check(m).volume, rel=1e-12)
    inside_out = repair(Mesh(box().triangles[:, ::-1]))
    assert inside_out.report.n_shells_turned_outward == 1
    assert check(inside_out.mesh).volume == pytest.approx(1.0)


def test_duplicates_and_collapsed_facets_are_removed():
    b = box((0, 0, 0), (2, 2, 2))
    t = b.triangles
    sliver = np.array([[t[0, 0], t[0, 1], t[0, 0]]])           # two corners on one vertex
    twin = t[:3]                                               # the same facets again
    wall = np.stack([t[4], t[4][::-1]])                        # a wall of no thickness
    fixed = repair(Mesh(np.concatenate([t, sliver, twin, wall])))
    assert fixed.report.n_collapsed_removed == 1
    assert fixed.report.n_duplicates_removed == 3 + 2
    r = check(fixed.mesh)
    assert len(fixed.mesh) == len(t) and r.watertight and r.volume == pytest.approx(8.0)


def test_bad_tolerance_is_refused():
    with pytest.raises(ValueError, match="tolerance"):
        repair(box(), tolerance=-1)


def test_repaired_file_reads_back_watertight(rng, tmp_path):
    noisy = _noisy(concat(box((0, 0, 0), (5, 5, 5)), box((0, 0, 10), (5, 5, 15))), rng)
    save(repair(noisy).mesh, tmp_path / "fixed.stl")
    assert check(load(tmp_path / "fixed.stl")).watertight


@pytest.mark.parametrize("name", CAD_FILES)
def test_real_cad_exports_repair_to_watertight(name):
    path = CAD / name
    if not path.exists():
        pytest.skip("../shared/meshes is not present")
    m = load(path)
    before, fixed, after = _repaired(m)
    assert after.n_misoriented_edges == 0
    assert after.volume == pytest.approx(before.volume, rel=1e-9)


@pytest.mark.parametrize("name", CAD_FILES)
def test_real_cad_exports_cut_closed_after_repair(name, tmp_path):
    path = CAD / name
    if not path.exists():
        pytest.skip("../shared/meshes is not present")
    from slicelab.tasks import run_job
    r = run_job("cut", path, {"repair": True, "preview": False}, tmp_path)
    assert r.results["repair"]["n_snapped_vertices"] > 0
    for part in ("rear", "front"):
        if part in r.results:
            assert check(load(tmp_path / f"{part}.stl")).watertight


def test_noisy_mesh_cuts_closed_after_repair(rng, tmp_path):
    from slicelab import cut
    from slicelab.mesh.written import write_mesh
    m = _noisy(concat(box((0, 0, 0), (20, 10, 10)), box((0, 0, 20), (10, 10, 30))), rng)
    fixed = repair(m).mesh
    for k, part in enumerate(cut(fixed, (0, 0, 5), (0.3, 0.1, 1))):
        write_mesh(part, tmp_path / f"{k}.stl")
        assert check(load(tmp_path / f"{k}.stl")).watertight


@pytest.mark.parametrize("tol", [1e-5, 1e-3, 0.05])
def test_near_vertex_pairs_are_those_a_kd_tree_finds(rng, tol):
    """Every pair within the tolerance, and no other, against SciPy's k-d tree: clusters of
    copies moved by about the tolerance (some just inside it, some just beyond), on a lattice
    (many points share coordinates, as on CAD faces) and at random."""
    from scipy.spatial import cKDTree

    from slicelab.mesh import near_vertex_pairs
    grid = np.stack(np.meshgrid(*[np.arange(0.0, 12, 1.5)] * 3), -1).reshape(-1, 3)
    v = np.concatenate([grid, rng.uniform(-40, 40, (3000, 3))])
    pick = rng.integers(0, len(v), 600)
    step = rng.normal(size=(600, 3))
    step *= (tol * rng.uniform(0.5, 1.5, 600) / np.linalg.norm(step, axis=1))[:, None]
    v = np.concatenate([v, v[pick] + step, v[pick[:100]] - step[:100]])
    ours = near_vertex_pairs(v, tol)
    theirs = np.sort(cKDTree(v).query_pairs(tol, output_type="ndarray"), axis=1)
    theirs = theirs[np.lexsort((theirs[:, 1], theirs[:, 0]))]
    assert len(ours) > 100
    assert np.array_equal(ours, theirs)


def _holed(mesh: Mesh, keep) -> Mesh:
    """The mesh without the facets `keep` leaves out (holes where they were)."""
    return Mesh(mesh.triangles[keep])


def test_holes_are_closed_and_the_parts_stay_closed_on_disk(tmp_path):
    """A box without one face (a planar hole) and a torus without a patch of its outer surface (a
    curved one, 4 x 3 facets), written with their holes and read back: repair with fill_holes closes
    both, and the written mesh is watertight, its windings consistent, its volume the box's exactly
    and the torus's within the patch's share."""
    block = box((0, 0, 0), (20, 10, 5))
    ring = torus(30, 10, 48, 24)
    centroid = ring.triangles.mean(axis=1)
    angle, radius = np.arctan2(centroid[:, 1], centroid[:, 0]), np.hypot(centroid[:, 0], centroid[:, 1])
    patch = (np.abs(angle) < 2 * np.pi / 48 * 2) & (radius > 38) & (np.abs(centroid[:, 2]) < 4)
    assert 8 <= patch.sum() <= 40
    for whole, holed, holes in ((block, _holed(block, slice(2, None)), 1),
                                (ring, _holed(ring, ~patch), 1),
                                (concat(block, ring), concat(_holed(block, slice(2, None)), _holed(ring, ~patch)), 2)):
        path = tmp_path / "holed.stl"
        save(holed, path)
        before = check(load(path))
        assert not before.watertight and before.n_open_edges > 0 and before.n_near_vertices == 0
        said = "(1 hole: --fill-holes closes it)" if holes == 1 else f"({holes} holes: --fill-holes closes them)"
        assert before.n_holes == holes and said in str(before)
        fixed = repair(load(path), fill_holes=True)
        assert fixed.report.n_holes_filled == holes
        assert any(c.startswith("filled 1 hole (" if holes == 1 else f"filled {holes} holes (the largest")
                   for c in fixed.report.changes())
        save(fixed.mesh, tmp_path / "filled.stl")
        after = check(load(tmp_path / "filled.stl"))
        assert after.watertight and after.winding_consistent and after.n_shells == check(whole).n_shells
        assert after.volume == pytest.approx(check(whole).volume, rel=2e-3)
    assert repair(load(tmp_path / "holed.stl")).report.n_holes_filled == 0  # asked for only


def test_slice_names_the_holes_and_fills_them_when_asked(tmp_path):
    """An open block: `slice` refuses it in one line naming --fill-holes (exit 2, no G-code), and
    with --fill-holes prints it, reporting the hole."""
    import subprocess
    import sys
    part = tmp_path / "open.stl"
    save(_holed(box((0, 0, 0), (12, 8, 1)), slice(2, None)), part)
    out = tmp_path / "part.gcode"
    base = [sys.executable, "-m", "slicelab", "slice", str(part), "-o", str(out), "--workers", "1"]
    r = subprocess.run(base, capture_output=True, text=True)
    assert r.returncode == 2 and "(1 hole: --fill-holes closes it)" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert not out.exists()
    r = subprocess.run(base + ["--fill-holes"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "filled 1 hole (14.4 mm across)" in r.stdout + r.stderr
    assert out.read_text().count(";LAYER_CHANGE") == 5


def _slice(*args):
    import subprocess
    import sys
    return subprocess.run([sys.executable, "-m", "slicelab", "slice", *map(str, args)], capture_output=True,
                          text=True, timeout=300)


def test_slice_repairs_what_is_safe_unasked_and_says_so(tmp_path):
    # Two cubes touching along an edge (a non-manifold edge, closed by winding), two facets reversed
    # (misoriented edges, as the 3DBenchy has), and an inside-out cube: sliced, each repair said
    # in one line and in the G-code header; --no-repair refuses instead, in one line.
    a, b = box((0, 0, 0), (10, 10, 10)).triangles, box((10, 10, 0), (20, 20, 10)).triangles
    t = np.concatenate([a, b]).copy()
    t[[3, 7]] = t[[3, 7]][:, ::-1]
    slicelab.save(slicelab.Mesh(t), tmp_path / "misoriented.stl")
    slicelab.save(slicelab.Mesh(a[:, ::-1].copy()), tmp_path / "inside_out.stl")
    r0 = check(slicelab.load(tmp_path / "misoriented.stl"))
    assert r0.n_misoriented_edges and r0.n_nonmanifold_edges and not r0.watertight
    for name, said in (("misoriented", "reversed 2 facets to agree with their neighbours"),
                       ("inside_out", "turned 1 inside-out shell outward")):
        out = tmp_path / f"{name}.gcode"
        r = _slice(tmp_path / f"{name}.stl", "-o", out, "--layer-height", "0.3", "--first-layer-height", "0.1")
        assert r.returncode == 0, r.stderr
        assert r.stdout.splitlines()[0] == f"repair: {said}"
        assert f"; repaired: {said}\n" in out.read_text().split(";LAYER_CHANGE")[0]
        assert out.read_text().count(";LAYER_CHANGE") == 34   # 0.1 mm, then 33 of 0.3 mm
        refused = _slice(tmp_path / f"{name}.stl", "-o", tmp_path / "no.gcode", "--no-repair")
        assert refused.returncode == 2 and "--no-repair" in refused.stderr
        assert refused.stderr.splitlines()[-1].startswith("slicelab: error:") and not (tmp_path / "no.gcode").exists()
    # A clean part is not touched: no repair line, and the same G-code as with --no-repair.
    slicelab.save(box((0, 0, 0), (10, 10, 4)), tmp_path / "clean.stl")
    r = _slice(tmp_path / "clean.stl", "-o", tmp_path / "a.gcode")
    assert r.returncode == 0 and not r.stdout.startswith("repair:")
    assert _slice(tmp_path / "clean.stl", "-o", tmp_path / "b.gcode", "--no-repair").returncode == 0
    assert (tmp_path / "a.gcode").read_bytes() == (tmp_path / "b.gcode").read_bytes()
