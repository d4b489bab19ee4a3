"""Layer rasters: nonzero/even-odd fill, world-anchored grid, hole hierarchy, block masks."""
import numpy as np
import pytest
from matplotlib.path import Path as MplPath

import slicelab
from slicelab.printing.grid.hierarchy import raster_hierarchy
from slicelab.printing.grid.raster import GridMask, rasterize
from slicelab.samples import box, concat, nested_shells
from layer_shapes import SHAPES, circle, rect, section_of, star


def target():
    """outer square > hole > island > hole, as four nested shells."""
    return concat(box((0, 0, 0), (40, 40, 10)), box((5, 5, -1), (35, 35, 11), inward=True),
                  box((10, 10, 0), (30, 30, 10)), box((15, 15, -1), (25, 25, 11), inward=True))


@pytest.mark.parametrize("mesh, depths", [(nested_shells(), [0, 1, 2]), (target(), [0, 1, 2, 3])])
def test_hierarchy_matches_vector_hierarchy(mesh, depths):
    s = slicelab.section(mesh, (0, 0, 5.5 if len(depths) == 4 else 20), (0, 0, 1))
    h = raster_hierarchy(rasterize(s, 0.25))
    assert sorted(h.depth.tolist()) == depths
    assert (h.loop >= 0).all()
    np.testing.assert_array_equal(s.loop_depth[h.loop], h.depth)
    # Parents agree too: the vector parent of a contour's loop is the loop of its raster parent.
    for k in range(len(h.depth)):
        if h.parent[k] >= 0:
            assert s.loop_parent[h.loop[k]] == h.loop[h.parent[k]]


def test_overlapping_cubes_nonzero_one_region_evenodd_hole(data_dir):
    mesh = slicelab.load(data_dir / "overlapping_cubes.stl")
    s = slicelab.section(mesh, (0, 0, 10.0), (0, 0, 1))
    p = 0.1
    nz = rasterize(s, p, rule="nonzero")
    eo = rasterize(s, p, rule="evenodd")
    hn, he = raster_hierarchy(nz), raster_hierarchy(eo)
    assert hn.depth.tolist() == [0]
    assert sorted(he.depth.tolist()) == [0, 1]
    # Union 20x20 + 20x20 - 10x10 overlap; pixel-centre sampling errs by under a pixel row per edge.
    assert abs(nz.area - 700.0) < 80 * p
    assert abs(eo.area - 600.0) < 120 * p


@pytest.mark.parametrize("name", list(SHAPES))
def test_evenodd_mask_matches_point_in_polygon(name):
    loops = SHAPES[name]
    r = rasterize(section_of(loops), 0.1, rule="evenodd")
    tile = r.tiles[0]
    rows, cols = np.indices(tile.shape)
    pts = tile.xy(rows.ravel(), cols.ravel())
    inside = np.zeros(len(pts), bool)
    for lp in loops:
        inside ^= MplPath(lp).contains_points(pts)
    assert np.count_nonzero(inside != tile.mask.ravel()) <= 2  # points exactly on an edge may differ


def test_nonzero_fills_overlapping_loops_and_cancels_opposite_ones():
    a, b = rect(0, 0, 4, 4), rect(2, 2, 6, 6)
    nz = rasterize(section_of([a, b]), 0.1)
    assert abs(nz.area - 28.0) < 0.1 * 24 * 0.6
    # A clockwise loop inside a counter-clockwise one is a hole under both rules.
    both = [rasterize(section_of([rect(0, 0, 4, 4), rect(1, 1, 2, 2)[::-1]]), 0.1, rule=r).area
            for r in ("nonzero", "evenodd")]
    assert abs(both[0] - 15.0) < 0.5 and abs(both[1] - 15.0) < 0.5


