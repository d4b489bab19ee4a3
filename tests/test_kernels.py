"""The compiled kernels against independent oracles: marching squares, halos, nearest segments, simplification."""
from __future__ import annotations

import numpy as np
import pytest

from slicelab.geometry import contours
from slicelab.geometry.blocks import EMPTY, FULL, BlockGrid
from slicelab.geometry.march_kernels import closed_cycles
from slicelab.geometry.segment_kernels import douglas_peucker
from slicelab.geometry.spatial import SegmentIndex
from slicelab.printing.steps.simplify import simplify_paths


def _field(seed: int, shape=(48, 56)) -> np.ndarray:
    rng = np.random.default_rng(seed)
    v = rng.normal(size=shape).cumsum(0).cumsum(1) * 0.02 + rng.normal(size=shape)
    return v.astype(np.float32)


@pytest.mark.parametrize("seed, b", [(0, 8), (1, 8), (2, 8), (3, 70)])
def test_march_blocks_gives_the_contours_of_the_whole_array(seed, b):
    # Every block active: the blocks' contours, chained across seams, are skimage's contours
    # of the assembled array (closed ones), point for point. Blocks of 70 pixels take two
    # 64-bit words a row in the kernel.
    from skimage.measure import find_contours
    v = _field(seed, (6 * b, 7 * b))
    level = float(np.median(v))
    v[0, :] = v[-1, :] = v[:, 0] = v[:, -1] = level - 10  # every contour closes inside
    g = BlockGrid(b, 2, -3, np.arange(6 * 7).reshape(6, 7))
    data = np.stack([v[i * b:(i + 1) * b, j * b:(j + 1) * b] for i in range(6) for j in range(7)])
    ours = contours.march_blocks(data, level, g, level - 10, level + 10)
    theirs = [c[:-1] for c in find_contours(v.astype(np.float64), level, fully_connected="high")]
    assert len(ours) == len(theirs) > 20
    origin = np.array([2 * b, -3 * b])
    key = lambda r: tuple(np.round(np.sort(r, axis=0)[0], 9))  # noqa: E731
    for a, t in zip(sorted(ours, key=key), sorted((c + origin for c in theirs), key=key)):
        assert len(a) == len(t)
        assert {tuple(x) for x in np.round(a, 6)} == {tuple(x) for x in np.round(t, 6)}


def test_march_blocks_with_uniform_blocks_matches_the_assembled_grid():
    # A ring-shaped band of active blocks between an empty outside and a full inside.
    b = 8
    yy, xx = np.mgrid[0:64, 0:64]
    v = (20.0 - np.hypot(yy - 31.5, xx - 31.5)).astype(np.float32)  # distance to a circle of radius 20
    table = np.full((8, 8), EMPTY)
    full = np.zeros((8, 8), bool)
    blocks = v.reshape(8, b, 8, b).transpose(0, 2, 1, 3)
    lo, hi = blocks.min(axis=(2, 3)), blocks.max(axis=(2, 3))
    active = (lo < 2.5) & (hi > -1.5)
    full[(lo >= 2.5)] = True
    table[full] = FULL
    table[active] = np.arange(active.sum())
    g = BlockGrid(b, 0, 0, table)
    for level in (0.0, 0.5, 1.25):
        ours = contours.march_blocks(blocks[active], level, g, -2.0, 3.0)
        ref = contours.march(g.assemble(blocks[active], np.float32(-2), np.float32(3), 0, 0, (64, 64)), level)
        assert len(ours) == len(ref) == 1
        assert np.array_equal(ours[0], ref[0])
        # The ring is the circle of radius 20 - level, within the interpolation's error.
        r = np.hypot(ours[0][:, 0] - 31.5, ours[0][:, 1] - 31.5)
        assert np.abs(r - (20 - level)).max() < 0.05


