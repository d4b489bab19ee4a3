"""Rectilinear filling and layer paths: inside the region, coverage, zigzags, order (issue 5)."""
import numpy as np
import pytest

import slicelab
from slicelab.printing.fill.lines import fill_lines
from slicelab.geometry.polygons import Polygon
from slicelab.printing import PrintSettings
from slicelab.printing.pipeline import LayerInputs, layer_paths, plan_layer
from slicelab.printing.steps.coverage import coverage_map, covered_pixels
from slicelab.printing.grid.raster import GridMask
from slicelab.samples import nested_shells
from layer_shapes import SHAPES, circle, rect, rotation, section_of

shapely = pytest.importorskip("shapely")

CONVEX = {
    "square": [rect(0, 0, 20, 20) + 0.013],
    "disc": [circle(10, 128, (0.01, 0.02))],
    "hexagon": [circle(8, 6, (3.1, -2.2)) @ rotation(0.2).T],
}


def _inside_region(paths, region, tol=1e-7):
    pts = np.concatenate(paths)
    return bool(np.all(shapely.distance(region, shapely.points(pts)) <= tol))


@pytest.mark.parametrize("name", [*CONVEX, *SHAPES])
@pytest.mark.parametrize("density", [0.2, 1.0])
def test_filling_stays_inside_the_last_perimeter(name, density):
    loops = {**CONVEX, **SHAPES}[name]
    lp = layer_paths(section_of(loops), PrintSettings(infill_density=density, pixel_size=0.1))
    region = shapely.Polygon(loops[0], loops[1:]).buffer(-0.8)  # inside the second perimeter
    assert lp.filling_segments
    # Centre lines stay inside the region; their extrusions overlap the last perimeter by at
    # most the configured 15% of a line width.
    assert _inside_region(lp.filling_segments, region)
    widened = region.buffer(0.15 * 0.4 + 1e-6 - 0.2)
    assert _inside_region(lp.filling_segments, widened.buffer(0.2 - 1e-6 + 1e-6), tol=1e-6)


@pytest.mark.parametrize("name", list(CONVEX))
def test_convex_regions_need_one_zigzag(name):
    for density in (0.2, 1.0):
        lp = layer_paths(section_of(CONVEX[name]), PrintSettings(infill_density=density, pixel_size=0.1))
        assert len(lp.filling_segments) <= 2, (name, density, len(lp.filling_segments))


@pytest.mark.parametrize("name", ["square", "disc"])
def test_solid_filling_covers_the_region(name):
    p = 0.05
    planned = plan_layer(section_of(CONVEX[name]), PrintSettings(infill_density=1.0, pixel_size=p))
    lp, f = planned.paths, planned.walls.fields[0]
    g = f.grid
    region = g.mask & (f.values >= 0.8)  # inside the last perimeter
    cov = np.zeros(g.shape, bool)
    for q in lp.filling_segments:
        cov |= covered_pixels(g.shape, g.row0, g.col0, p, q, 0.4)
    gaps = np.count_nonzero(region & ~cov) / np.count_nonzero(region)
    assert gaps < 0.01
    # The whole layer: perimeters and filling together leave under 1% uncovered.
    counts, grid = coverage_map(lp, p)
    material = g.window(grid.row0, grid.col0, grid.shape)
    assert np.count_nonzero(material & (counts == 0)) < 0.01 * np.count_nonzero(material)


def test_lines_lie_on_a_world_anchored_grid_and_alternate():
    s = 2.0
    for loops in (CONVEX["disc"], [rect(3.3, 1.7, 17.1, 9.9)]):
        for layer, angle in ((0, 45.0), (1, 135.0)):
            lp = layer_paths(section_of(loops), PrintSettings(pixel_size=0.1), LayerInputs(index=layer))
            a = np.radians(angle)
            n = np.array([-np.sin(a), np.cos(a)])
            d = np.array([np.cos(a), np.sin(a)])
            on_grid = off_grid = 0.0
            for q in lp.filling_segments:
                seg = np.diff(q, axis=0)
                length = np.hypot(*seg.T)
                # Fill lines are parallel to d; links follow the boundary (a pixel staircase of
                # the filling limit may have a few short pieces parallel to d too).
                along = np.abs(seg @ n) <= 1e-9 * length
                offs = (q[:-1] @ n) / s
                grid = np.abs(offs - np.round(offs)) < 1e-6
                on_grid += length[along & grid].sum()
                off_grid += length[along & ~grid].sum()
            assert on_grid > 0 and off_grid < 0.02 * on_grid


