"""Perimeters by erosion against exact vector offsets (shapely, dev extra), thin walls, gap fill."""
import numpy as np
import pytest

import slicelab
from slicelab.geometry.spatial import SegmentIndex
from slicelab.printing.pipeline import plan_layer
from slicelab.printing.steps.perimeters import layer_perimeters as perimeters
from slicelab.samples import nested_shells
from layer_shapes import SHAPES, corner_angles, rect, section_of

shapely = pytest.importorskip("shapely")

P = 0.05  # a fine pixel: the geometry tests below hold to 0.01 mm here
#: Largest distance (mm) between our perimeters and the exact offsets, away from sharp corners,
#: by pixel size: the default (0.1 mm) stays well inside the 0.025 mm a print needs.
TOLERANCE = {0.05: 0.01, 0.1: 0.015, 0.2: 0.02}


def _densify(rings, step=0.01):
    return np.concatenate([np.asarray(shapely.segmentize(shapely.LinearRing(r), step).coords) for r in rings])


def _sharp_corner_tips(loops, level):
    """Where the exact offset at `level` has the corners of polygon corners sharper than 90 degrees."""
    tips = []
    for lp in loops:
        ccw = shapely.LinearRing(lp).is_ccw
        ring = lp if ccw else lp[::-1]
        ang = corner_angles(ring) if ccw else corner_angles(ring)
        for k in np.flatnonzero(ang < 90):
            a = ring[k - 1] - ring[k]
            b = ring[(k + 1) % len(ring)] - ring[k]
            bis = a / np.linalg.norm(a) + b / np.linalg.norm(b)
            tips.append(ring[k] + bis / np.linalg.norm(bis) * level / np.sin(np.radians(ang[k]) / 2))
    return np.array(tips).reshape(-1, 2)


@pytest.mark.parametrize("pixel", sorted(TOLERANCE))
@pytest.mark.parametrize("name", list(SHAPES))
def test_perimeters_match_exact_offsets(name, pixel):
    loops = SHAPES[name]
    per = perimeters(section_of(loops), 0.4, 2, pixel_size=pixel)
    poly = shapely.Polygon(loops[0], loops[1:])
    for k, level in enumerate(per.levels):
        ref = poly.buffer(-level, join_style="round", quad_segs=64)
        ours = shapely.MultiPolygon([shapely.Polygon(q.exterior, q.holes) for q in per.rings[k]])
        # Simplification (0.01 mm) cuts chords inside curves: at most a strip that wide along the boundary.
        assert abs(ours.area - ref.area) <= max(1e-3 * ref.area, 0.01 * ref.length * (pixel > 0.1))
        # Both ways: our boundary's points to the exact boundary, and back.
        mine = _densify([r for q in per.rings[k] for r in (q.exterior, *q.holes)])
        exact = np.concatenate([np.asarray(shapely.segmentize(g, 0.01).coords)
                                for g in getattr(ref.boundary, "geoms", [ref.boundary])])
        d1 = shapely.distance(ref.boundary, shapely.points(mine))
        d2 = shapely.distance(ours.boundary, shapely.points(exact))
        tips = _sharp_corner_tips(loops, level)
        for pts, d in ((mine, d1), (exact, d2)):
            near = np.zeros(len(pts), bool)
            for t in tips:
                near |= np.hypot(*(pts - t).T) < 0.25
            assert d[~near].max() <= TOLERANCE[pixel], (name, level, d[~near].max())
            if near.any():
                assert d[near].max() <= 0.5 * pixel, (name, level, d[near].max())


def test_sharp_corners_are_snapped_exactly():
    per = perimeters(section_of([rect(0.013, 0.021, 10.013, 6.021)]), 0.4, 2, pixel_size=0.1)
    for k, level in enumerate(per.levels):
        (poly,) = per.rings[k]
        assert len(poly.exterior) == 4
        lo = np.array([0.013, 0.021]) + level
        hi = np.array([10.013, 6.021]) - level
        np.testing.assert_allclose(np.sort(poly.exterior[:, 0]), [lo[0]] * 2 + [hi[0]] * 2, atol=1e-9)
        np.testing.assert_allclose(np.sort(poly.exterior[:, 1]), [lo[1]] * 2 + [hi[1]] * 2, atol=1e-9)