@pytest.mark.parametrize("seed", range(4))
def test_a_masks_contours_on_its_seamed_blocks_are_those_of_the_assembled_mask(seed):
    # Random block tables whose full and empty blocks touch (edge to edge and at corners) with
    # active blocks among them: marched on the few blocks `seamed` holds (full ones beside empty ones), the mask's contours are
    # those of the whole assembled mask, ring for ring and point for point (and those `widen` gives).
    b = 4
    rng = np.random.default_rng(seed)
    status = rng.integers(0, 3, (9, 11))  # 0 empty, 1 full, 2 active
    table = np.where(status == 0, EMPTY, FULL)
    table[status == 2] = np.arange(np.count_nonzero(status == 2))
    g = BlockGrid(b, -2, 3, table)
    bits = rng.random((np.count_nonzero(status == 2), b, b)) < 0.5
    seamed, sb = g.seamed(bits, False, True)
    wide, wb = g.widen(bits, False, True)
    assert len(sb) < len(wb)
    shape = ((table.shape[0] + 2) * b, (table.shape[1] + 2) * b)
    whole = g.assemble(bits.view(np.uint8), np.uint8(0), np.uint8(1), (g.row0 - 1) * b, (g.col0 - 1) * b, shape)
    ref = contours.march(whole.astype(np.float32), 0.5)
    origin = np.array([(g.row0 - 1) * b, (g.col0 - 1) * b])
    ours = contours.march_blocks(sb.astype(np.float32), 0.5, seamed, 0.0, 1.0)
    assert len(ours) == len(ref) > 10
    first = lambda r: (r[0, 0], r[0, 1])  # noqa: E731  (each ring starts at its lowest point)
    for a, r in zip(sorted(ours, key=first), sorted((r + origin for r in ref), key=first), strict=True):
        np.testing.assert_array_equal(a, r)
    for a, w in zip(ours, contours.march_blocks(wb.astype(np.float32), 0.5, wide, 0.0, 1.0), strict=True):
        np.testing.assert_array_equal(a, w)


def test_closed_cycles_drops_open_chains_and_orders_rings_by_lowest_point():
    # Two cycles (keys 0->1->2->0 and 10->11->10) and an open chain 20->21->22.
    start = np.array([21, 1, 10, 2, 0, 11, 20])
    end = np.array([22, 2, 11, 0, 1, 10, 21])
    pts = np.array([[9, 9], [5, 1], [0, 7], [5, 2], [4, 3], [1, 0], [9, 8]], float)
    ring_points, bounds = closed_cycles(start, end, pts)
    rings = [ring_points[bounds[i]:bounds[i + 1]].tolist() for i in range(len(bounds) - 1)]
    assert rings == [[[0, 7], [1, 0]], [[4, 3], [5, 1], [5, 2]]]


def test_fill_blocks_halo_is_the_neighbours_pixels():
    # pack() on a grid with empty and full neighbours, checked pixel by pixel against the
    # assembled grid read around each block.
    rng = np.random.default_rng(3)
    b, h = 4, 6  # the halo reaches two blocks away
    table = np.array([[0, FULL, 1], [EMPTY, 2, 3], [4, FULL, EMPTY]])
    g = BlockGrid(b, -1, 2, table)
    data = rng.integers(0, 200, size=(5, b, b)).astype(np.uint8)
    packed = g.pack(data, h, np.uint8(250), np.uint8(251))
    big = g.assemble(data, np.uint8(250), np.uint8(251), (g.row0 - 3) * b, (g.col0 - 3) * b, (9 * b, 9 * b))
    rows0, cols0 = g.origins()
    for k in range(5):
        r, c = rows0[k] - (g.row0 - 3) * b - h, cols0[k] - (g.col0 - 3) * b - h
        assert np.array_equal(packed[k], big[r:r + b + 2 * h, c:c + b + 2 * h])


def test_nearest_matches_brute_force():
    rng = np.random.default_rng(4)
    seg = rng.uniform(0, 20, size=(300, 2, 2))
    q = rng.uniform(-2, 22, size=(2000, 2))
    a, d = seg[:, 0], seg[:, 1] - seg[:, 0]
    w = q[:, None] - a[None]
    t = np.clip((w * d[None]).sum(-1) / (d * d).sum(-1)[None], 0, 1)
    dist = np.hypot(*(w - t[..., None] * d[None]).transpose(2, 0, 1))
    exact = dist.min(axis=1)
    idx = SegmentIndex(seg, 1.0)
    for reach in (0.5, 1.0, 2.5):  # the buckets are shared between reaches; answers are not
        got, s, tt = idx.nearest(q, reach=reach)
        np.testing.assert_allclose(got, exact, atol=1e-12)
        np.testing.assert_allclose(dist[np.arange(len(q)), s], exact, atol=1e-12)


