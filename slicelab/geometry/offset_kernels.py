"""Compiled loops that move contour rings onto the exact offsets of a boundary.

Marching squares interpolates a distance field linearly between pixel
centres: exact along the offset's straight runs, off it round arcs and
creases. `onto_offset` moves every ring vertex onto the exact offset and
follows its arcs and creases, from the exact distances to the boundary's
pieces in their buckets (as `slicelab.geometry.segment_kernels.band_distances`
reads them), in one compiled pass per level.

See Also
--------
slicelab.printing.grid.distance.level_rings : the rings this moves.
slicelab.geometry.spatial.SegmentIndex.piece_buckets : the buckets.

References
----------
.. [1] S. K. Lam, A. Pitrou, S. Seibert, "Numba: a LLVM-based Python JIT
   compiler", LLVM-HPC 2015.
"""
from __future__ import annotations

import numpy as np

from .compiled import njit

__all__ = ["onto_offset"]


@njit(cache=True, nogil=True)
def _nearest_piece(x, y, cell, ox, oy, width, height, start, owner, pieces):
    """Distance from (x, y) to the nearest piece its bucket lists, and that nearest point (inf if none)."""
    bx = int(np.floor(x / cell)) - ox
    by = int(np.floor(y / cell)) - oy
    if bx < 0 or bx >= width or by < 0 or by >= height:
        return np.inf, x, y
    key = by * width + bx
    low, fx, fy = np.inf, x, y
    for u in range(start[key], start[key + 1]):
        s = owner[u]
        ax, ay = pieces[s, 0, 0], pieces[s, 0, 1]
        dx, dy = pieces[s, 1, 0] - ax, pieces[s, 1, 1] - ay
        wx, wy = x - ax, y - ay
        t = min(max((wx * dx + wy * dy) / max(dx * dx + dy * dy, 1e-300), 0.0), 1.0)
        ex, ey = wx - t * dx, wy - t * dy
        e2 = ex * ex + ey * ey
        if e2 < low:
            low, fx, fy = e2, ax + t * dx, ay + t * dy
    return np.sqrt(low), fx, fy


@njit(cache=True, nogil=True)
def _on_material_side(x, y, cell, ox, oy, width, height, start, owner, pieces):
    """Whether (x, y) lies on the material side (the left) of the boundary pieces nearest to it.

    An unsigned distance cannot tell the offset inside the material from its mirror outside;
    the pieces run with the material on their left. Nearest to a piece's inside, the point's
    side of that piece says; nearest to a vertex, the pieces that end and start there do: at a
    convex vertex the point must be left of both, at a reflex one left of either.
    """
    bx = int(np.floor(x / cell)) - ox
    by = int(np.floor(y / cell)) - oy
    if bx < 0 or bx >= width or by < 0 or by >= height:
        return False
    key = by * width + bx
    low, best, best_t = np.inf, -1, 0.0
    for u in range(start[key], start[key + 1]):
        s = owner[u]
        ax, ay = pieces[s, 0, 0], pieces[s, 0, 1]
        dx, dy = pieces[s, 1, 0] - ax, pieces[s, 1, 1] - ay
        wx, wy = x - ax, y - ay
        t = min(max((wx * dx + wy * dy) / max(dx * dx + dy * dy, 1e-300), 0.0), 1.0)
        ex, ey = wx - t * dx, wy - t * dy
        e2 = ex * ex + ey * ey
        if e2 < low:
            low, best, best_t = e2, s, t
    if best < 0:
        return False
    ax, ay = pieces[best, 0, 0], pieces[best, 0, 1]
    dx, dy = pieces[best, 1, 0] - ax, pieces[best, 1, 1] - ay
    left = dx * (y - ay) - dy * (x - ax) > 0.0
    if 0.0 < best_t < 1.0:
        return left
    # The foot is a vertex: find the pieces ending and starting there.
    vx, vy = (ax, ay) if best_t == 0.0 else (pieces[best, 1, 0], pieces[best, 1, 1])
    eps = 1e-9 * (1.0 + abs(vx) + abs(vy))
    into, out_of = -1, -1
    for u in range(start[key], start[key + 1]):
        s = owner[u]
        if abs(pieces[s, 1, 0] - vx) <= eps and abs(pieces[s, 1, 1] - vy) <= eps:
            into = s
        if abs(pieces[s, 0, 0] - vx) <= eps and abs(pieces[s, 0, 1] - vy) <= eps:
            out_of = s
    if into < 0 or out_of < 0:
        return left
    ix, iy = pieces[into, 1, 0] - pieces[into, 0, 0], pieces[into, 1, 1] - pieces[into, 0, 1]
    ox_, oy_ = pieces[out_of, 1, 0] - pieces[out_of, 0, 0], pieces[out_of, 1, 1] - pieces[out_of, 0, 1]
    left_in = ix * (y - pieces[into, 0, 1]) - iy * (x - pieces[into, 0, 0]) > 0.0
    left_out = ox_ * (y - pieces[out_of, 0, 1]) - oy_ * (x - pieces[out_of, 0, 0]) > 0.0
    if ix * oy_ - iy * ox_ > 0.0:  # a left turn: a convex corner of the material
        return left_in and left_out
    return left_in or left_out