def test_hierarchy_is_recomputed_at_every_level():
    # A dumbbell: two squares joined by a 0.6 mm neck. The first perimeter (0.2) goes round
    # both; the second (0.6) cannot pass the neck, so erosion splits the island in two.
    dumbbell = np.array([[0, 0], [5, 0], [5, 2.2], [7, 2.2], [7, 0], [12, 0], [12, 5], [7, 5], [7, 2.8],
                         [5, 2.8], [5, 5], [0, 5]], float) + 0.011
    per = perimeters(section_of([dumbbell]), 0.4, 2, pixel_size=P)
    assert [len(level) for level in per.rings] == [1, 2]
    # Two holes 0.6 mm apart: separate around the first perimeter, merged at the second.
    holes = [rect(2, 2, 5, 5)[::-1] + 0.013, rect(5.6, 2, 8.6, 5)[::-1] + 0.013]
    per = perimeters(section_of([rect(0, 0, 11, 7) + 0.013, *holes]), 0.4, 2, pixel_size=P)
    assert [len(level[0].holes) for level in per.rings] == [2, 1]


def test_nested_shells_depths_per_level():
    s = slicelab.section(nested_shells(), (0, 0, 20), (0, 0, 1))
    per = perimeters(s, 0.4, 2, pixel_size=0.1)
    for level in per.rings:
        assert sorted(p.depth for p in level) == [0, 2]
        assert sorted(len(p.holes) for p in level) == [0, 1]


def test_thin_wall_gets_gap_fill_along_its_middle():
    wall = rect(0, 0, 10, 0.3) + (0.012, 0.017)
    per = perimeters(section_of([wall]), 0.4, 2, pixel_size=P)
    assert per.thin_walls == 1
    assert all(len(level) == 0 for level in per.rings)
    assert len(per.gap_fill) == 1
    line, width = per.gap_fill[0], per.gap_widths[0]
    assert np.hypot(*np.diff(line, axis=0).T).sum() > 9.0
    np.testing.assert_allclose(line[:, 1], 0.017 + 0.15, atol=P)
    assert np.all(np.abs(width - 0.3) <= 2 * P)


def test_gap_between_perimeters_is_filled():
    # A 1.1 mm wall: perimeters at 0.2 and 0.6 from each side leave 0.3 mm in the middle.
    wall = rect(0, 0, 20, 1.1) + (0.012, 0.017)
    per = perimeters(section_of([wall]), 0.4, 2, pixel_size=P)
    assert per.thin_walls == 0 and len(per.rings[0]) == 1 and len(per.rings[1]) == 0
    assert len(per.gap_fill) >= 1
    k = max(range(len(per.gap_fill)), key=lambda i: len(per.gap_fill[i]))
    longest = per.gap_fill[k]
    assert np.hypot(*np.diff(longest, axis=0).T).sum() > 15
    np.testing.assert_allclose(longest[:, 1], 0.017 + 0.55, atol=P)
    assert np.all(np.abs(per.gap_widths[k] - 0.3) <= 2 * P)
    # A 1.9 mm wall: the filling's region (centre lines 0.94 mm in) is a sliver too thin to fill,
    # so the middle 0.3 mm between the perimeters is gap fill as well.
    per = perimeters(section_of([rect(0, 0, 20, 1.9) + (0.012, 0.017)]), 0.4, 2, pixel_size=P)
    assert per.fill == [] and len(per.rings[1]) == 1
    k = max(range(len(per.gap_fill)), key=lambda i: len(per.gap_fill[i]))
    np.testing.assert_allclose(per.gap_fill[k][:, 1], 0.017 + 0.95, atol=P)
    assert np.all(np.abs(per.gap_widths[k] - 0.3) <= 2 * P)
    # Material too thin to print at all (under half a line width) is left alone.
    per = perimeters(section_of([rect(0, 0, 10, 0.12)]), 0.4, 2, pixel_size=P)
    assert per.gap_fill == [] and per.thin_walls == 1


def test_segment_index_is_exact_against_brute_force():
    rng = np.random.default_rng(5)
    seg = rng.uniform(-10, 10, (300, 2, 2))
    q = rng.uniform(-12, 12, (500, 2))
    d, s, t = SegmentIndex(seg, 0.5).nearest(q)
    a, b = seg[:, 0], seg[:, 1]
    ab = b - a
    tt = np.clip(np.einsum("qsk,sk->qs", q[:, None] - a, ab) / np.einsum("sk,sk->s", ab, ab), 0, 1)
    brute = np.hypot(*(q[:, None] - a - tt[..., None] * ab).transpose(2, 0, 1)).min(axis=1)
    np.testing.assert_allclose(d, brute, rtol=0, atol=1e-12)


