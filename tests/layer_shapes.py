"""Small 2-D shapes and sections shared by the layer-raster tests (issue 5)."""
from __future__ import annotations

import numpy as np

from slicelab.geometry.polygons import loop_hierarchy
from slicelab.geometry.planes import Frame
from slicelab.slicing.sections import Section


def section_of(loops) -> Section:
    """A horizontal Section made straight from oriented loops (outer CCW, holes CW)."""
    loops = [np.asarray(lp, float) for lp in loops]
    segs = np.concatenate([np.stack([lp, np.roll(lp, -1, axis=0)], 1) for lp in loops])
    depth, parent = loop_hierarchy(loops)
    return Section(Frame.from_plane((0, 0, 0), (0, 0, 1)), segs, loops, hierarchy=(depth, parent))


def star(n=5, r1=10.0, r2=4.0, c=(0.3, 0.7)):
    t = np.pi * 2 * np.arange(2 * n) / (2 * n) + 0.1
    r = np.where(np.arange(2 * n) % 2 == 0, r1, r2)
    return np.c_[r * np.cos(t), r * np.sin(t)] + c


def circle(r, n=64, c=(0.0, 0.0)):
    t = 2 * np.pi * np.arange(n) / n
    return np.c_[r * np.cos(t), r * np.sin(t)] + c


def rotation(a):
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def rect(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)


SHAPES = {
    "star": [star()],
    "rotated_rect_with_hole": [(rect(0, 0, 12, 8) - (6, 4)) @ rotation(0.3).T + 0.013, circle(2.0)[::-1]],
    "L": [np.array([[0, 0], [10, 0], [10, 3], [3, 3], [3, 10], [0, 10]], float) + 0.0137],
}


def corner_angles(ring):
    """Interior angle (degrees) at each vertex of a counter-clockwise ring."""
    a = np.roll(ring, 1, axis=0) - ring
    b = np.roll(ring, -1, axis=0) - ring
    ang = np.degrees(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.einsum("ij,ij->i", a, b)))
    return np.where(ang < 0, ang + 360, ang)