def test_fill_lines_against_shapely_intersection():
    sq = Polygon(rect(0.3, 0.1, 7.7, 5.2), (rect(2, 2, 3, 3)[::-1],), 0)
    f = fill_lines([sq], 0.5, 30.0)
    inv = f.rot
    poly = shapely.Polygon(sq.exterior, sq.holes)
    total = 0.0
    for a, b in zip(f.start, f.end):
        p0 = np.array([f.xc[a], f.yc[a]]) @ inv
        p1 = np.array([f.xc[b], f.yc[b]]) @ inv
        total += np.hypot(*(p1 - p0))
    ref = 0.0
    for k in range(-40, 40):
        line = shapely.LineString(np.array([[-50, k * 0.5], [50, k * 0.5]]) @ inv)
        ref += line.intersection(poly).length
    assert total == pytest.approx(ref, rel=1e-9)


def test_layer_paths_order_and_formalism():
    s = slicelab.section(nested_shells(), (0, 0, 20), (0, 0, 1))
    lp = layer_paths(s, PrintSettings(pixel_size=0.1))
    first = layer_paths(s, PrintSettings(pixel_size=0.1, external_perimeters_first=True))
    # Two islands (the outer wall with its cavity, the cube in the cavity): each prints its
    # perimeters, then its gap fill and filling. By default the innermost perimeter goes first and
    # the outer one last; with external_first, the outer one (and the cavity's wall) first.
    walls = ("internal", "hole", "external")
    for paths, outer_first in ((lp, False), (first, True)):
        assert len(paths.external_contour_segments) == 2
        kinds = paths.kinds()
        starts = [i for i, k in enumerate(kinds) if k in walls and (i == 0 or kinds[i - 1] not in walls)]
        assert len(starts) == 2, kinds
        for start, stop in zip(starts, starts[1:] + [len(kinds)]):
            block = kinds[start:stop]
            n = sum(k in walls for k in block)
            assert all(k in walls for k in block[:n]) and not any(k in walls for k in block[n:])
            assert block[0 if outer_first else n - 1] == "external", block
        assert "hole" in kinds  # the cavity's wall: an outer wall of its own kind
    for q in lp.external_contour_segments + lp.internal_contour_segments:
        np.testing.assert_array_equal(q[0], q[-1])
    # Travel is exactly the gaps between consecutive paths.
    items = list(lp.ordered())
    travel = sum(np.hypot(*(b[0] - a[-1])) for (_, a, _), (_, b, _) in zip(items, items[1:]))
    assert lp.travel_length == pytest.approx(travel)
    # Seams and nearest-first ordering beat printing the same paths in a fixed order.
    naive = sum(np.hypot(*(b[0] - a[-1])) for a, b in zip(
        lp.filling_segments[::-1], lp.filling_segments[::-1][1:]))
    assert lp.travel_length <= naive + sum(np.hypot(*(q[0] - q[-1])) for q in lp.filling_segments)


def test_overlapping_cubes_one_island_under_nonzero(data_dir):
    s = slicelab.section(slicelab.load(data_dir / "overlapping_cubes.stl"), (0, 0, 10), (0, 0, 1))
    nz = layer_paths(s, PrintSettings(pixel_size=0.1))
    eo = layer_paths(s, PrintSettings(pixel_size=0.1, rule="evenodd"))
    assert len(nz.external_contour_segments) == 1 and len(nz.internal_contour_segments) == 1
    assert not any(k == "gap_fill" for k, _ in nz.sequence)
    # Even-odd: the overlap is a hole, and the two L-shaped rests touch only at two corners,
    # so erosion parts them into two islands.
    assert len(eo.external_contour_segments) == 2 and len(eo.internal_contour_segments) == 2
    # The outer perimeter is the exact offset of the union: the buried edges do not count.
    ext = shapely.Polygon(nz.external_contour_segments[0])
    ref = shapely.box(0, 0, 20, 20).union(shapely.box(10, 10, 30, 30)).buffer(-0.2, quad_segs=64)
    assert ext.area == pytest.approx(ref.area, rel=1e-4)
    assert shapely.hausdorff_distance(ext.boundary, ref.boundary, densify=0.01) < 0.01