@njit(cache=True, nogil=True)
def _grow(out, m, more):
    """`out` with room for `more` rows past its first m."""
    if m + more < len(out):
        return out
    grown = np.empty((2 * len(out) + more, 2))
    grown[:m] = out[:m]
    return grown


@njit(cache=True, nogil=True)
def _crease_point(x0, y0, x1, y1, n0x, n0y, n1x, n1y, level, reach, cell, ox, oy, width, height, start, owner,
                  pieces):
    """Where the offsets through chord ends 0 and 1 meet beside the chord, exactly at `level` (nan if nowhere).

    Each end's feature is a boundary segment (the offset is the tangent line
    there) or a boundary vertex (the offset is the circle of radius `level`
    round its foot, ``end - level normal``): the meeting points of each
    pairing are tried, and the first beside the chord whose exact distance
    to the boundary is the level, on the material's side of it
    (`_on_material_side`), wins.
    """
    lx, ly = x1 - x0, y1 - y0
    l2 = lx * lx + ly * ly
    f0x, f0y = x0 - level * n0x, y0 - level * n0y
    f1x, f1y = x1 - level * n1x, y1 - level * n1y
    cand = np.full((7, 2), np.nan)
    den = n0y * n1x - n0x * n1y  # the tangents (-n0y, n0x) and (-n1y, n1x) crossed
    if abs(den) > 1e-12:
        t = -(lx * n1x + ly * n1y) / den
        cand[0, 0], cand[0, 1] = x0 - t * n0y, y0 + t * n0x
    dx, dy = f1x - f0x, f1y - f0y
    dl = np.sqrt(dx * dx + dy * dy)
    if 1e-9 < dl < 2 * level:
        h = np.sqrt(level * level - 0.25 * dl * dl) / dl
        cand[1, 0], cand[1, 1] = 0.5 * (f0x + f1x) - h * dy, 0.5 * (f0y + f1y) + h * dx
        cand[2, 0], cand[2, 1] = 0.5 * (f0x + f1x) + h * dy, 0.5 * (f0y + f1y) - h * dx
    # The tangent line at one end against the circle round the other's foot.
    for w in range(2):
        px, py = (x0, y0) if w == 0 else (x1, y1)
        ux, uy = (-n0y, n0x) if w == 0 else (-n1y, n1x)
        cx, cy = (f1x, f1y) if w == 0 else (f0x, f0y)
        wx, wy = px - cx, py - cy
        bq = ux * wx + uy * wy
        disc = bq * bq - (wx * wx + wy * wy - level * level)
        if disc >= 0:
            root = np.sqrt(disc)
            cand[3 + 2 * w, 0], cand[3 + 2 * w, 1] = px + (-bq - root) * ux, py + (-bq - root) * uy
            cand[4 + 2 * w, 0], cand[4 + 2 * w, 1] = px + (-bq + root) * ux, py + (-bq + root) * uy
    for c in range(7):
        qx, qy = cand[c, 0], cand[c, 1]
        if not np.isfinite(qx):
            continue
        along = ((qx - x0) * lx + (qy - y0) * ly) / l2
        if not (0.0 < along < 1.0) or abs((qx - x0) * ly - (qy - y0) * lx) > (0.5 * np.sqrt(l2) + reach) * np.sqrt(l2):
            continue
        d, fx, fy = _nearest_piece(qx, qy, cell, ox, oy, width, height, start, owner, pieces)
        # At the level, and inside: the mirror of the offset outside the material is at the level too.
        if abs(d - level) <= 1e-9 + 1e-7 * level and _on_material_side(qx, qy, cell, ox, oy, width, height,
                                                                        start, owner, pieces):
            return qx, qy
    return np.nan, np.nan