def test_douglas_peucker_keeps_every_dropped_vertex_within_tolerance():
    rng = np.random.default_rng(5)
    path = np.cumsum(rng.normal(size=(3000, 2)) * 0.05, axis=0)
    keep = np.zeros(len(path), bool)
    keep[[0, 999, 1000, 2999]] = True  # two polylines, 0..999 and 1000..2999
    tol = 0.05
    out = douglas_peucker(path, keep, tol)
    assert out[keep].all() and 20 < out.sum() < 2500
    kept = np.flatnonzero(out)
    for a, b in zip(kept[:-1], kept[1:]):
        if a == 999:
            continue
        p, s, e = path[a + 1:b], path[a], path[b]
        d = e - s
        t = np.clip(((p - s) @ d) / max(d @ d, 1e-300), 0, 1)
        assert np.hypot(*(p - s - t[:, None] * d).T).max(initial=0) <= tol + 1e-12
    # and simplify_paths keeps the ends of each path
    simple = simplify_paths([path[:1000], path[1000:]], tol)
    assert np.array_equal(simple[0][[0, -1]], path[[0, 999]]) and np.array_equal(simple[1][[0, -1]], path[[1000, 2999]])


def _star(n=7, r0=6.0, r1=2.5, centre=(0.013, -0.021)):
    t = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    r = np.where(np.arange(2 * n) % 2 == 0, r0, r1)
    return np.c_[centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)]


def test_distance_field_is_the_brute_force_distance_on_every_material_pixel():
    # Every material pixel held: the distance from its centre to the nearest boundary segment
    # (all segments, numpy), capped at the field's depth; outside pixels at -p/2.
    from types import SimpleNamespace
    from slicelab.printing.grid.distance import distance_field
    from slicelab.printing.grid.raster import rasterize
    hole = _star(5, 1.5, 0.8)[::-1]
    p = 0.1
    r = rasterize(SimpleNamespace(loops=[_star(), hole]), p, band=1.5)
    (tile,), (segs,) = r.tiles, r.segments
    f = distance_field(tile, SegmentIndex(segs, 2 * p, join=True), [0.2, 0.6], depth=0.94)
    rows0, cols0 = tile.blocks.origins()
    k, i, j = np.nonzero(np.ones(f.blocks.shape, bool))
    q = np.c_[(cols0[k] + j) * p, (rows0[k] + i) * p]
    loops = [_star(), hole]
    edges = np.concatenate([np.stack([lp, np.roll(lp, -1, axis=0)], 1) for lp in loops])
    a, d = edges[:, 0], edges[:, 1] - edges[:, 0]
    w = q[:, None] - a[None]
    t = np.clip((w * d[None]).sum(-1) / (d * d).sum(-1)[None], 0, 1)
    exact = np.hypot(*(w - t[..., None] * d[None]).transpose(2, 0, 1)).min(axis=1)
    inside = tile.bits[k, i, j]
    got = f.blocks[k, i, j]
    np.testing.assert_allclose(got[inside], np.minimum(exact[inside], f.deep), atol=1e-5)
    assert (got[~inside] == np.float32(-p / 2)).all()
    assert f.refined == int(np.count_nonzero(exact[inside] < f.deep)) > 1000


def test_cut_at_crossings_cuts_each_piece_where_edges_cross_it():
    from slicelab.geometry.segment_kernels import cut_at_crossings
    shapely = pytest.importorskip("shapely")
    rng = np.random.default_rng(3)
    pieces = rng.uniform(0, 10, (40, 2, 2))
    edges = rng.uniform(0, 10, (25, 2, 2))
    parts = cut_at_crossings(pieces, edges)
    fence = shapely.MultiLineString([e for e in edges])
    at = 0
    for pc in pieces:  # each piece comes back as consecutive parts from its start to its end
        line = shapely.LineString(pc)
        crossings = line.intersection(fence)
        n_cross = len(shapely.get_parts(crossings)) if not crossings.is_empty else 0
        mine = parts[at:at + n_cross + 1]
        at += n_cross + 1
        np.testing.assert_allclose(mine[0, 0], pc[0])
        np.testing.assert_allclose(mine[-1, 1], pc[1])
        np.testing.assert_allclose(mine[1:, 0], mine[:-1, 1])
        # Every cut lies on an edge, and the lengths add up.
        for x in mine[1:, 0]:
            assert fence.distance(shapely.Point(x)) < 1e-9
        assert abs(np.hypot(*(mine[:, 1] - mine[:, 0]).T).sum() - line.length) < 1e-9
    assert at == len(parts) > len(pieces)


