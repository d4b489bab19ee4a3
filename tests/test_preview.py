"""Split previews: a dense mesh drawn from points covers what the exact fill covers, with no holes."""
from __future__ import annotations

import numpy as np
import pytest

from slicelab.geometry import Frame
from slicelab.samples import sphere
from slicelab.viz import render_depth

FRAME = Frame.from_plane((0, 0, 0), (0, 0, 1))


def _pixel_centres(extent, shape):
    s0, s1, t0, t1 = extent
    rows, cols = shape
    x = s0 + (np.arange(cols) + 0.5) * (s1 - s0) / cols
    y = t1 - (np.arange(rows) + 0.5) * (t1 - t0) / rows
    return np.meshgrid(x, y)


def test_a_dense_sphere_drawn_from_points_is_a_full_disc():
    m = sphere(20.0, 200, 400)  # facets of about 0.3 mm, pixels of 0.83 mm: drawn as points
    extent, shape = (-25, 25, -25, 25), (60, 60)
    img = render_depth(m.triangles, m.normals, FRAME, extent, shape)
    x, y = _pixel_centres(extent, shape)
    r = np.hypot(x, y)
    covered = img[..., 3] > 0
    assert covered[r < 20 - 0.9].all()          # no hole inside the silhouette
    assert not covered[r > 20 + 0.9].any()      # nothing outside it
    # Seen from +z the upper half faces the viewer: shaded as outside (grey, not terracotta).
    centre = img[30, 30, :3]
    assert abs(centre[0] - centre[2]) < 0.05


@pytest.mark.parametrize("n_lat, n_lon", [(24, 48), (200, 400)], ids=["coarse: filled", "dense: points"])
def test_both_ways_of_drawing_give_the_disc_to_a_pixel(n_lat, n_lon):
    m = sphere(20.0, n_lat, n_lon)
    extent, shape = (-25, 25, -25, 25), (50, 50)
    covered = render_depth(m.triangles, m.normals, FRAME, extent, shape)[..., 3] > 0
    x, y = _pixel_centres(extent, shape)
    r = np.hypot(x, y)
    assert covered[r < 19].all() and not covered[r > 21].any()
    # Pixels of 1 mm2; drawn as points, the rim may light pixels up to half a pixel outside it.
    assert np.count_nonzero(covered) == pytest.approx(np.pi * 20 ** 2, rel=0.08)


def test_a_decimated_drawing_keeps_large_facets_and_matches_the_full_one():
    # A dense sphere (160 k facets) beside a box of 12 large facets: drawn from a sample of 3600
    # facets, the box must still be whole (wide facets are always drawn) and the sphere a disc.
    from slicelab import Mesh
    from slicelab.samples import box
    m = Mesh(np.concatenate([sphere(20.0, 200, 400).triangles, box((25, -10, -5), (45, 10, 5)).triangles]))
    extent, shape = (-25, 50, -37.5, 37.5), (60, 60)
    full = render_depth(m.triangles, m.normals, FRAME, extent, shape, decimate=False)
    dec = render_depth(m.triangles, m.normals, FRAME, extent, shape)
    x, y = _pixel_centres(extent, shape)
    on_box = (x > 25 + 1.25) & (x < 45 - 1.25) & (np.abs(y) < 10 - 1.25)
    assert (dec[..., 3] > 0)[on_box].all()
    r = np.hypot(x, y)
    covered = dec[..., 3] > 0
    assert covered[r < 20 - 1.25].all() and not covered[(r > 20 + 1.25) & (x < 22)].any()
    # Pixel for pixel, a spread point shades a pixel as its neighbour's facet: a little lighter or
    # darker, never the other side's colour (terracotta) or empty.
    both = covered & (full[..., 3] > 0)
    assert np.count_nonzero(covered != (full[..., 3] > 0)) <= 0.03 * np.count_nonzero(both)
    shade = np.abs(dec[..., :3] - full[..., :3]).max(axis=2)[both]
    assert np.median(shade) < 0.03 and shade.max() < 0.25