@njit(cache=True, nogil=True)
def _start_at_sharpest(out, s, e):
    """Ring ``out[s:e]`` without repeated points, turned round to start at its sharpest turn (a
    corner, if it has one): simplification keeps a ring's first vertex, so it is best one that is
    needed anyway. Returns the ring's new end."""
    k = s
    for i in range(s, e):  # two vertices moved to the same corner become one
        if k > s and out[i, 0] == out[k - 1, 0] and out[i, 1] == out[k - 1, 1]:
            continue
        out[k, 0], out[k, 1] = out[i, 0], out[i, 1]
        k += 1
    while k - s > 1 and out[k - 1, 0] == out[s, 0] and out[k - 1, 1] == out[s, 1]:
        k -= 1
    n = k - s
    if n < 3:
        return k
    best, at = -1.0, 0
    for i in range(n):
        h = s + (i - 1) % n
        c = s + i
        q = s + (i + 1) % n
        ux, uy = out[c, 0] - out[h, 0], out[c, 1] - out[h, 1]
        vx, vy = out[q, 0] - out[c, 0], out[q, 1] - out[c, 1]
        norm = np.sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy))
        turn = 1.0 - (ux * vx + uy * vy) / norm if norm > 0 else 0.0
        if turn > best:
            best, at = turn, i
    if at:
        ring = out[s:k].copy()
        for i in range(n):
            out[s + i, 0], out[s + i, 1] = ring[(i + at) % n, 0], ring[(i + at) % n, 1]
    return k