def test_grid_is_anchored_to_the_world_origin():
    p = 0.05
    a = rasterize(section_of([rect(1.01, 2.02, 5.5, 4.3)]), p).tiles[0]
    shift = np.array([37, -12]) * p  # an exact number of pixels
    b = rasterize(section_of([rect(1.01, 2.02, 5.5, 4.3) + shift]), p).tiles[0]
    assert (b.col0 - a.col0, b.row0 - a.row0) == (37, -12)
    xy = a.xy(0, 0)
    np.testing.assert_allclose(xy / p, np.round(xy / p), atol=1e-9)
    np.testing.assert_array_equal(a.mask, b.mask)
    # Set algebra between layers works by integer offsets.
    back = GridMask(b.mask, b.row0 + 12, b.col0 - 37, p)
    assert (a - back).area == 0
    rows, cols = np.nonzero(a.mask)
    h, w = np.ptp(rows) + 1, np.ptp(cols) + 1
    assert np.count_nonzero((a - b).mask) == h * w - (h - 12) * (w - 37)
    assert np.count_nonzero((a & b).mask) == (h - 12) * (w - 37)
    assert (a | b).area == pytest.approx(2 * a.area - (a & b).area)


def test_far_islands_share_a_tile_but_cost_their_boundaries():
    # Two 2 mm squares 500 mm apart: one tile for the layer, pixels held only near the squares,
    # each island counted and drawn in its own box (the window between them is never made).
    far = section_of([rect(0, 0, 2, 2), rect(500, 300, 502, 302)])
    r = rasterize(far, 0.05)
    assert len(r.tiles) == 1 and r.loop_island.tolist() == [0, 1]
    assert r.pixels <= 2 * 4 * 32 ** 2  # at most four blocks of 32 px round each square
    assert r.island_pixels().tolist() == [1600, 1600] and abs(r.area - 8.0) < 1e-9
    box = r.island_boxes[1]
    assert box.tolist() == [300 / 0.05 - 3, 500 / 0.05 - 3, 302 / 0.05 + 3, 502 / 0.05 + 3]
    h = raster_hierarchy(r)
    assert sorted(h.loop.tolist()) == [0, 1] and h.depth.tolist() == [0, 0]
    assert "mask" not in vars(r.tiles[0])  # the tile's whole window was not assembled


def test_transform_and_indices_round_trip():
    r = rasterize(section_of([star()]), 0.05)
    t = r.tiles[0]
    rc = np.array([[3.25, 7.5], [10, 0]])
    xy = t.xy(rc[:, 0], rc[:, 1])
    np.testing.assert_allclose(t.indices(xy), rc)
    np.testing.assert_allclose((t.transform @ np.c_[rc[:, ::-1], np.ones(2)].T).T[:, :2], xy)


def test_bad_arguments():
    s = section_of([circle(1.0)])
    with pytest.raises(ValueError, match="rule"):
        rasterize(s, 0.1, rule="winding")
    with pytest.raises(ValueError, match="pixel size"):
        rasterize(s, -1)
    assert rasterize(slicelab.section(box(), (0, 0, 5), (0, 0, 1)), 0.1).tiles == ()


def _ring_edges(loops):
    return np.concatenate([np.stack([lp, np.roll(lp, -1, axis=0)], 1) for lp in loops])


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
@pytest.mark.parametrize("size", [8, 32])
def test_block_masks_are_the_whole_window_masks(rule, size):
    from slicelab.printing.grid.raster import raster_blocks, winding_numbers
    rng = np.random.default_rng(size)
    p = 0.05
    for band in (0.1, 0.7, 2.0):
        loops = [star(5, 6, 2.5, rng.uniform(-1, 1, 2)), circle(1.5, 40, rng.uniform(-1, 1, 2))[::-1],
                 rect(-4, -4, 1, 1) + rng.uniform(0, 1, 2)]  # overlapping shells: the rules differ
        e = _ring_edges(loops)
        m = raster_blocks(e, -180, -190, (370, 380), p, rule=rule, band=band, size=size)
        w = winding_numbers(e, -180, -190, (370, 380), p)
        ref = (w != 0) if rule == "nonzero" else (w % 2 == 1)
        np.testing.assert_array_equal(m.mask, ref)
        assert m.area == pytest.approx(np.count_nonzero(ref) * p * p)
        rows, cols = rng.integers(-200, 200, (2, 500))
        np.testing.assert_array_equal(m.at(rows, cols), GridMask(ref, -180, -190, p).window(-200, -200, (400, 400))[
            rows + 200, cols + 200])
        # Pixels are held only near the boundary: every held block is within the band of an edge.
        assert m.pixels < m.mask.size