def test_solid_mask_region_is_filled_solid_at_its_own_angle():
    loops = [rect(0, 0, 20, 20) + 0.013]
    p = 0.1
    mask = np.zeros((300, 150), bool)
    mask[:, :] = True  # x in [-2, 13) : the left part
    solid = GridMask(mask, -50, -20, p)
    lp = layer_paths(section_of(loops), PrintSettings(pixel_size=p), LayerInputs(solid=solid, solid_angle=0.0))
    kinds = np.array(lp.filling_kinds)
    assert {"solid", "sparse"} <= set(kinds)
    sol = [q for q, k in zip(lp.filling_segments, kinds) if k == "solid"]
    pts = np.concatenate(sol)
    assert pts[:, 0].max() <= 13 * 1.0 - 0.05 + 1e-6 + 0.2  # stays in the mask (up to its edge)
    ys = np.unique(np.round(np.concatenate([q[np.abs(np.diff(q[:, 1], append=np.nan)) < 1e-9][:, 1]
                                            for q in sol]), 9))
    assert np.allclose(np.diff(ys), 0.4)  # horizontal lines, one line width apart
    sparse_pts = np.concatenate([q for q, k in zip(lp.filling_segments, kinds) if k == "sparse"])
    assert sparse_pts[:, 0].min() >= 13 - 0.05 - 1e-6


def test_empty_section_gives_empty_paths():
    lp = layer_paths(section_of([rect(0, 0, 0.1, 0.1)]), PrintSettings(pixel_size=0.05))
    assert lp.filling_segments == [] and lp.external_contour_segments == []
    with pytest.raises(ValueError, match="density"):
        layer_paths(section_of([rect(0, 0, 1, 1)]), PrintSettings(infill_density=1.5))


def test_rectilinear_leaves_out_stubs_at_corners():
    # Lines at 45 degrees across a square graze its corners: pieces shorter than a quarter of
    # the spacing would be stubs of a few hundredths of a millimetre; none is laid, and the
    # rest of the square is still filled.
    from slicelab.geometry.polygons import Polygon
    from slicelab.printing.fill.lines import rectilinear
    # The lower left corner lies 0.03 mm off a line: without the rule, a 0.054 mm stub.
    sq = Polygon(np.array([[0, 0], [8, 0], [8, 8], [0, 8]], float) + [0.013, 0.055], (), 0)
    spacing = 0.4

    def pieces(**kw):  # the lengths of the line pieces (segments along the lines' direction)
        along = []
        for q in rectilinear([sq], spacing, 45.0, **kw):
            d = np.diff(q, axis=0)
            length = np.hypot(*d.T)
            diagonal = (length > 1e-9) & (np.abs(np.abs(d[:, 0]) - np.abs(d[:, 1])) < 1e-6 * length)
            along.append(length[diagonal & (np.sign(d[:, 0]) == np.sign(d[:, 1]))])
        return np.concatenate(along)

    assert pieces(min_length=0.0).min() < 0.06
    kept = pieces()
    assert kept.min() >= 0.25 * spacing
    assert abs(kept.sum() * spacing - 64.0) < 0.02 * 64.0


def test_rectilinear_links_lines_along_the_boundary_into_zigzags():
    # A 10 mm square at 1 mm spacing: its ten lines linked by nine 1 mm steps along the boundary,
    # one zigzag of 109 mm; links longer than max_link are not taken.
    from slicelab.printing.fill.lines import rectilinear
    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float) + 0.25
    one = rectilinear([Polygon(square, (), 0)], 1.0, 0.0)
    assert len(one) == 1 and len(one[0]) == 20
    assert float(np.hypot(*np.diff(one[0], axis=0).T).sum()) == pytest.approx(109.0, abs=1e-9)
    apart = rectilinear([Polygon(square, (), 0)], 1.0, 0.0, max_link=0.5)
    assert len(apart) == 10 and all(len(p) == 2 for p in apart)
    # A square hole: the four lines through it are cut in two; 14 pieces (84 mm) in zigzags whose
    # links are 1 mm steps along the outer boundary or the hole's.
    hole = np.array([[3, 3], [3, 7], [7, 7], [7, 3]], float) + 0.25
    paths = rectilinear([Polygon(square, (hole,), 0)], 1.0, 0.0)
    pieces = sum(len(p) for p in paths) // 2
    links = pieces - len(paths)
    total = sum(float(np.hypot(*np.diff(p, axis=0).T).sum()) for p in paths)
    assert pieces == 14 and total == pytest.approx(84.0 + links * 1.0, abs=1e-9)