@njit(cache=True, nogil=True)
def onto_offset(pts, bounds, level, tol, near, reach, cell, ox, oy, width, height, start, owner, pieces):
    """Contour rings moved onto the exact offset at `level` of the boundary, its arcs and creases followed.

    Each vertex within `near` of the level (its exact distance to the
    nearest piece) moves along the line from its nearest boundary point (its
    foot) to the level's distance on that line, where the offset passes; the
    offset's normal there is that line's direction. Then each chord between
    two moved vertices whose neighbours turn enough is checked: a chord with
    both ends on the arc round one boundary vertex gets even steps along the
    arc, as few as keep each within `tol` of it; otherwise the point where
    the offsets of its ends' features meet (a crease: `_crease_point`), or
    else its middle moved onto the offset, goes in if it lies more than ``tol
    / 2`` off the chord, and both halves are checked in turn, at most 8 deep.
    Up to 10 vertices off the level between two moved ones are the cut-off
    tip of a sharp corner of the offset: they give way to the point where the
    offsets through those two meet, if it is exactly at the level.

    Parameters
    ----------
    pts : (n, 2) float ndarray
        The rings' vertices (mm), one ring after another.
    bounds : (r + 1,) int ndarray
        Ring k is ``pts[bounds[k]:bounds[k + 1]]``, implicitly closed.
    level, tol, near : float
        The offset's distance, the chords' tolerance, and how far off the
        level a vertex may be to be moved (mm).
    reach : float
        How far beyond half its chord a corner's tip may lie (mm).
    cell, ox, oy, width, height, start, owner, pieces
        Buckets of boundary pieces, as for
        `slicelab.geometry.segment_kernels.band_distances`; `cell` at least ``level + near``.

    Returns
    -------
    out : (m, 2) ndarray
    out_bounds : (r + 1,) int ndarray
    """
    n = len(pts)
    moved = np.empty((n, 2))
    normal = np.zeros((n, 2))
    good = np.zeros(n, np.bool_)
    for i in range(n):
        x, y = pts[i, 0], pts[i, 1]
        d, fx, fy = _nearest_piece(x, y, cell, ox, oy, width, height, start, owner, pieces)
        if abs(d - level) <= near and d > 0.0:
            normal[i, 0], normal[i, 1] = (x - fx) / d, (y - fy) / d
            x, y = fx + level * normal[i, 0], fy + level * normal[i, 1]
            good[i] = True
        moved[i, 0], moved[i, 1] = x, y
    arc_step = 2 * np.arccos(max(1.0 - tol / level, -1.0)) if level > 0 else np.pi
    out = np.empty((2 * n + 16, 2))
    out_bounds = np.zeros(len(bounds), np.int64)
    m = 0
    # A stack of chords still to check (kind 0: ends and their normals) and points to emit (kind 1).
    stack = np.empty((64, 8))
    kind = np.empty(64, np.int64)
    depth = np.empty(64, np.int64)
    for r in range(len(bounds) - 1):
        a, b = bounds[r], bounds[r + 1]
        first = a
        while first < b and not good[first]:
            first += 1
        if first == b:  # nothing to move: the ring as it is
            out = _grow(out, m, b - a)
            out[m:m + b - a] = pts[a:b]
            m += b - a
            out_bounds[r + 1] = m
            continue
        i = first
        while True:  # from each moved vertex i to the next, j, round the ring from `first`
            j = i + 1 if i + 1 < b else a
            run = 0
            while not good[j]:
                j = j + 1 if j + 1 < b else a
                run += 1
            out = _grow(out, m, 1)
            out[m, 0], out[m, 1] = moved[i, 0], moved[i, 1]
            m += 1
            top = 0
            if run > 0:
                # Vertices off the level between i and j: a sharp corner of the offset that
                # interpolation cut off, if the offsets through i and j meet near it exactly.
                qx, qy = np.nan, np.nan
                if run <= 10:
                    qx, qy = _crease_point(moved[i, 0], moved[i, 1], moved[j, 0], moved[j, 1], normal[i, 0],
                                           normal[i, 1], normal[j, 0], normal[j, 1], level, reach, cell, ox, oy,
                                           width, height, start, owner, pieces)
                if np.isfinite(qx):
                    out = _grow(out, m, 1)
                    out[m, 0], out[m, 1] = qx, qy
                    m += 1
                else:
                    out = _grow(out, m, run)
                    u = i
                    for _ in range(run):
                        u = u + 1 if u + 1 < b else a
                        out[m, 0], out[m, 1] = pts[u, 0], pts[u, 1]
                        m += 1
                i = j
                if i == first:
                    break
                continue
            # The offset between i and j turns by about as much as the edges before and after
            # the chord: if so little that it strays less than tol / 2 from the chord, go on.
            h = i - 1 if i > a else b - 1
            k = j + 1 if j + 1 < b else a
            ux, uy = moved[i, 0] - moved[h, 0], moved[i, 1] - moved[h, 1]
            vx, vy = moved[k, 0] - moved[j, 0], moved[k, 1] - moved[j, 1]
            cross, dot = ux * vy - uy * vx, ux * vx + uy * vy
            lx, ly = moved[j, 0] - moved[i, 0], moved[j, 1] - moved[i, 1]
            span = np.sqrt(lx * lx + ly * ly)
            norm = np.sqrt(ux * ux + uy * uy) * np.sqrt(vx * vx + vy * vy)
            # tan(delta / 2) = sin / (1 + cos)
            if not (b - a >= 4 and dot > 0 and norm > 0 and 0.5 * span * abs(cross) / (norm + dot) <= 0.5 * tol):
                stack[0, 0], stack[0, 1], stack[0, 2], stack[0, 3] = moved[i, 0], moved[i, 1], moved[j, 0], moved[j, 1]
                stack[0, 4], stack[0, 5], stack[0, 6] = normal[i, 0], normal[i, 1], normal[j, 0]
                stack[0, 7] = normal[j, 1]
                kind[0], depth[0] = 0, 0
                top = 1
            while top > 0:
                top -= 1
                if kind[top] == 1:
                    out = _grow(out, m, 1)
                    out[m, 0], out[m, 1] = stack[top, 0], stack[top, 1]
                    m += 1
                    continue
                x0, y0, x1, y1 = stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3]
                n0x, n0y, n1x, n1y = stack[top, 4], stack[top, 5], stack[top, 6], stack[top, 7]
                dep = depth[top]
                lx, ly = x1 - x0, y1 - y0
                l2 = lx * lx + ly * ly
                if dep >= 8 or l2 == 0.0:
                    continue
                qx = np.nan
                fdx = (x1 - level * n1x) - (x0 - level * n0x)
                fdy = (y1 - level * n1y) - (y0 - level * n0y)
                if n0x * n1x + n0y * n1y < 1.0 - 1e-12 and fdx * fdx + fdy * fdy > 1e-18:
                    # Two features (the ends' feet apart): the point where their offsets meet, if
                    # the chord cut it off (however little: a corner is a corner).
                    qx, qy = _crease_point(x0, y0, x1, y1, n0x, n0y, n1x, n1y, level, reach, cell, ox, oy, width,
                                           height, start, owner, pieces)
                if np.isfinite(qx):
                    if abs((qx - x0) * ly - (qy - y0) * lx) <= 1e-9 * l2:
                        continue
                    dq, fqx, fqy = _nearest_piece(qx, qy, cell, ox, oy, width, height, start, owner, pieces)
                    cx, cy, cnx, cny = qx, qy, (qx - fqx) / dq, (qy - fqy) / dq
                else:
                    if l2 <= tol * tol:
                        continue
                    sx, sy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
                    d, fx, fy = _nearest_piece(sx, sy, cell, ox, oy, width, height, start, owner, pieces)
                    if not (abs(d - level) <= near) or d <= 0.0:
                        continue
                    ax, ay, bx, by = x0 - fx, y0 - fy, x1 - fx, y1 - fy
                    ra, rb = np.sqrt(ax * ax + ay * ay), np.sqrt(bx * bx + by * by)
                    if abs(ra - level) <= 1e-6 * level and abs(rb - level) <= 1e-6 * level:
                        # Both ends on the arc round the foot: as many even steps as keep each
                        # chord within tol of it (fewer, longer moves than halving).
                        theta = np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
                        steps = int(np.ceil(abs(theta) / arc_step))
                        out = _grow(out, m, steps)
                        phi = np.arctan2(ay, ax)
                        for q in range(1, steps):
                            out[m, 0] = fx + level * np.cos(phi + theta * q / steps)
                            out[m, 1] = fy + level * np.sin(phi + theta * q / steps)
                            m += 1
                        continue
                    cnx, cny = (sx - fx) / d, (sy - fy) / d
                    cx, cy = fx + level * cnx, fy + level * cny
                    if abs((cx - x0) * ly - (cy - y0) * lx) <= 0.5 * tol * np.sqrt(l2):
                        continue  # the chord follows the offset
                # In order: the first half, the new point, the second half.
                stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3] = cx, cy, x1, y1
                stack[top, 4], stack[top, 5], stack[top, 6], stack[top, 7] = cnx, cny, n1x, n1y
                kind[top], depth[top] = 0, dep + 1
                stack[top + 1, 0], stack[top + 1, 1] = cx, cy
                kind[top + 1] = 1
                stack[top + 2, 0], stack[top + 2, 1], stack[top + 2, 2], stack[top + 2, 3] = x0, y0, cx, cy
                stack[top + 2, 4], stack[top + 2, 5], stack[top + 2, 6], stack[top + 2, 7] = n0x, n0y, cnx, cny
                kind[top + 2], depth[top + 2] = 0, dep + 1
                top += 3
            i = j
            if i == first:
                break
        m = _start_at_sharpest(out, out_bounds[r], m)
        out_bounds[r + 1] = m
    return out[:m], out_bounds