def test_simplify_chains_keeps_every_vertex_within_tolerance_and_runs_apart():
    from slicelab.geometry.spatial import simplify_chains
    shapely = pytest.importorskip("shapely")
    rng = np.random.default_rng(5)
    t = np.linspace(0, 2 * np.pi, 400)
    wavy = np.c_[t, 0.3 * np.sin(3 * t) + rng.normal(0, 0.002, len(t))]
    circle = np.c_[20 + 5 * np.cos(t), 5 * np.sin(t)]
    circle[-1] = circle[0]  # a closed run
    runs = [wavy[:200], wavy[210:], circle]  # the gap between the first two is not a segment
    seg = np.concatenate([np.stack([r[:-1], r[1:]], 1) for r in runs])
    out = simplify_chains(seg, 0.01)
    assert len(out) < len(seg) / 3
    for r in runs:  # each run's vertices lie within the tolerance of the simplified segments
        lines = shapely.MultiLineString([s for s in out])
        assert shapely.distance(lines, shapely.points(r)).max() <= 0.01 + 1e-12
    # Every output segment joins two vertices of one run, and the runs' ends stay.
    owner = {tuple(v): k for k, r in enumerate(runs) for v in r}
    assert all(owner[tuple(a)] == owner[tuple(b)] for a, b in out)
    ends = {tuple(x) for s in out for x in s}
    assert all(tuple(r[0]) in ends and tuple(r[-1]) in ends for r in runs)