def test_bad_arguments():
    s = section_of([rect(0, 0, 2, 2)])
    with pytest.raises(ValueError, match="line width"):
        perimeters(s, 0.0)
    with pytest.raises(ValueError, match="perimeter count"):
        perimeters(s, 0.4, -1)


def test_march_matches_skimage_find_contours():
    from skimage import measure

    from slicelab.geometry.contours import march
    rng = np.random.default_rng(0)

    def area(r):
        return 0.5 * np.sum(r[:, 1] * np.roll(r[:, 0], -1) - np.roll(r[:, 1], -1) * r[:, 0])

    for _ in range(100):  # random fields are full of saddles
        v = rng.normal(size=(12, 15))
        v[0] = v[-1] = v[:, 0] = v[:, -1] = -5
        ref = [c[:-1] for c in measure.find_contours(v, 0.3, fully_connected="high", positive_orientation="low")]
        ours = march(v, 0.3)
        assert len(ours) == len(ref)
        key = (lambda rings: sorted(tuple(np.round(p, 9)) for r in rings for p in r))
        assert key(ours) == key(ref)
        np.testing.assert_allclose(sorted(map(area, ours)), sorted(map(area, ref)), atol=1e-12)


def _rings_of(polygons):
    return sorted((r for q in polygons for r in (q.exterior, *q.holes)), key=lambda r: tuple(r[0]))


@pytest.mark.parametrize("name, p", [(name, 0.1) for name in [*SHAPES, "walls", "ring"]] + [("walls", 0.05)])
def test_block_seams_change_nothing(name, p):
    # Perimeters, filling region, gap fill and thin walls come out the same, array for array,
    # with small blocks as with blocks of 512 px that hold the island in one to four.
    from slicelab.printing.grid.raster import rasterize
    from layer_shapes import circle
    loops = {"walls": [rect(0, 0, 10, 0.3) + 0.012, rect(0, 1, 20, 2.1) + 0.017, rect(0, 3, 20, 4.9) + 0.013],
             "ring": [circle(6, 90, (0.01, 0.02)), circle(4.6, 90, (0.01, 0.02))[::-1]]}.get(name) or SHAPES[name]
    s = section_of(loops)
    whole = perimeters(rasterize(s, p, block=512), 0.4, 2)
    for block in (16, 32):
        per = perimeters(rasterize(s, p, block=block), 0.4, 2)
        for ours, ref in zip(per.rings + [per.fill], whole.rings + [whole.fill]):
            a, b = _rings_of(ours), _rings_of(ref)
            assert len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b)), (name, block)
        assert len(per.gap_fill) == len(whole.gap_fill)
        for g in per.gap_fill:
            assert any(np.array_equal(g, h) for h in whole.gap_fill)
        assert per.thin_walls == whole.thin_walls
        assert sum(f.refined for f in per.fields) == sum(f.refined for f in whole.fields)


def test_march_blocks_matches_march_across_seams():
    from slicelab.geometry.blocks import EMPTY, FULL, BlockGrid
    from slicelab.geometry.contours import march, march_blocks
    rng = np.random.default_rng(3)
    for _ in range(100):
        b = int(rng.integers(2, 6))
        kinds = np.pad(rng.choice([0, EMPTY, FULL], tuple(rng.integers(2, 6, 2)), p=[0.6, 0.2, 0.2]), 1,
                       constant_values=EMPTY)
        # Uniform blocks of different kinds do not touch (as in a layer's mask).
        grid = BlockGrid.from_status(b, int(rng.integers(-3, 3)), int(rng.integers(-3, 3)), kinds == 0, kinds == FULL)
        grid, _ = grid.widen(np.zeros((len(grid), b, b), bool), False, True)
        data = rng.normal(size=(len(grid), b, b)).astype(np.float32)
        nr, nc = grid.table.shape
        r0, c0 = grid.row0 * b - 1, grid.col0 * b - 1
        whole = grid.assemble(data, np.float32(-5), np.float32(5), r0, c0, (nr * b + 2, nc * b + 2))
        ref = sorted(tuple(q) for r in march(whole, 0.3) for q in np.round(r + [r0, c0], 9))
        ours = sorted(tuple(q) for r in march_blocks(data, 0.3, grid, -5.0, 5.0) for q in np.round(r, 9))
        assert ours == ref


