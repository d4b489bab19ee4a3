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


def test_the_split_preview_file_shows_the_halves_and_the_section_where_they_are(tmp_path):
    import cv2

    import slicelab
    from slicelab.samples import torus
    # A torus split through its axis: the section is two discs of radius 10 at x = +-30.
    sp = slicelab.split(torus(30, 10, 96, 48), (0, 0, 0), (0, 1, 0))
    layout = slicelab.viz.save_split_preview(sp, tmp_path / "preview.png", pixels=240)
    img = cv2.imread(str(tmp_path / "preview.png"))[..., ::-1].astype(int)  # read back: RGB
    frame = sp.section.frame
    s0, s1, t0, t1 = layout["extent"]

    def pixel(panel, point):
        x, y, w, h = layout["panels"][panel]
        s, t = (np.asarray(point, float) - frame.origin) @ np.stack([frame.u, frame.v]).T
        return img[int(y + (t1 - t) / (t1 - t0) * h), int(x + (s - s0) / (s1 - s0) * w)]

    def redness(rgb):
        return int(rgb[0]) - max(int(rgb[1]), int(rgb[2]))

    for panel in (0, 1):
        # The tube at x = 0 is seen from outside (the front's outer side, the rear's inner side):
        # grey, not under the section.
        grey = pixel(panel, (0, 0, 0))
        assert 60 < grey[0] < 245 and abs(grey[0] - grey[2]) < 20
        assert pixel(panel, (0, 0, 12)).tolist() == [255, 255, 255]  # above the torus: paper
        assert pixel(panel, (-42, 0, 0)).tolist() == [255, 255, 255]
        # The discs are tinted red; their rims are drawn in red.
        assert redness(pixel(panel, (30, 0, 0))) > 25 and redness(pixel(panel, (-30, 0, 0))) > 25
        rim = [max(redness(pixel(panel, (c + 10 * np.cos(a) + dx, 0, 10 * np.sin(a) + dz)))
                   for dx in (-0.2, 0, 0.2) for dz in (-0.2, 0, 0.2))
               for c in (-30, 30) for a in np.linspace(0, 2 * np.pi, 24, endpoint=False)]
        assert min(rim) > 60


def test_a_decimated_hollow_ball_shows_no_farther_surface_through_the_nearer_one():
    # A ball with a wall 3 mm thick (inner sphere wound inwards), 320 k facets drawn from a sample
    # of 14 k: a pixel left without points of the outer surface would show the inner one (darker,
    # or terracotta from behind). Pits and one-pixel cracks are closed: every pixel inside the
    # silhouette has the shade of the exact drawing.
    from slicelab import Mesh
    m = Mesh(np.concatenate([sphere(20.0, 200, 400).triangles, sphere(17.0, 200, 400).triangles[:, ::-1]]))
    extent, shape = (-25, 25, -25, 25), (120, 120)
    full = render_depth(m.triangles, m.normals, FRAME, extent, shape, decimate=False)
    dec = render_depth(m.triangles, m.normals, FRAME, extent, shape)
    x, y = _pixel_centres(extent, shape)
    inside = np.hypot(x, y) < 19
    assert (dec[..., 3] > 0)[inside].all()
    assert np.abs(dec[..., :3] - full[..., :3]).max(axis=2)[inside].max() < 0.1


def test_a_fan_of_slivers_in_a_decimated_drawing_is_a_whole_disc():
    # A disc of radius 15 fanned into 2000 slivers (as a cap may be), beside a dense sphere that
    # makes the drawing decimated: the slivers are drawn as points spread over them, not filled
    # over their boxes, and the disc must still be whole and as the exact drawing shades it.
    from slicelab import Mesh
    a = np.linspace(0, 2 * np.pi, 2001)
    rim = np.column_stack([45 + 15 * np.cos(a), 15 * np.sin(a), np.zeros_like(a)])
    fan = np.stack([np.broadcast_to([45.0, 0.0, 0.0], (2000, 3)), rim[:-1], rim[1:]], axis=1)
    m = Mesh(np.concatenate([sphere(20.0, 200, 400).triangles, fan]))
    extent, shape = (-25, 70, -47.5, 47.5), (200, 200)
    full = render_depth(m.triangles, m.normals, FRAME, extent, shape, decimate=False)
    dec = render_depth(m.triangles, m.normals, FRAME, extent, shape)
    x, y = _pixel_centres(extent, shape)
    r = np.hypot(x - 45, y)
    on_disc, off_disc = r < 15 - 0.5, (r > 15 + 1.0) & (x > 22)
    assert (dec[..., 3] > 0)[on_disc].all() and not (dec[..., 3] > 0)[off_disc].any()
    assert np.abs(dec[..., :3] - full[..., :3]).max(axis=2)[on_disc].max() < 0.02


def test_the_exploded_view_file_shows_each_piece_in_its_colour_where_it_lies(tmp_path):
    import cv2

    import slicelab
    from slicelab.samples import box
    from slicelab.viz import save_exploded_png
    parts = slicelab.cut(box((0, 0, 0), (40, 40, 40)), (0, 0, 20), (0, 0, 1))
    save_exploded_png((parts.rear, parts.front), tmp_path / "exploded.png", title="cube: cut", pixels=300)
    img = cv2.imread(str(tmp_path / "exploded.png"))[..., ::-1].astype(int)  # read back: RGB
    # The rear (lower) piece is blue, the front (upper) one orange: both seen, the orange above.
    blue = (img[..., 2] > img[..., 0] + 40) & (img[..., 2] > 80)
    orange = (img[..., 0] > img[..., 2] + 80) & (img[..., 1] > img[..., 2] + 20)
    assert blue.sum() > 5000 and orange.sum() > 5000
    assert np.nonzero(orange)[0].mean() < np.nonzero(blue)[0].mean()
    # The two halves are pushed apart: rows between them hold neither.
    gap = ~(blue | orange).any(axis=1)
    rows_o, rows_b = np.nonzero(orange.any(axis=1))[0], np.nonzero(blue.any(axis=1))[0]
    assert gap[rows_o.max() + 1:rows_b.min()].all() or rows_o.max() < rows_b.min()
