"""Compiled text: a layer's G-code moves written as Python's ``%.3f`` / ``%.5f`` would, in one pass.

A layer's G-code is mostly lines ``G1 X.. Y.. E..``, some thousands of them, with a
few headers, travels and retractions between its paths. `layer_moves` writes a whole
layer (all but its first line) into one byte buffer in a compiled loop
(`slicelab.geometry.compiled`), byte for byte what `slicelab.gcode.writer` writes
with Python, and gives the layer's filament and time as the Python writer sums them:
`stream_seconds` is `slicelab.gcode.estimate.move_times` with numpy's pairwise
summation. `format_moves` writes the extrusion lines alone. Numbers are written by
`slicelab.files.numbers.put_number`, the one number formatter (exact rounding, ties to
even, Python's signs); a number it cannot write (not finite, or too large) is said.

See Also
--------
slicelab.gcode.writer.write_gcode : the writer that uses it.

"""
from __future__ import annotations

import numpy as np

from ..files.numbers import put_number, put_text
from ..geometry.compiled import njit

__all__ = ["format_moves", "fixed", "layer_moves", "stream_seconds", "warm"]

@njit(cache=True, nogil=True)
def format_moves(values, out, offsets):
    """Lines ``G1 X<x> Y<y> E<e>`` (3, 3 and 5 decimals) for rows 1.. of `values`.

    Parameters
    ----------
    values : (n, 3) float64 ndarray
        x, y and the filament of the move to each row's point (row 0 has no move).
    out : (m,) uint8 ndarray
        Room for the text: 80 bytes a row is enough for any number under 9e10.
    offsets : (n + 1,) int64 ndarray
        Filled: the line of row i is ``out[offsets[i]:offsets[i + 1]]`` (i >= 1).

    Returns
    -------
    int
        The text's length, or -1 if a value is not finite or too large to format here.
    """
    n = values.shape[0]
    pos = 0
    offsets[0] = 0
    if n > 0:
        offsets[1] = 0
    for i in range(1, n):
        out[pos] = 71  # "G1 X"
        out[pos + 1] = 49
        out[pos + 2] = 32
        out[pos + 3] = 88
        pos = put_number(out, pos + 4, values[i, 0], 3, 1000.0)
        if pos < 0:
            return -1
        out[pos] = 32  # " Y"
        out[pos + 1] = 89
        pos = put_number(out, pos + 2, values[i, 1], 3, 1000.0)
        if pos < 0:
            return -1
        out[pos] = 32  # " E"
        out[pos + 1] = 69
        pos = put_number(out, pos + 2, values[i, 2], 5, 100000.0)
        if pos < 0:
            return -1
        out[pos] = 10
        pos += 1
        offsets[i + 1] = pos
    return pos