def test_segment_index_reach_gives_the_same_answers():
    rng = np.random.default_rng(7)
    t = np.sort(rng.uniform(0, 2 * np.pi, 60))
    ring = np.c_[10 * np.cos(t), 10 * np.sin(t)]
    seg = np.stack([ring, np.roll(ring, -1, axis=0)], 1)
    q = rng.uniform(-12, 12, (3000, 2))
    d0 = SegmentIndex(seg, 0.2).nearest(q)[0]
    for reach in (0.1, 0.8, 5.0):
        d1 = SegmentIndex(seg, 0.2, join=True).nearest(q, reach=reach)[0]
        np.testing.assert_allclose(d1, d0, rtol=0, atol=1e-12)


def test_work_grows_with_the_boundary():
    # Pixels the perimeters touch grow with a ring's radius, not with its area.
    from layer_shapes import circle
    touched = []
    for radius in (10.0, 40.0):
        n = int(2 * np.pi * radius / 0.5)
        per = perimeters(section_of([circle(radius, n), circle(radius - 4, n)[::-1]]), 0.4, 2, pixel_size=P)
        touched.append(sum(f.grid.pixels for f in per.fields))
    assert touched[1] / touched[0] < 5


def test_default_pixel_is_one_whose_accuracy_is_tested():
    # Left out, the pixel is half the line width: 0.2 mm for the default 0.4 mm lines.
    assert slicelab.PrintSettings().pixel_size in TOLERANCE
    s = section_of([rect(0, 0, 10, 6) + 0.013])
    assert perimeters(s, 0.4, 2).fields[0].grid.pixel_size in TOLERANCE
    assert plan_layer(s).walls.fields[0].grid.pixel_size in TOLERANCE
    assert perimeters(s, 0.6, 2).fields[0].grid.pixel_size == pytest.approx(0.3)
    assert slicelab.PrintSettings(line_width=0.6).pixel_size == pytest.approx(0.3)
    assert slicelab.PrintSettings(line_width=0.6, pixel_size=0.1).pixel_size == 0.1
    with pytest.raises(ValueError, match="pixel_size must be at most the line width"):
        slicelab.PrintSettings(pixel_size=0.5)


@pytest.mark.parametrize("pixel", [0.1, 0.2])
def test_offsets_follow_arcs_and_creases_between_pixels(pixel):
    # A plate with a tongue 1 mm wide hanging from it: round the tongue's root the offsets are
    # arcs of radius `level`, and at 0.6 mm (more than half the tongue) the two arcs meet in a
    # crease 0.33 mm above the root, which linear interpolation between 0.2 mm pixels cuts by 0.07 mm.
    plate = np.array([[0, 3], [4, 3], [4, 0], [5, 0], [5, 3], [9, 3], [9, 6], [0, 6]], float) + (0.013, 0.021)
    per = perimeters(section_of([plate]), 0.4, 2, pixel_size=pixel)
    poly = shapely.Polygon(plate)
    for k, level in enumerate(per.levels):
        ref = poly.buffer(-level, quad_segs=256).exterior
        (ring,) = [q.exterior for q in per.rings[k]]
        ours = shapely.LinearRing(ring)
        assert shapely.hausdorff_distance(ours, ref, densify=0.005) <= 0.012, level
        if level > 0.5:
            crease = shapely.Point(np.array([4.5, 3 + np.sqrt(level ** 2 - 0.25)]) + (0.013, 0.021))
            assert ours.distance(crease) <= 0.01
        # Arcs in even steps: no chord much shorter than an arc of radius `level` needs to stay
        # within 0.01 mm, but where an arc meets a line or a crease.
        chords = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
        need = 2 * level * np.sin(np.arccos(1 - 0.01 / level) / 2)
        assert np.count_nonzero(chords < 0.5 * need) <= 4, (level, np.sort(chords)[:8])