def test_block_mask_algebra_and_opening_match_whole_masks():
    from slicelab.printing.grid.masks import open_mask
    a = rasterize(section_of([star(5, 8, 3)]), 0.05, band=0.4).tiles[0]
    b = rasterize(section_of([circle(5, 64, (2.0, 1.0))]), 0.05, band=0.4).tiles[0]
    ga, gb = a.to_grid(), b.to_grid()
    win = (-200, -200, (400, 400))
    for ours, ref in ((a & b, ga & gb), (a - b, ga - gb), (a | b, ga | gb), (b - a, gb - ga)):
        np.testing.assert_array_equal(ours.window(*win), ref.window(*win))
        assert ours.area == pytest.approx(ref.area)
        for r in (1, 4):
            np.testing.assert_array_equal(open_mask(ours, r).window(*win), open_mask(ref, r).window(*win))


def test_block_mask_dilation_matches_opencv_on_the_whole_mask():
    import cv2
    from slicelab.printing.grid.masks import dilate_mask, near_mask
    # A ring: full blocks in its wall, empty ones in its hole and around it, active ones between.
    a = rasterize(section_of([circle(9.0, 128), circle(3.0, 64)[::-1]]), 0.05, band=0.4).tiles[0]
    assert a.blocks.n_full > 0 and (a.blocks.table == -1).any()
    win = (-200, -200, (400, 400))
    for k in (1, 3, 9):  # within a block, and across several (blocks are 8 pixels or more)
        yy, xx = np.mgrid[-k:k + 1, -k:k + 1]
        disc = (yy * yy + xx * xx <= k * k + 0.5).astype(np.uint8)
        ref = cv2.dilate(a.window(*win).view(np.uint8), disc).view(bool)
        got = dilate_mask(a, disc)
        np.testing.assert_array_equal(got.window(*win), ref)
        np.testing.assert_array_equal(dilate_mask(a.to_grid(), disc).window(*win), ref)
        assert got.area == pytest.approx(ref.sum() * 0.05 ** 2)
        # Read on some blocks only (active, full, empty and beyond the mask's table alike).
        b = a.blocks.size
        lo, hi = -(200 // b), 200 // b  # the blocks inside the window
        rows, cols = np.mgrid[lo:hi, lo:hi].reshape(2, -1)
        near = near_mask(a, rows, cols, disc)
        for n, (i, j) in enumerate(zip(rows, cols)):
            r, c = i * b + 200, j * b + 200
            np.testing.assert_array_equal(near[n], ref[r:r + b, c:c + b])


def test_pixels_held_grow_with_the_boundary_not_the_area():
    # A ring of constant 4 mm wall: its window grows with the square of its radius, the pixels
    # held along its boundary only with the radius.
    held, window = [], []
    for radius in (20.0, 80.0):
        n = int(2 * np.pi * radius / 0.5)
        r = rasterize(section_of([circle(radius, n), circle(radius - 4, n)[::-1]]), 0.05)
        held.append(r.pixels)
        window.append(sum(t.mask.size for t in r.tiles))
        assert r.area == pytest.approx(np.pi * (radius ** 2 - (radius - 4) ** 2), rel=2e-3)
    assert window[1] / window[0] > 14
    assert held[1] / held[0] < 4.5


def test_a_strip_thinner_than_the_disc_across_a_block_seam_opens_to_nothing_from_the_erosion_alone(monkeypatch):
    # Four pixels wide across the seam of two blocks: in the mosaic, each block's halo holds the
    # other's pixels beside its own copy, eight in a row, which survive an erosion of radius 2.
    # Only the blocks' own pixels may decide, without the second, wider pass of the opening.
    from slicelab.geometry.blocks import BlockGrid
    from slicelab.printing.grid.masks import open_mask
    strip = np.array([[2.95, 0.0], [3.35, 0.0], [3.35, 4.0], [2.95, 4.0]])  # pixel columns 30-33
    m = rasterize(section_of([strip]), 0.1).tiles[0]
    assert m.blocks.n_full == 0 and len(np.unique(m.blocks.origins()[1])) == 2
    assert open_mask(m.to_grid(), 2) is None  # the whole mask's opening: nothing
    monkeypatch.setattr(BlockGrid, "widen", lambda *a, **k: pytest.fail("the opening ran its second pass"))
    assert open_mask(m, 2) is None


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_a_shell_inside_another_bounds_material_only_under_evenodd(rule):
    """Two shells, one inside the other and touching nowhere, both outward: under nonzero the inner
    one lies in material on both sides (winding 1 and 2) and bounds nothing, so the distances the
    perimeters follow ignore it; under even-odd it is a hole's wall. A hole (an inward shell) bounds
    material under both rules. Each loop is judged whole: all of its edges, or none."""
    s = slicelab.section(concat(box((0, 0, 0), (20, 20, 2)), box((6, 6, 0), (14, 14, 2)),
                                box((16, 2, 0), (18, 4, 2), inward=True)), (0, 0, 1), (0, 0, 1))
    (segs,) = rasterize(s, 0.2, rule=rule).segments
    boxes = {"outer": ((0, 0), (20, 20)), "inner": ((6, 6), (14, 14)), "hole": ((16, 2), (18, 4))}

    def edges_of(lo, hi):  # the section's edges, and the bounding ones, lying in the box lo..hi
        inside = lambda pts: np.all((pts >= np.array(lo) - 1e-9) & (pts <= np.array(hi) + 1e-9), axis=(-2, -1))  # noqa: E731
        loops = sum(len(lp) for lp in s.loops if inside(lp[None]))
        return loops, int(np.count_nonzero(inside(segs)))

    counts = {name: edges_of(*b) for name, b in boxes.items()}
    assert all(n >= 4 for n, _ in counts.values())
    assert counts["hole"][1] == counts["hole"][0]  # a hole's wall under both rules
    assert counts["inner"][1] == (0 if rule == "nonzero" else counts["inner"][0])
    assert len(segs) == counts["outer"][0] - counts["inner"][0] + counts["inner"][1]  # the outer box holds all


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_a_raster_drawn_on_the_neighbours_mask_is_the_raster_drawn_afresh(rule):
    """The planner draws each neighbour's mask alone (`layer_mask`) and a layer's islands and bounding
    edges on that mask: the same raster as drawn whole, and the mask is taken as it is."""
    from slicelab.printing.grid.raster import layer_mask
    s = slicelab.section(concat(box((0, 0, 0), (20, 20, 2)), box((6, 6, 0), (14, 14, 2)),
                                box((16, 2, 0), (18, 4, 2), inward=True), box((30, 0, 0), (33, 3, 2))),
                         (0, 0, 1), (0, 0, 1))
    mask = layer_mask(s, 0.2, rule=rule, band=1.2)
    whole, on_mask = rasterize(s, 0.2, rule=rule, band=1.2), rasterize(s, 0.2, rule=rule, band=1.2, tile=mask)
    assert on_mask.tiles[0] is mask
    np.testing.assert_array_equal(on_mask.tiles[0].mask, whole.tiles[0].mask)
    np.testing.assert_array_equal(on_mask.island_boxes, whole.island_boxes)
    assert len(whole.island_boxes) == 2
    for a, b in zip(on_mask.segments, whole.segments, strict=True):
        np.testing.assert_array_equal(a, b)
    empty = slicelab.section(box((0, 0, 5), (1, 1, 6)), (0, 0, 1), (0, 0, 1))  # (the plane misses it)
    assert layer_mask(empty, 0.2) is None and rasterize(empty, 0.2, tile=None).tiles == ()


def test_a_mask_dilated_by_the_reach_disc_is_what_the_distance_transform_puts_within_the_reach():
    # The skins' gap fill and the overhangs' first pass dilate a mask instead of measuring the
    # distance to it: the same pixels, ties at the reach included (float32, as OpenCV measures;
    # 0.05 mm pixels and 0.5 mm lines put pixels 6 apart at 5.999999999999999 reaches).
    import cv2
    from slicelab.printing.grid.masks import reach_disc
    rng = np.random.default_rng(3)
    for t in range(120):
        p = (0.05, 0.1, 0.2, 0.15, 0.3)[t % 5]
        src = rng.random(tuple(rng.integers(20, 90, 2))) < rng.uniform(0.005, 0.2)
        src[0, 0] = True
        dist = cv2.distanceTransform((~src).astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * p
        for reach, slack in ((0.5 * 0.4 + p, 0.0), (0.5 * 0.5 + p, 0.0), (0.2 * np.tan(np.radians(50)), 0.5 * p)):
            far = ~cv2.dilate(src.astype(np.uint8), reach_disc(reach, p, slack)).astype(bool)
            np.testing.assert_array_equal(far, dist - slack > reach)
