"""Connected components of graphs and thinning: against SciPy and OpenCV, and the skeleton's topology."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from slicelab.geometry.graphs import GUO_HALL, graph_components, thin, thinning_table

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("seed", range(6))
def test_components_are_scipys(seed):
    # The same count and the same labels (numbered by lowest node), isolated nodes, repeated edges
    # and loops included.
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 400))
    m = int(rng.integers(0, 2 * n))
    a, b = rng.integers(0, n, m), rng.integers(0, n, m)
    count, labels = graph_components(n, a, b)
    theirs = connected_components(coo_matrix((np.ones(m), (a, b)), shape=(n, n)), directed=False)
    assert count == theirs[0]
    assert labels.tolist() == theirs[1].tolist()


def test_components_of_a_long_path_and_no_edges():
    n = 100_000
    order = np.random.default_rng(0).permutation(n)  # one path visiting the nodes in a random order
    count, labels = graph_components(n, order[:-1], order[1:])
    assert count == 1 and not labels.any()
    count, labels = graph_components(3, [], [])
    assert count == 3 and labels.tolist() == [0, 1, 2]


def test_components_refuse_edges_outside_the_nodes():
    with pytest.raises(ValueError, match="outside 0..2"):
        graph_components(3, [0, 3], [1, 1])
    with pytest.raises(ValueError, match="outside"):
        graph_components(3, [-1], [1])
    with pytest.raises(ValueError, match="two ends"):
        graph_components(3, [0, 1], [1])


def _shapes(seed: int, count: int):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        h, w = (int(x) for x in rng.integers(8, 70, 2))
        img = np.zeros((h, w), np.uint8)
        for _ in range(int(rng.integers(1, 6))):
            if rng.random() < 0.4:
                centre = tuple(int(x) for x in rng.integers(0, (w, h)))
                cv2.circle(img, centre, int(rng.integers(1, 14)), 1, -1)
                if rng.random() < 0.5:  # a hole in it
                    cv2.circle(img, centre, int(rng.integers(0, 5)), 0, -1)
            else:
                p, q = (tuple(int(x) for x in rng.integers(0, (w, h))) for _ in range(2))
                cv2.line(img, p, q, 1, int(rng.integers(1, 7)))
        yield img.astype(bool)


def _count(mask: np.ndarray, connectivity: int) -> int:
    return cv2.connectedComponents(mask.astype(np.uint8), connectivity=connectivity)[0] - 1


def test_thinning_keeps_every_part_and_every_hole():
    # The skeleton lies in the shape, has as many 8-connected parts and as many holes (4-connected
    # parts of the background, the image padded so that the outside is one), and thinning it again
    # removes nothing.
    for mask in _shapes(0, 300):
        s = thin(mask)
        assert not (s & ~mask).any()
        assert _count(s, 8) == _count(mask, 8)
        assert _count(~np.pad(s, 1), 4) == _count(~np.pad(mask, 1), 4)
        assert np.array_equal(thin(s), s)


@pytest.mark.parametrize("width", range(1, 9))
def test_a_strip_thins_to_one_pixel_on_its_middle(width):
    # A horizontal strip of any width, even ones included, keeps one pixel per column on its middle
    # row (one of the two middle rows for even widths), its ends shortened by at most its width.
    m = np.zeros((width + 6, 60), bool)
    m[3:3 + width, 5:55] = True
    s = thin(m)
    rows, cols = np.nonzero(s)
    assert np.array_equal(np.bincount(cols, minlength=60)[cols.min():cols.max() + 1], np.ones(cols.max() - cols.min() + 1))
    assert cols.min() <= 5 + width and cols.max() >= 54 - width
    assert np.all(np.abs(rows - (3 + (width - 1) / 2)) <= 0.5)


@pytest.mark.parametrize("angle", [15.0, 30.0, 45.0, 60.0, 110.0])
def test_a_sloping_strip_thins_to_its_centre_line(angle):
    # Away from its ends, the skeleton of a strip 5 pixels wide at any slope lies within a pixel
    # and a half of its centre line, and follows it without a gap.
    m = np.zeros((120, 120), np.uint8)
    t = np.radians(angle)
    d = np.array([np.cos(t), np.sin(t)])
    a, b = np.array([60, 60]) - 50 * d, np.array([60, 60]) + 50 * d
    cv2.line(m, tuple(int(round(x)) for x in a), tuple(int(round(x)) for x in b), 1, 5)
    s = thin(m.astype(bool))
    r, c = np.nonzero(s)
    xy = np.stack([c, r], 1) - np.array([60, 60])
    along, across = xy @ d, xy @ np.array([-d[1], d[0]])
    inner = np.abs(along) < 45
    assert np.abs(across[inner]).max() <= 1.5
    steps = np.diff(np.sort(along[inner]))
    assert _count(s, 8) == 1 and steps.max() <= 1.5 and np.sort(along[inner])[[0, -1]].tolist() == pytest.approx(
        [-45, 45], abs=1.5)


def test_the_table_is_guo_and_halls():
    # A few neighbourhoods by hand (bits N, NE, E, SE, S, SW, W, NW): an end point (one
    # neighbour) stays, a pixel joining two parts stays, a corner of a block goes in either
    # subiteration, a pixel on a block's side in the subiteration that peels that side (the
    # first: west and south; the second: east and north).
    n, ne, e, se, s, sw, w, nw = (1 << i for i in range(8))
    assert GUO_HALL[e] == 0  # an end
    assert GUO_HALL[n | s] == 0  # a bridge between two parts
    assert GUO_HALL[e | se | s] == 3 and GUO_HALL[w | nw | n] == 3  # corners
    assert GUO_HALL[n | ne | e | se | s] == 1 and GUO_HALL[w | nw | n | ne | e] == 1  # west and south sides
    assert GUO_HALL[s | sw | w | nw | n] == 2 and GUO_HALL[e | se | s | sw | w] == 2  # east and north sides
    assert GUO_HALL[0] == 0 and GUO_HALL[255] == 0  # alone, or inside
    assert np.array_equal(thinning_table(lambda *p: np.zeros(256, bool)), np.zeros(256, np.uint8))


def test_a_slice_imports_neither_scipy_nor_scikit_image(tmp_path):
    # Importing either costs a command about 0.25 s: slicing, checking the mesh and planning the
    # print (gap fill's thinning and the islands' components included) do without them, and
    # without numpy.ma (10-14 ms in each worker), which np.unique and np.isin load.
    # (Said by an exit handler: the command ends its process once it is done, exit handlers run.)
    probe = ("import atexit, runpy, sys; sys.argv = sys.argv[1:]; "
             "atexit.register(lambda: print('loaded:', sorted(m for m in ('scipy', 'skimage', 'numpy.ma') "
             "if m in sys.modules))); runpy.run_module('slicelab', run_name='__main__')")
    from slicelab import Mesh, save
    from slicelab.samples import box
    wall = tmp_path / "wall.stl"
    save(box((0, 0, 0), (20, 1.0, 1)), wall)  # a wall 1 mm thick: gap fill between its perimeters
    # A block whose corner at (20, 10, 5) is one single-precision step off on one facet: --repair
    # snaps it (near-coincident vertices, without a k-d tree) and makes windings agree.
    t = box((0, 0, 0), (20, 10, 5)).triangles.astype(np.float32)
    corner = np.flatnonzero(np.all(t.reshape(-1, 3) == (20, 10, 5), axis=1))[0]
    t.reshape(-1, 3)[corner, 0] = np.nextafter(np.float32(20), np.float32(21))
    noisy = tmp_path / "noisy.stl"
    save(Mesh(t.astype(np.float64)), noisy)
    for part, more in ((wall, []), (ROOT / "data" / "mushroom.stl", ["--support", "auto"]), (noisy, ["--repair"])):
        out = tmp_path / "part.gcode"
        r = subprocess.run([sys.executable, "-c", probe, "slicelab", "slice", str(part), "-o", str(out),
                            "--workers", "1", *more], capture_output=True, text=True, cwd=ROOT)
        assert r.returncode == 0, r.stderr
        assert "loaded: []" in r.stdout
        assert out.read_bytes().count({wall: b";TYPE:Gap fill", noisy: b";TYPE:External perimeter"}.get(
            part, b";TYPE:Support material")) > 0
        assert part != noisy or "snapped 1 near-coincident vertex" in r.stdout + r.stderr


def _chains_by_list_ranking(start_key, end_key):
    """The chains as a sort of the keys and list ranking by pointer jumping find them (numpy and
    SciPy's components): the oracle of `chain_segments`' compiled walk."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    m = len(start_key)
    os_, oe = np.argsort(start_key, kind="stable"), np.argsort(end_key, kind="stable")
    ss, se = start_key[os_], end_key[oe]
    first_s = np.searchsorted(ss, se, side="left")
    count_s = np.searchsorted(ss, se, side="right") - first_s
    rank = np.arange(m) - np.searchsorted(se, se, side="left")
    ok = rank < count_s
    nxt = np.full(m, -1)
    nxt[oe[ok]] = os_[first_s[ok] + rank[ok]]  # the k-th arrival at a key takes its k-th departure
    has = nxt >= 0
    prv = np.full(m, -1)
    prv[nxt[has]] = np.flatnonzero(has)
    src = np.flatnonzero(has)
    n_comp, comp = connected_components(coo_matrix((np.ones(len(src)), (src, nxt[has])), shape=(m, m)),
                                        directed=False)
    is_open = np.zeros(n_comp, bool)
    is_open[comp[prv < 0]] = True
    lowest = np.full(n_comp, m)
    np.minimum.at(lowest, comp, np.arange(m))
    tail = nxt.copy()
    tail[prv[lowest[~is_open]]] = -1  # each cycle cut before its lowest segment
    dist = (tail >= 0).astype(np.int64)
    jump = tail.copy()
    active = np.flatnonzero(jump >= 0)
    while len(active):  # list ranking: each segment's distance to its chain's end
        j = jump[active]
        dist[active] += dist[j]
        jump[active] = jump[j]
        active = active[jump[active] >= 0]
    counts = np.bincount(comp, minlength=n_comp)
    bounds = np.concatenate([[0], np.cumsum(counts)])
    order = np.empty(m, np.int64)
    order[bounds[comp] + counts[comp] - 1 - dist] = np.arange(m)
    return order, bounds, ~is_open


@pytest.mark.parametrize("seed", range(8))
def test_chains_are_list_rankings(seed):
    # Loops, open chains, keys met several times (an in-plane vertex touched twice), negative and
    # huge keys: the compiled walk chains them as the sort and list ranking do, chain for chain.
    from slicelab.geometry import chain_segments
    rng = np.random.default_rng(seed)
    n_loops = int(rng.integers(0, 30))
    starts, ends = [], []
    base = 0
    for _ in range(n_loops):  # rings of keys, some repeated, some broken open
        k = int(rng.integers(1, 40))
        keys = base + rng.integers(0, max(1, k // (1 + seed % 3)), k)
        base += k
        starts += keys.tolist()
        nxt = np.roll(keys, -1)
        if rng.random() < 0.3:
            nxt[-1] = -base - 7  # the chain ends on a key no segment starts at
        ends += nxt.tolist()
    perm = rng.permutation(len(starts))
    scale = [1, 2 ** 40 + 3, -1][seed % 3]
    s = np.array(starts, np.int64)[perm] * scale
    e = np.array(ends, np.int64)[perm] * scale
    c = chain_segments(s, e)
    order, bounds, closed = _chains_by_list_ranking(s, e)
    assert c.order.tolist() == order.tolist()
    assert c.bounds.tolist() == bounds.tolist()
    assert c.closed.tolist() == closed.tolist()
    walk = [c.order[a:b] for a, b in zip(c.bounds[:-1], c.bounds[1:])]  # each step ends where the next starts
    assert all((e[w[:-1]] == s[w[1:]]).all() for w in walk)
    assert all(e[w[-1]] == s[w[0]] for w, shut in zip(walk, c.closed) if shut)


def test_chains_of_nothing_and_of_a_long_ring():
    from slicelab.geometry import chain_segments
    c = chain_segments(np.zeros(0, np.int64), np.zeros(0, np.int64))
    assert c.order.tolist() == [] and c.bounds.tolist() == [0] and len(c) == 0
    n = 200_000
    keys = np.random.default_rng(1).permutation(n)  # one ring through every key, segments shuffled
    c = chain_segments(keys, np.roll(keys, -1))
    assert len(c) == 1 and c.closed.tolist() == [True]
    assert c.order[0] == 0 and sorted(c.order.tolist()) == list(range(n))
    with pytest.raises(ValueError, match="same length"):
        chain_segments(np.zeros(2, np.int64), np.zeros(3, np.int64))