@pytest.mark.parametrize("pixel", [0.05, 0.1, 0.2])
def test_a_raster_with_the_perimeters_band_is_used_as_it_is(pixel):
    from slicelab.printing.steps.perimeters import perimeter_band
    s = section_of([rect(0, 0, 10, 6) + 0.013])
    raster = slicelab.rasterize(s, pixel, band=perimeter_band(0.4, 2, 0.15, pixel))
    per = perimeters(raster, 0.4, 2, overlap=0.15)
    assert per.fields[0].grid is raster.tiles[0]
    # A narrower band is made again, wide enough.
    narrow = slicelab.rasterize(s, pixel, band=0.5)
    assert perimeters(narrow, 0.4, 2, overlap=0.15).fields[0].grid is not narrow.tiles[0]


@pytest.mark.parametrize("pixel", [0.1, 0.2])
@pytest.mark.parametrize("wall", [0.3, 1.1])
def test_thin_walls_and_gaps_keep_their_gap_fill_at_coarse_pixels(pixel, wall):
    # A 0.3 mm wall (thinner than a line) and the 0.3 mm left between the perimeters of a 1.1 mm
    # wall are one or two pixels across at 0.2 mm: they must still get gap fill along their
    # middle, wherever the pixel grid falls.
    for shift in (0.0, 0.05, 0.1, 0.15):
        loops = [rect(0, 0, 20, wall) + (0.012, 0.017 + shift)]
        per = perimeters(section_of(loops), 0.4, 2, pixel_size=pixel)
        length = sum(np.hypot(*np.diff(q, axis=0).T).sum() for q in per.gap_fill)
        assert length > 18, (wall, shift, length)
        mid = 0.017 + shift + wall / 2
        for q, width in zip(per.gap_fill, per.gap_widths):
            line = shapely.LineString(q)
            pts = shapely.get_coordinates(line.interpolate(np.arange(0, line.length, 0.05)))
            inner = (pts[:, 0] > 1) & (pts[:, 0] < 19)  # away from the ends, where the skeleton forks
            assert np.abs(pts[inner, 1] - mid).max() <= 0.6 * pixel + 0.01
            assert np.all((width >= 0.2 - 1e-9) & (width <= 0.6 + 1e-9))


def test_thin_islands_are_counted_one_by_one_in_a_shared_tile():
    # Far-apart islands share the layer's tile: a 5 mm square (its perimeters fit), a 0.3 mm
    # wall (too thin for one) and a ring whose hole is an island of its own (an island in a hole:
    # counted on the pixels). One thin island each time.
    square, wall = rect(0, 0, 5, 5), rect(20, 0, 30, 0.3) + (0.012, 0.017)
    assert perimeters(section_of([square]), 0.4, 2, pixel_size=P).thin_walls == 0
    per = perimeters(section_of([square, wall]), 0.4, 2, pixel_size=P)
    assert per.thin_walls == 1 and len(per.rings[0]) == 1 and len(per.gap_fill) == 1
    ring = [rect(40, 0, 50, 10), rect(42, 2, 48, 8)[::-1], rect(44.9, 3, 45.2, 7)]  # a thin bar in the hole
    per = perimeters(section_of([square, *ring]), 0.4, 2, pixel_size=P)
    assert per.thin_walls == 1
    per = perimeters(section_of([square, wall, *ring]), 0.4, 2, pixel_size=P)
    assert per.thin_walls == 2


def test_medial_fill_of_far_slivers_is_each_sliver_alone():
    # Three 0.3 mm slivers at the corners of a 300 mm window (a box of 2.25 million pixels, as a
    # wide ring's solid skin has): each gives its own centre line, 0.3 mm wide, as when alone; the
    # long one crosses several blocks and comes out whole.
    from slicelab.printing.steps.gapfill import medial_fill
    from slicelab.printing.grid.masks import GridMask
    p, w = 0.2, 0.4
    mask = np.zeros((1500, 1500), bool)
    slivers = [(slice(10, 12), slice(20, 120)), (slice(1400, 1402), slice(1300, 1340)),
               (slice(700, 760), slice(5, 7))]  # rows x cols of pixels: 0.4 mm across (2 px)
    for rows, cols in slivers:
        mask[rows, cols] = True
    lines, widths = medial_fill(GridMask(mask, -700, 300, p), mask, w, 0.5 * w)
    alone = []
    for rows, cols in slivers:
        one = np.zeros_like(mask)
        one[rows, cols] = True
        alone.append(medial_fill(GridMask(one, -700, 300, p), one, w, 0.5 * w))
    assert len(lines) == 3 == sum(len(a[0]) for a in alone)
    key = lambda q: tuple(np.round(q[0], 9))  # noqa: E731
    for got, want in zip(sorted(lines, key=key), sorted((a[0][0] for a in alone), key=key)):
        np.testing.assert_array_equal(got, want)
    length = sorted(float(np.hypot(*np.diff(q, axis=0).T).sum()) for q in lines)
    np.testing.assert_allclose(length, [(40 - 2) * p, (60 - 2) * p, (100 - 2) * p], atol=2 * p)
    for q in lines:  # each along its sliver's middle
        horizontal = np.ptp(q[:, 0]) > np.ptp(q[:, 1])
        across = q[:, 1] / p + 700 if horizontal else q[:, 0] / p - 300
        assert np.ptp(across) <= 1
    assert all(np.all((wd >= 0.5 * w - 1e-9) & (wd <= 1.5 * w)) for wd in widths)