@njit(cache=True, nogil=True)
def _block_sum(a, lo, n):
    """numpy's sum of a[lo:lo + n], n <= 128: eight accumulators (fewer than 8: in order)."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[lo + i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    while i < n - (n % 8):
        j = lo + i
        r0 += a[j]
        r1 += a[j + 1]
        r2 += a[j + 2]
        r3 += a[j + 3]
        r4 += a[j + 4]
        r5 += a[j + 5]
        r6 += a[j + 6]
        r7 += a[j + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@njit(cache=True, nogil=True)
def _pairwise(a, lo, n):
    """a[lo:lo + n].sum() as numpy sums a contiguous float64 array, bit for bit: halves (cut at a
    multiple of 8) summed apart and added, down to blocks of 128 or fewer (`_block_sum`). The
    halving is walked with a stack, not by recursion (a compiled module cannot call itself)."""
    if n <= 128:
        return _block_sum(a, lo, n)
    spans = np.empty((64, 3), np.int64)  # lo, n, next step (0: left half, 1: right half, 2: add)
    values = np.empty(64)
    top = nv = 0
    spans[0, 0], spans[0, 1], spans[0, 2] = lo, n, 0
    while top >= 0:
        s_lo, s_n, step = spans[top, 0], spans[top, 1], spans[top, 2]
        if s_n <= 128:
            values[nv] = _block_sum(a, s_lo, s_n)
            nv += 1
            top -= 1
            continue
        half = s_n // 2
        half -= half % 8
        if step == 2:
            values[nv - 2] = values[nv - 2] + values[nv - 1]
            nv -= 1
            top -= 1
            continue
        spans[top, 2] = step + 1
        top += 1
        if step == 0:
            spans[top, 0], spans[top, 1] = s_lo, half
        else:
            spans[top, 0], spans[top, 1] = s_lo + half, s_n - half
        spans[top, 2] = 0
    return values[0]


@njit(cache=True, nogil=True)
def _planned_times(D, length, feed, limits, m):
    """The times of the first `m` moves of `D` (rows dx, dy, dz, de, each of some length), a move
    after them in row m if there is one: `slicelab.gcode.estimate.move_times`'s model, its
    numpy operations one by one in the same order (so the same numbers, bit for bit)."""
    k = D.shape[0]
    cruise, acc, safe = np.empty(k), np.empty(k), np.empty(k)
    v = np.empty((k, 4))
    for i in range(k):  # each move's cruise, acceleration, safe speed and velocity
        inv = 1.0 / length[i]
        f = max(feed[i], limits[16] if D[i, 3] == 0 else limits[15])
        cut = np.inf
        top = np.inf
        for a in range(4):
            share = abs(D[i, a]) * inv
            speed = share * f
            if speed > 0:
                cut = min(cut, limits[7 + a] / speed)
            if share > 0:
                top = min(top, limits[3 + a] / share)
        c = f * min(cut, 1.0)
        cruise[i] = c
        if D[i, 0] == 0 and D[i, 1] == 0 and D[i, 2] == 0:
            base = limits[1]
        elif D[i, 3] > 0 and (D[i, 0] != 0 or D[i, 1] != 0):
            base = limits[0]
        else:
            base = limits[2]
        acc[i] = min(base, top)
        low = np.inf
        for a in range(4):
            v[i, a] = (D[i, a] * inv) * c
            if abs(v[i, a]) > limits[11 + a]:
                low = min(low, limits[11 + a])
        safe[i] = min(c, low)
    cap = np.empty(m + 1)
    cap[0] = safe[0] * safe[0]
    for j in range(1, k):  # Marlin's classic jerk at each junction
        pf, cf = cruise[j - 1], cruise[j]
        larger = pf > cf
        scale = cf / pf if larger else 1.0
        factor = np.inf
        for a in range(4):
            vx = v[j - 1, a] * scale
            vn = v[j, a]
            if vx > vn:
                jump = vx - vn if (vn > 0 or vx < 0) else max(vx, -vn)
            else:
                jump = vn - vx if (vn < 0 or vx > 0) else max(-vx, vn)
            factor = min(factor, limits[11 + a] / jump if jump > limits[11 + a] else 1.0)
        vj = (cf if larger else pf) * factor
        near = vj * 0.99
        if safe[j - 1] > near and safe[j] > near:
            vj = safe[j]
        if not pf > 1e-4:  # estimate.JUNCTION_FLOOR
            vj = safe[j]
        cap[j] = vj * vj
    if k == m:  # nothing follows: the last move ends at its safe speed
        cap[m] = safe[m - 1] * safe[m - 1]
    s = np.empty(m + 1)
    s[0] = 0.0
    for j in range(m):
        s[j + 1] = s[j] + 2 * acc[j] * length[j]
    fwd = np.empty(m + 1)
    low = np.inf
    for j in range(m + 1):  # forward pass: a junction is no faster than the one before allows
        low = min(low, cap[j] - s[j])
        fwd[j] = min(low + s[j], cap[j])
    u = np.empty(m + 1)
    low = np.inf
    for j in range(m, -1, -1):  # backward pass
        low = min(low, fwd[j] + s[j])
        u[j] = max(min(low - s[j], fwd[j]), 0.0)
    t = np.empty(m)
    for i in range(m):
        c, a, ln = cruise[i], acc[i], length[i]
        ff = c * c
        u0, u1 = min(u[i], ff), min(u[i + 1], ff)
        v0, v1 = np.sqrt(u0), np.sqrt(u1)
        peak2 = a * ln + 0.5 * (u0 + u1)
        if peak2 >= ff:
            t[i] = (c - v0) / a + (c - v1) / a + (ln - (2 * c * c - u0 - u1) / (2 * a)) / c
        else:
            t[i] = (2 * np.sqrt(peak2) - v0 - v1) / a
    return t


@njit(cache=True, nogil=True)
def stream_seconds(rows, start, limits, then):
    """The time of a stream of moves, as `slicelab.gcode.estimate.move_times` gives it and
    numpy sums it, bit for bit.

    Parameters
    ----------
    rows : (n, 5) float64 ndarray
        Each move's end x, y, z, filament and feed rate (mm/s), as written
        (ends rounded to 3 decimals and filament to 5 here, as the text rounds them).
    start : (3,) float64 ndarray
        The nozzle before the first move.
    limits : (17,) float64 ndarray
        The machine's limits (`slicelab.gcode.estimate.MachineLimits.vector`).
    then : (5,) float64 ndarray
        The move after the stream (dx, dy, dz, de, feed), whose junction with the last move
        ends the stream; none if it has no length or no feed rate.

    Returns
    -------
    float
    """
    n = rows.shape[0]
    if n == 0:
        return 0.0
    ends = np.empty((n, 3))
    for i in range(n):
        for c in range(3):
            ends[i, c] = np.rint(rows[i, c] * 1000.0) / 1000.0
    d = np.empty((n, 4))
    length = np.empty(n)
    m = 0
    for i in range(n):
        sx, sy, sz = (start[0], start[1], start[2]) if i == 0 else (ends[i - 1, 0], ends[i - 1, 1], ends[i - 1, 2])
        d[i, 0], d[i, 1], d[i, 2] = ends[i, 0] - sx, ends[i, 1] - sy, ends[i, 2] - sz
        d[i, 3] = np.rint(rows[i, 3] * 100000.0) / 100000.0
        ln = np.sqrt((d[i, 0] * d[i, 0] + d[i, 1] * d[i, 1]) + d[i, 2] * d[i, 2])
        length[i] = ln if ln > 0 else abs(d[i, 3])
        if length[i] > 0 and rows[i, 4] > 0:
            m += 1
    t = np.zeros(n)
    if m == 0:
        return 0.0
    nl = np.sqrt((then[0] * then[0] + then[1] * then[1]) + then[2] * then[2])
    nl = nl if nl > 0 else abs(then[3])
    more = 1 if (nl > 0 and then[4] > 0) else 0
    D = np.empty((m + more, 4))
    lengths = np.empty(m + more)
    feeds = np.empty(m + more)
    keep = np.empty(m, np.int64)
    j = 0
    for i in range(n):  # the moves of some length, in order
        if length[i] > 0 and rows[i, 4] > 0:
            for a in range(4):
                D[j, a] = d[i, a]
            lengths[j], feeds[j], keep[j] = length[i], rows[i, 4], i
            j += 1
    if more:
        for a in range(4):
            D[m, a] = then[a]
        lengths[m], feeds[m] = nl, then[4]
    times = _planned_times(D, lengths, feeds, limits, m)
    for j in range(m):
        t[keep[j]] = times[j]
    return _pairwise(t, 0, n)


@njit(cache=True, nogil=True)
def _number(out, pos, head, x, digits, scale, tail):
    """`head`, x with `digits` decimals (`put_number`), `tail`; -1 if x cannot be written here."""
    if pos < 0:
        return -1
    pos = put_number(out, put_text(out, pos, head), x, digits, scale)
    return -1 if pos < 0 else put_text(out, pos, tail)


@njit(cache=True, nogil=True)
def layer_moves(xy, counts, kind, width, numbers, speeds, perimeter, bridge, words, word_at, travel_f, retract_f,
                start, pos, text):
    """One layer's G-code after its first line: every path's ``;TYPE:``, ``;WIDTH:``, feed,
    travel (retracting and lifting beyond the minimum travel) and extrusion moves, byte for
    byte as `slicelab.gcode.writer` writes them with Python; the layer's filament and time.

    Parameters
    ----------
    xy : (n, 2) float64 ndarray
        The paths' points, path after path (bed coordinates).
    counts : (p,) int64 ndarray
        Points of each path (2 or more).
    kind : (p,) int64 ndarray
        Each path's kind: an index into `speeds`, `perimeter` and `word_at`.
    width : (n,) float64 ndarray
        Line width at each point.
    numbers : (37,) float64 ndarray
        z, layer height, filament fed per mm^3 of extrusion, a bridge strand's cross-section
        (mm^2, `slicelab.printing.PrintSettings.bridge_strand`), first layer
        (1 or 0), speed factor, small perimeter speed, minimum print speed, first layer
        speed, travel feed and retraction feed (mm/s, as written), retraction length, z
        lift, shortest travel that retracts, small perimeter length; then the machine's
        limits (17, `slicelab.gcode.estimate.MachineLimits.vector`) and the move after the
        layer (5: dx, dy, dz, de, feed; see `stream_seconds`).
    speeds : (k,) float64 ndarray
        Print speed of each kind.
    perimeter : (k,) bool ndarray
        Kinds slowed to the small perimeter speed when closed and short.
    bridge : int
        The bridge's kind (its paths are laid as round strands and set the fan full), -1 if none.
    words, word_at : uint8 ndarray, (k + 1,) int64 ndarray
        Kind i's ``;TYPE:`` line is ``words[word_at[i]:word_at[i + 1]]``.
    travel_f, retract_f : uint8 ndarrays
        The travel and retraction feed rates as written (F values).
    start : (3,) float64 ndarray
        Where the layer's first line (its z move) leaves the nozzle.
    pos : (3,) float64 ndarray
        The last extrusion's end (x, y) and 1, or 0 third before any extrusion.
    text : bool
        False: the filament and the time only.

    Returns
    -------
    out : (m,) uint8 ndarray
        The text is ``out[:size]``; a NUL "FAN" NUL marker stands where a bridge ends
        (the layer's own fan comes back).
    size : int
        -1 if a number cannot be written here (the caller then writes the layer with Python).
    filament, seconds : float
        As the Python writer sums them (`stream_seconds`).
    """
    z, h, k_e, strand = numbers[0], numbers[1], numbers[2], numbers[3]
    first, factor, small_speed, min_speed, first_speed = numbers[4] > 0, numbers[5], numbers[6], numbers[7], numbers[8]
    travel_feed, retract_feed, retract, lift, min_travel = numbers[9], numbers[10], numbers[11], numbers[12], numbers[13]
    small_length = numbers[14]
    n = xy.shape[0]
    p = len(counts)
    none = np.zeros(0, np.uint8)
    newline = np.array([10], np.uint8)
    fan_back = np.array([0, 70, 65, 78, 0], np.uint8)  # NUL FAN NUL
    fan_full = np.array([77, 49, 48, 54, 32, 83, 50, 53, 53, 10], np.uint8)  # M106 S255
    # The words as ASCII codes (a compiled module holds no byte strings): "G1 E", "G1 Z", "G0 X", "G1 X",
    # " Y", " E", and the ends " F<travel feed>" and " F<retraction feed>" with their newlines.
    g1_e, g1_z, g0_x, g1_x = (np.array([71, 49, 32, 69], np.uint8), np.array([71, 49, 32, 90], np.uint8),
                              np.array([71, 48, 32, 88], np.uint8), np.array([71, 49, 32, 88], np.uint8))
    sp_y, sp_e = np.array([32, 89], np.uint8), np.array([32, 69], np.uint8)
    travel_end = np.concatenate((np.array([32, 70], np.uint8), travel_f, newline))
    retract_end = np.concatenate((np.array([32, 70], np.uint8), retract_f, newline))
    width_head = np.array([59, 87, 73, 68, 84, 72, 58], np.uint8)  # ;WIDTH:
    width_tail = np.array([10, 71, 49, 32, 70], np.uint8)  # newline, G1 F
    begins = np.empty(p, np.int64)
    b = 0
    for i in range(p):
        begins[i] = b
        b += counts[i]
    m1 = max(n - 1, 0)
    seg, e, e5, inner = np.empty(m1), np.empty(m1), np.empty(m1), np.empty(m1)
    path = 0
    for j in range(n - 1):  # segment j joins points j and j + 1
        while path + 1 < p and begins[path + 1] <= j:
            path += 1
        seg[j] = np.hypot(xy[j + 1, 0] - xy[j, 0], xy[j + 1, 1] - xy[j, 1])
        wm = 0.5 * (width[j] + width[j + 1])
        inner[j] = 0.0 if j == begins[path] + counts[path] - 1 else wm  # one joining two paths counts nothing
        # A bridge's strand hangs round, not flattened by a layer below (`PrintSettings.bridge_strand`).
        e[j] = (strand if kind[path] == bridge else wm * h) * seg[j] * k_e
        e5[j] = np.rint(e[j] * 100000.0) / 100000.0
    rows = np.empty((n + 5 * p + 1, 5))  # every move: x, y, z, filament, feed
    rows[0, 0], rows[0, 1], rows[0, 2], rows[0, 3], rows[0, 4] = start[0], start[1], z, 0.0, travel_feed
    m = 1
    out = np.empty(80 * n + 400 * p + 200, np.uint8)
    size = 0
    filament = 0.0
    current = -1
    for i in range(p):  # over paths
        a = begins[i]
        b = a + counts[i]
        k = kind[i]
        if k != current:
            if current >= 0 and current == bridge:
                size = put_text(out, size, fan_back)
            size = put_text(out, size, words[word_at[k]:word_at[k + 1]])
            if k == bridge:  # bridge threads set in the air: full cooling
                size = put_text(out, size, fan_full)
            current = k
        x0, y0 = xy[a, 0], xy[a, 1]
        if i == 0:
            travel = np.hypot(x0 - pos[0], y0 - pos[1]) if pos[2] > 0 else np.inf
        else:
            travel = np.hypot(x0 - xy[a - 1, 0], y0 - xy[a - 1, 1])
        if travel > 1e-9:
            hop = travel > min_travel and retract > 0
            if hop:
                if text:
                    size = _number(out, size, g1_e, -retract, 5, 100000.0, retract_end)
                rows[m, 0], rows[m, 1], rows[m, 2] = rows[m - 1, 0], rows[m - 1, 1], rows[m - 1, 2]
                rows[m, 3], rows[m, 4] = -retract, retract_feed
                m += 1
                if lift > 0:
                    if text:
                        size = _number(out, size, g1_z, z + lift, 3, 1000.0, travel_end)
                    rows[m, 0], rows[m, 1], rows[m, 2] = rows[m - 1, 0], rows[m - 1, 1], z + lift
                    rows[m, 3], rows[m, 4] = 0.0, travel_feed
                    m += 1
            zt = z + lift if hop else z
            if text:
                size = _number(out, size, g0_x, x0, 3, 1000.0, sp_y)
                size = _number(out, size, none, y0, 3, 1000.0, travel_end)
            rows[m, 0], rows[m, 1], rows[m, 2], rows[m, 3], rows[m, 4] = x0, y0, zt, 0.0, travel_feed
            m += 1
            if hop:
                if lift > 0:
                    if text:
                        size = _number(out, size, g1_z, z, 3, 1000.0, newline)
                    rows[m, 0], rows[m, 1], rows[m, 2], rows[m, 3], rows[m, 4] = x0, y0, z, 0.0, travel_feed
                    m += 1
                if text:
                    size = _number(out, size, g1_e, retract, 5, 100000.0, retract_end)
                rows[m, 0], rows[m, 1], rows[m, 2], rows[m, 3], rows[m, 4] = x0, y0, z, retract, retract_feed
                m += 1
        speed = first_speed if first else speeds[k]
        if perimeter[k] and b - a > 3 and xy[a, 0] == xy[b - 1, 0] and xy[a, 1] == xy[b - 1, 1] \
                and _pairwise(seg, a, b - 1 - a) < small_length:
            speed = min(speed, small_speed)
        if factor < 1:
            speed = max(min(speed, min_speed), speed * factor)
        # The path's mean width: its segments (and the one joining it to the next) summed as
        # numpy's reduceat sums them, the first and then the rest pairwise.
        last = b if i + 1 < p else n - 1
        mean = (inner[a] + _pairwise(inner, a + 1, last - a - 1)) / max(counts[i] - 1, 1)
        feed = np.rint(60 * speed) / 60
        if text:
            size = _number(out, size, width_head, mean, 3, 1000.0, width_tail)
            size = _number(out, size, none, 60 * speed, 0, 1.0, newline)
        for j in range(a + 1, b):  # the extrusion moves to the path's points
            if text:
                size = _number(out, size, g1_x, xy[j, 0], 3, 1000.0, sp_y)
                size = _number(out, size, none, xy[j, 1], 3, 1000.0, sp_e)
                size = _number(out, size, none, e[j - 1], 5, 100000.0, newline)
            rows[m, 0], rows[m, 1], rows[m, 2], rows[m, 3], rows[m, 4] = xy[j, 0], xy[j, 1], z, e[j - 1], feed
            m += 1
        if size < 0:
            return out, -1, 0.0, 0.0
        filament += _pairwise(e5, a, b - 1 - a)
    if current >= 0 and current == bridge:
        size = put_text(out, size, fan_back)
    return out, size, filament, stream_seconds(rows[:m], start, numbers[15:32], numbers[32:37])


def fixed(values: np.ndarray) -> tuple[str, np.ndarray] | None:
    """The moves' text for rows 1.. of (n, 3) `values` and each row's line offsets, or None if a
    value cannot be formatted here (the caller formats those with Python).

    Examples
    --------
    >>> text, off = fixed(np.array([[0, 0, 0], [1.0625, -0.0001, 0.123456], [2.5, 10.0, 1e-6]]))
    >>> text[off[1]:off[3]]
    'G1 X1.062 Y-0.000 E0.12346\\nG1 X2.500 Y10.000 E0.00000\\n'
    >>> text[off[1]:off[3]] == "G1 X%.3f Y%.3f E%.5f\\n" % (1.0625, -0.0001, 0.123456) + \\
    ...     "G1 X%.3f Y%.3f E%.5f\\n" % (2.5, 10.0, 1e-6)
    True
    """
    v = np.ascontiguousarray(values, np.float64)
    n = len(v)
    out = np.empty(80 * max(n, 1), np.uint8)
    offsets = np.zeros(n + 1, np.int64)
    size = format_moves(v, out, offsets)
    if size < 0:
        return None
    return out[:size].tobytes().decode("ascii"), offsets


def warm() -> None:
    """Call the kernel once with the types the writer uses (see `slicelab.geometry.kernels.warm`).

    Examples
    --------
    >>> warm()
    """
    fixed(np.zeros((2, 3)))
    u8, i64 = np.zeros(1, np.uint8), np.zeros(2, np.int64)
    layer_moves(np.zeros((2, 2)), np.full(1, 2, np.int64), np.zeros(1, np.int64), np.zeros(2), np.zeros(37),
                np.zeros(1), np.zeros(1, np.bool_), -1, u8, i64, u8, u8, np.zeros(3), np.zeros(3), True)