def test_march_cells_asks_for_more_room_rather_than_losing_segments():
    from slicelab.geometry.march_kernels import march_cells
    b = 8
    v = _field(4)
    g = BlockGrid(b, 0, 0, np.arange(6 * 7).reshape(6, 7))
    data = np.stack([v[i * b:(i + 1) * b, j * b:(j + 1) * b] for i in range(6) for j in range(7)])
    rows0, cols0 = g.origins()
    args = (data, float(np.median(v)), g.neighbours, rows0, cols0, -1, -1, 7 * b + 3)
    uniform = (np.float32(-9), np.float32(9))
    start, end, points, complete = march_cells(*args, 100000, *uniform)
    assert complete and len(start) > 100
    few = march_cells(*args, len(start) // 2, *uniform)
    assert not few[3] and len(few[0]) == 0
    # The contours through the public entry point are the same whatever room it starts with.
    assert sum(len(r) for r in contours.march_blocks(data, float(np.median(v)), g, -9.0, 9.0)) <= len(start)


@pytest.mark.parametrize("seed", [0, 1])
def test_winding_blocks_is_the_brute_force_winding_number_on_every_held_pixel(seed):
    # Overlapping star-shaped loops, some clockwise, against the winding number summed from each
    # loop's turning angle around every pixel centre (no crossing rule involved).
    from slicelab.printing.grid.raster import winding_blocks
    rng = np.random.default_rng(seed)
    loops = []
    for k in range(4):
        t = np.sort(rng.uniform(0, 2 * np.pi, 40))
        r = rng.uniform(2, 6, 40)
        ring = np.stack([r * np.cos(t), r * np.sin(t)], 1) + rng.uniform(-3, 3, 2)
        loops.append(ring if k % 3 else ring[::-1])
    b, p = 8, 0.25
    table = np.full((6, 7), EMPTY)
    held = rng.random(table.shape) < 0.6
    table[held] = np.arange(held.sum())
    g = BlockGrid(b, -3, -4, table)
    edges = np.concatenate([np.stack([q, np.roll(q, -1, axis=0)], 1) for q in loops])  # oriented
    numbers = winding_blocks(edges, g, p)
    rows, cols = g.origins()
    rr, cc = np.meshgrid(np.arange(b), np.arange(b), indexing="ij")
    centres = np.stack([(cols[:, None, None] + cc) * p, (rows[:, None, None] + rr) * p], -1).reshape(-1, 2)
    turn = np.zeros(len(centres))
    for ring in loops:
        a = ring[None] - centres[:, None]
        ang = np.arctan2(a[..., 1], a[..., 0])
        turn += np.angle(np.exp(1j * (np.roll(ang, -1, axis=1) - ang))).sum(axis=1)
    expected = np.rint(turn / (2 * np.pi)).astype(int).reshape(numbers.shape)
    assert np.abs(expected).max() >= 2 and (expected < 0).any()  # overlaps of both orientations
    assert np.array_equal(numbers, expected)
    for rule, bits in (("nonzero", expected != 0), ("evenodd", expected % 2 == 1)):
        got, some = winding_blocks(edges, g, p, rule=rule)
        assert np.array_equal(got, bits)
        assert np.array_equal(some, bits.any(axis=(1, 2)))


def _loop_edges(loops):
    edges = np.concatenate([np.stack([lp, np.roll(lp, -1, axis=0)], 1) for lp in loops]).astype(np.float64)
    return edges, np.r_[0, np.cumsum([len(lp) for lp in loops])]


def test_loops_touch_against_shapely():
    # Whether a layer's loops meet anywhere (crossing, touching, overlapping in line) against
    # GEOS: closed lines are simple together only if no two meet.
    shapely = pytest.importorskip("shapely")
    from slicelab.geometry.segment_kernels import loops_touch
    sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    cases = {
        "apart": [sq, sq + 3],
        "nested": [sq * 3, sq[::-1] + 1],
        "crossing": [sq, sq + 1],
        "corner on corner": [sq, sq + 2],
        "shared edge": [sq, sq + (2, 0)],
        "vertex on an edge": [sq, np.array([[2, 1], [4, 0], [4, 2]], float)],
        "folded back": [np.array([[0, 0], [2, 0], [1, 0], [1, 1]], float)],
    }
    rng = np.random.default_rng(3)
    for k in range(40):  # random star-shaped loops, some meeting
        t = np.sort(rng.uniform(0, 2 * np.pi, 12))
        loops = [np.c_[np.cos(t), np.sin(t)] * rng.uniform(0.5, 2, (12, 1)) + rng.uniform(-2, 2, 2)
                 for _ in range(rng.integers(1, 4))]
        cases[f"random {k}"] = loops
    seen = set()
    for name, loops in cases.items():
        edges, bounds = _loop_edges(loops)
        want = not shapely.MultiLineString([np.vstack([lp, lp[:1]]) for lp in loops]).is_simple
        assert loops_touch(edges, bounds) == want, name
        seen.add(want)
    assert seen == {True, False}


def test_blocks_near_marks_the_blocks_each_piece_box_meets():
    """The compiled marking against the definition written out with numpy: each segment cut into
    pieces no longer than a block (`split_segments`), each piece's pixel box widened by the reach,
    every block that box meets marked; random segments, pixel sizes, blocks, reaches and ranges
    (negative coordinates included)."""
    from slicelab.geometry.blocks import blocks_near
    from slicelab.geometry.spatial import split_segments
    rng = np.random.default_rng(7)
    for _ in range(300):
        segs = rng.uniform(-50, 50, (int(rng.integers(0, 40)), 2, 2)) * rng.choice([0.01, 0.3, 1, 3])
        p, size, reach = float(rng.choice([0.05, 0.2, 0.25])), int(rng.choice([4, 16, 32])), int(rng.integers(0, 9))
        r0, c0 = int(rng.integers(-60, 0)), int(rng.integers(-60, 0))
        rows, cols = (r0, r0 + int(rng.integers(0, 60))), (c0, c0 + int(rng.integers(0, 60)))
        want = np.zeros((rows[1] - rows[0] + 1, cols[1] - cols[0] + 1), bool)
        if len(segs):
            pieces, _ = split_segments(segs, size * p)
            lo = np.floor(pieces.min(axis=1) / p).astype(np.int64) - reach
            hi = np.ceil(pieces.max(axis=1) / p).astype(np.int64) + reach
            for (x0, y0), (x1, y1) in zip(lo, hi):  # over pieces: the oracle may be slow
                want[max(y0 // size - rows[0], 0):max(y1 // size - rows[0] + 1, 0),
                     max(x0 // size - cols[0], 0):max(x1 // size - cols[0] + 1, 0)] = True
        np.testing.assert_array_equal(blocks_near(segs, p, size, reach, rows, cols), want)


def test_row_crossings_against_each_edge_and_row_walked_in_python():
    """Every (edge, pixel-centre row) crossing, its x and winding step, against a plain Python walk
    of each edge's rows (half-open in y, so a row through a shared vertex counts once)."""
    import math

    from slicelab.geometry.segment_kernels import row_crossings
    rng = np.random.default_rng(11)
    for _ in range(200):
        e = np.round(rng.uniform(-20, 20, (int(rng.integers(1, 30)), 2, 2)), int(rng.integers(0, 3)))
        p, first = float(rng.choice([0.1, 0.2, 0.5])), int(rng.integers(-150, 0))
        stop = first + int(rng.integers(0, 300))
        want = []
        for (x0, y0), (x1, y1) in e:  # over edges: the oracle may be slow
            for r in range(max(math.ceil(min(y0, y1) / p), first), min(math.ceil(max(y0, y1) / p), stop)):
                y = r * p
                want.append((r, x0 + (y - y0) / (y1 - y0) * (x1 - x0), -1 if y1 > y0 else 1))
        rows, x, step = row_crossings(e, p, first, stop)
        assert rows.tolist() == [w[0] for w in want] and step.tolist() == [w[2] for w in want]
        np.testing.assert_allclose(x, [w[1] for w in want], rtol=0, atol=1e-9)


def test_bucket_boxes_lists_each_box_in_every_bucket_it_meets():
    """Each square bucket lists, in increasing order, exactly the boxes that meet it once widened
    by a cell (brute force over buckets and boxes); over a limit nothing is listed."""
    from slicelab.geometry.segment_kernels import bucket_boxes
    rng = np.random.default_rng(9)
    for _ in range(100):
        n, cell = int(rng.integers(1, 25)), float(rng.choice([0.5, 1.0, 2.5]))
        lo = rng.uniform(-10, 10, (n, 2))
        hi = lo + rng.uniform(0, 4, (n, 2))
        origin, width, height, start, owner, fits = bucket_boxes(lo, hi, cell, -1)
        assert fits and start[-1] == len(owner)
        for r in range(height):  # over buckets: the oracle may be slow
            for c in range(width):
                b_lo = cell * (origin + [c, r])
                meets = np.all((lo - cell < b_lo + cell) & (hi + cell >= b_lo), axis=1)
                q = r * width + c
                assert owner[start[q]:start[q + 1]].tolist() == np.flatnonzero(meets).tolist()
        assert not bucket_boxes(lo, hi, cell, len(owner) - 1)[5]


@pytest.mark.parametrize("b", [3, 8])  # 9 pixels a block: byte by byte; 64: eight pixels a word
def test_combine_blocks_is_the_set_operation_of_the_whole_masks(b):
    from slicelab.geometry.kernels import combine_blocks
    rng = np.random.default_rng(b)
    bb = b * b

    def random_mask(shape):
        kind = rng.choice([-1, -2, 0], size=shape, p=[0.3, 0.2, 0.5])
        table = np.full(shape, -1, np.int64)
        held = np.flatnonzero(kind.ravel() == 0)
        table.ravel()[held] = np.arange(len(held))
        table[kind == -2] = -2
        bits = (rng.random((len(held), bb)) < rng.choice([0.0, 0.5, 1.0], size=(len(held), 1))).astype(np.uint8)
        return table, bits

    def whole(table, bits, r, c, r0, c0, nr, nc):  # the mask's blocks on world blocks r0.., c0..
        out = np.zeros((nr, nc, bb), np.uint8)
        for i in range(nr):
            for j in range(nc):
                ti, tj = r0 + i - r, c0 + j - c
                if 0 <= ti < table.shape[0] and 0 <= tj < table.shape[1]:
                    s = table[ti, tj]
                    out[i, j] = 1 if s == -2 else (0 if s == -1 else bits[s])
        return out

    for _ in range(20):
        ta, bits_a = random_mask((5, 6))
        tb, bits_b = random_mask((4, 7))
        ra, ca, rb, cb = 2, -1, 3, 0
        for op, f in ((0, np.bitwise_and), (1, lambda x, y: x & (1 - y)), (2, np.bitwise_or)):
            r0, c0, nr, nc = 1, -2, 8, 10
            table, bits = combine_blocks(op, bb, ta, ra, ca, bits_a.ravel(), tb, rb, cb, bits_b.ravel(), r0, c0,
                                         nr, nc)
            expected = f(whole(ta, bits_a, ra, ca, r0, c0, nr, nc), whole(tb, bits_b, rb, cb, r0, c0, nr, nc))
            got = whole(table, bits.reshape(-1, bb), r0, c0, r0, c0, nr, nc)
            np.testing.assert_array_equal(got, expected)
            # Canonical: all-clear blocks empty, all-set full, the held ones in row-major order.
            held = table[table >= 0]
            np.testing.assert_array_equal(held, np.arange(len(held)))
            sums = bits.reshape(-1, bb).sum(axis=1)
            assert np.all((sums > 0) & (sums < bb))


@pytest.mark.parametrize("seed", range(4))
def test_ring_hierarchy_matches_the_even_odd_test_ring_by_ring(seed):
    # Nested and disjoint rings (circles of distinct radii, some clockwise): each ring's depth is
    # the number of larger rings holding its first vertex (numpy's even-odd test, ring by ring),
    # and its parent the smallest of them.
    from slicelab.geometry.polygons import loop_hierarchy, points_in_ring, signed_area
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    loops = []
    for _ in range(int(rng.integers(2, 30))):
        c, r = rng.uniform(-20, 20, 2), rng.uniform(0.5, 15)
        ring = c + r * np.c_[np.cos(t), np.sin(t)]
        loops.append(ring[::-1] if rng.random() < 0.5 else ring)
    areas = np.array([abs(signed_area(q)) for q in loops])
    depth, parent = loop_hierarchy(loops)
    for c in range(len(loops)):
        holders = [a for a in range(len(loops)) if a != c and areas[a] >= areas[c]
                   and points_in_ring(loops[c][:1], loops[a])[0]]
        assert depth[c] == len(holders)
        assert parent[c] == (min(holders, key=lambda a: areas[a]) if holders else -1)


def _walked_chains(skel):
    """The skeleton's chains walked pixel by pixel in Python: the oracle of the compiled walk."""
    from slicelab.geometry.contours import skeleton_neighbours
    pts, nbr = skeleton_neighbours(skel)
    deg = (nbr >= 0).sum(axis=1).tolist()
    nbr = nbr.tolist()
    junction = [d >= 3 for d in deg]
    seen = list(junction)
    chains = []

    def walk(start):
        path, prev, cur = [start], -1, start
        seen[start] = True
        while True:
            nxt = [j for j in nbr[cur] if j >= 0 and j != prev and not seen[j]]
            if not nxt:
                return path
            prev, cur = cur, nxt[0]
            seen[cur] = True
            path.append(cur)

    for s in sorted(range(len(pts)), key=lambda i: deg[i] != 1):
        if seen[s]:
            continue
        path = walk(s)
        if deg[s] != 1:
            path = walk(s)[1:][::-1] + path
            if deg[s] == 2 and len(path) > 2 and path[0] in nbr[path[-1]]:
                path.append(path[0])
        ends = [j for j in nbr[path[0]] if j >= 0 and junction[j]][:1], \
            [j for j in nbr[path[-1]] if j >= 0 and junction[j]][:1]
        path = ends[0] + path + ends[1]
        if len(path) >= 2:
            chains.append(pts[path])
    return chains


def test_skeleton_chains_walk_lines_cycles_and_junctions():
    from slicelab.geometry.contours import trace_skeleton
    from slicelab.geometry.graphs import thin
    line = np.zeros((3, 9), bool)
    line[1, 1:8] = True
    (chain,) = trace_skeleton(line)
    assert sorted(map(tuple, chain)) == [(1, c) for c in range(1, 8)] and abs(int(chain[0, 1]) - int(chain[-1, 1])) == 6
    plus = np.zeros((9, 9), bool)
    plus[4, 1:8] = plus[1:8, 4] = True
    chains = trace_skeleton(plus)
    assert len(chains) == 4 and all(len(c) == 4 and (4, 4) in map(tuple, c[[0, -1]]) for c in chains)
    ring = np.zeros((12, 12), np.uint8)
    import cv2
    cv2.circle(ring, (6, 6), 4, 1, 1)
    (cycle,) = trace_skeleton(thin(ring.astype(bool)))
    assert np.array_equal(cycle[0], cycle[-1]) and len(cycle) > 10
    rng = np.random.default_rng(7)
    for trial in range(40):  # thinned random blobs: branches, junction clusters, cycles
        img = np.zeros((60, 80), np.uint8)
        for _ in range(rng.integers(1, 6)):
            cv2.line(img, tuple(int(v) for v in rng.integers(0, 80, 2)), tuple(int(v) for v in rng.integers(0, 60, 2)),
                     1, int(rng.integers(1, 7)))
        skel = thin(img.astype(bool))
        ours, theirs = trace_skeleton(skel), _walked_chains(skel)
        assert len(ours) == len(theirs)
        for a, b in zip(ours, theirs):
            np.testing.assert_array_equal(a, b)