def test_walls_cut_by_a_mask_survive_rings_that_pinch_or_cross():
    # GEOS stops with "TopologyException: side location conflict" when an overlay meets a ring
    # that crosses itself (a simplified level ring that pinched): split_by_mask makes each side
    # valid first and snap-rounds if GEOS still fails, so the layer is planned, not lost.
    import shapely
    from slicelab.geometry.polygons import Polygon, signed_area
    from slicelab.geometry.regions import overlay, valid_region
    from slicelab.printing.grid.masks import GridMask
    from slicelab.printing.steps.perimeters import split_by_mask
    bowtie = Polygon(np.array([[0, 0], [2, 2], [2, 0], [0, 2]], float), [], 0)
    with pytest.raises(shapely.errors.GEOSException):  # what the walls met before
        shapely.MultiPolygon([shapely.Polygon(bowtie.exterior)]).intersection(shapely.box(-1, -1, 1, 3))
    mask = GridMask(np.ones((40, 20), bool), -10, -10, 0.1)   # pixels' edges: x, y from -1.05 to 0.95, 2.95
    inside, outside = split_by_mask([bowtie], mask)
    got = sum(abs(signed_area(r)) for r in inside + outside)
    assert got == pytest.approx(2.0, abs=1e-9)    # the two triangles the bow-tie is made of
    # Inside: the left triangle (0, 0), (1, 1), (0, 2) but its tip beyond x = 0.95.
    assert sum(abs(signed_area(r)) for r in inside) == pytest.approx(1 - 0.05 ** 2, abs=1e-9)
    assert valid_region([shapely.Polygon(bowtie.exterior)]).is_valid
    # An overlay GEOS cannot do in floating point is done on the snapping grid instead.
    calls = []

    def fussy(a, b, grid_size=None):
        calls.append(grid_size)
        if grid_size is None:
            raise shapely.errors.GEOSException("TopologyException: side location conflict")
        return shapely.intersection(a, b, grid_size=grid_size)
    assert overlay(fussy, shapely.box(0, 0, 2, 2), shapely.box(1, 1, 3, 3)).area == pytest.approx(1.0)
    assert calls == [None, 1e-4]


def test_corners_of_the_offset_are_found_inside_the_material_not_in_its_mirror():
    # The point where the offsets through two ring vertices meet is at the level's distance from
    # the boundary on both sides of it: chosen outside, a perimeter spiked 1.2 mm out of this
    # quadrilateral (and of rear_case.stl's layer 379). Every vertex of every level lies inside,
    # at the level's distance or more (less the tolerance).
    from types import SimpleNamespace

    import shapely
    from slicelab.printing.grid.raster import rasterize
    quad = np.array([[45.776467681152795, -3.4254649070641108], [42.17646768115279, -8.225464907064111],
                     [46.97646768115279, -12.42546490706411], [51.776467681152795, -15.42546490706411]])
    per = perimeters(rasterize(SimpleNamespace(loops=[quad]), 0.2), 0.4, 2)
    region = shapely.Polygon(quad)
    for level, polys in zip(per.levels, per.rings):
        pts = shapely.points(np.concatenate([p.exterior for p in polys]))
        assert shapely.contains(region, pts).all()
        assert shapely.distance(region.boundary, pts).min() >= level - 0.02
