"""The scan generator grows what real material has: lips, irregular and level breaks, base sherds,
angular steps, low-poly thick fragments, reassembled vessels with gaps; and its truth is consistent."""
import math

import numpy as np
import pytest

from slicelab import Mesh, check, samples
from slicelab.geometry.topology import edge_table, shells, weld


def _angles(v):
    return np.degrees(np.arctan2(v[:, 1], v[:, 0]))


@pytest.mark.parametrize("form", samples.FORMS)
def test_lips_change_the_outline_near_the_rim_only_and_keep_the_forms_rim(form):
    flat = samples.vessel_truth(form)
    for lip in samples.LIPS:
        outer, inner = samples.vessel_outlines(form, lip)
        ring = np.vstack([outer, inner])
        t = samples.vessel_truth(form, lip)
        assert float(ring[:, 1].max()) == pytest.approx(flat["height"], abs=1e-9)  # the crest at the form's height
        assert t["height"] == flat["height"]
        if lip == "everted":  # the flare is the form's own: the rim moves out
            assert t["rim_diameter"] > flat["rim_diameter"] + 2
            continue
        # Rounding and bevelling take clay from the top only: the form's rim, base and belly stay.
        assert t["rim_diameter"] == pytest.approx(flat["rim_diameter"], abs=1e-9)
        assert t["base_diameter"] == flat["base_diameter"]
        low = ring[:, 1] < flat["height"] - 6.0
        flat_ring = np.vstack(samples.vessel_outlines(form))
        assert np.array_equal(ring[low], flat_ring[flat_ring[:, 1] < flat["height"] - 6.0])
        # The capacity grows by the wedge the lip's shaping leaves under the crest's plane, never shrinks.
        assert flat["capacity"] <= t["capacity"] <= flat["capacity"] * 1.03
        # A rounded lip has no corner: the outline turns less than 10 degrees between its 0.02 mm steps.
        if lip == "rounded":
            top = outer[outer[:, 1] > flat["height"] - 3.0]
            d = np.diff(top, axis=0)
            turn = np.abs(np.diff(np.unwrap(np.arctan2(d[:, 1], d[:, 0]))))
            assert np.degrees(turn).max() < 10


@pytest.mark.parametrize("steps", [180, 240, 1440])
def test_a_vessel_can_have_any_number_of_steps_round_its_axis(steps):
    v, f = samples.vessel_mesh("bowl", 1.0, steps=steps)
    assert check(Mesh.from_vertices_faces(v, f)).watertight
    r = np.hypot(v[:, 0], v[:, 1])
    widest = np.isclose(r, r.max())
    assert len(np.unique(np.round(_angles(v[widest]), 6))) == steps


@pytest.mark.parametrize("breaks", samples.BREAKS)
@pytest.mark.parametrize("kind", samples.SHERDS)
def test_every_sherd_is_a_closed_block_whose_truth_its_mesh_shows(kind, breaks):
    v, f, info = samples.broken_sherd("pot", kind, 60.0, spacing=1.0, seed=5, breaks=breaks,
                                      lip="rounded" if kind == "rim" else "flat")
    r = check(Mesh.from_vertices_faces(v, f))
    assert r.watertight and r.volume > 0
    ang = (_angles(v) - _angles(v).min()) % 360  # the sherd sits at angles 0..span from its first break
    assert info["span"] == pytest.approx(float(ang.max() - ang.min()), abs=0.5)
    if kind == "rim":
        # The rim fraction is the lip's arc at its crest's outer edge: the vertices there span it.
        crest = v[v[:, 2] >= v[:, 2].max() - 0.05]
        a = (_angles(crest) - _angles(v).min()) % 360
        assert 360 * info["rim_fraction"] == pytest.approx(float(a.max() - a.min()), abs=2.5)
        assert info["base_fraction"] == 0.0
    if kind == "base":
        assert 0.1 < info["base_fraction"] < 0.25 and info["rim_fraction"] == 0.0
    if breaks == "straight":
        assert info["span"] == pytest.approx(60.0, abs=1e-6)


def test_irregular_breaks_waver_as_real_ones_and_a_level_break_runs_level():
    def lower_break(breaks, seed):
        v, f, info = samples.broken_sherd("beaker", "rim", 90.0, spacing=0.5, seed=seed, breaks=breaks, rough=0.0)
        low = v[v[:, 2] <= v[:, 2].min() + 12]
        # The lowest point in each degree: where the break runs.
        k = np.floor(_angles(low) - _angles(low).min()).astype(int)
        return np.array([low[k == j, 2].min() for j in np.unique(k)[8:-8]])  # clear of the side breaks

    for seed in (1, 2, 3):
        irregular = lower_break("irregular", seed)
        assert 2.0 <= np.ptp(irregular) <= 8.5  # wavering up to 4 mm either way
        level = lower_break("level", seed)
        assert np.ptp(level) <= 0.6  # within 0.25 mm either way, and the sampling
    # Side breaks waver by degrees: the sherd's edge angle changes with height.
    v, f, _ = samples.broken_sherd("pot", "rim", 60.0, spacing=0.5, seed=4, rough=0.0)
    a = _angles(v)
    bands = [a[(v[:, 2] >= z) & (v[:, 2] < z + 2)] for z in np.arange(85, 118, 4)]
    assert np.ptp([b.min() for b in bands if len(b)]) > 1.0


def test_a_low_poly_thick_fragment_is_a_few_hundred_uneven_facets():
    for kind in samples.SHERDS:
        for seed in range(4):
            mesh, truth = samples.scan("pot", sherd=kind, lowpoly=True, seed=seed)
            v, f = weld(mesh.triangles)
            assert 250 <= len(mesh) <= 420 and check(mesh).watertight
            edges = np.linalg.norm(v[f] - v[np.roll(f, 1, axis=1)], axis=2)
            assert edges.max() / np.median(edges) > 1.5  # uneven, as decimation leaves them
            assert truth["kind"] == kind and truth["spacing"] is None


def test_a_reassembled_vessel_is_closed_fragments_with_gaps_some_missing():
    v, f, info = samples.assembled_vessel("pot", fragments=30, spacing=2.0, seed=3)
    vw, fw = weld(v[f])
    n, label = shells(fw)
    assert n == info["fragments"] and info["missing"] >= 1
    assert (edge_table(fw)["counts"] == 2).all()  # every fragment closed
    # Gaps: no two fragments touch (each shell's own vertices only).
    assert len(vw) == len(np.unique(np.round(v[f].reshape(-1, 3), 9), axis=0))
    assert 0 < info["rim_fraction"] < 1 and 0 < info["base_fraction"] < 1
    mesh, truth = samples.scan("pot", fragments=30, spacing=2.0, seed=3)
    assert truth["kind"] == "fragmentary" and truth["rim_fraction"] == info["rim_fraction"]


def test_a_chipped_open_rim_is_open_below_its_top():
    mesh, truth = samples.scan("pot", spacing=2.0, open_rim=True, chip=25.0, pose=False, seed=1)
    r = check(mesh)
    assert r.n_open_edges > 0 and truth["chip"] == 25.0
    top = mesh.triangles[..., 2].max()
    # Facets within 8 mm of the top are gone over 25 degrees: the notch.
    c = mesh.triangles.mean(axis=1)
    near = c[:, 2] > top - 7.0
    ang = np.sort(np.degrees(np.arctan2(c[near, 1], c[near, 0])) % 360)
    gaps = np.diff(np.concatenate([ang, ang[:1] + 360]))
    assert 20 < gaps.max() < 30
