"""Bridges, overhangs and mid-air islands: found from the layer masks, printed or reported.

Parts are built from boxes and voxels with known geometry; the G-code is read back from disk.
"""
import math
import subprocess
import sys

import numpy as np
import pytest

import slicelab
from slicelab.gcode.writer import write_gcode
from slicelab.samples import box, concat, voxels
from slicelab.printing import PrintSettings, plan
from slicelab.printing.steps.overhangs import EDGE_MARGIN

S = dict(pixel_size=0.1, layer_height=0.25, first_layer_height=0.25, skirt_loops=0)


def bridge_part():
    """Two 5 x 10 x 6 mm pillars 20 mm apart, a 2 mm deck across them."""
    occ = np.zeros((30, 10, 8), bool)
    occ[:5, :, :6] = occ[25:, :, :6] = True
    occ[:, :, 6:] = True
    return voxels(occ)


def ramp(angle: float, height: float = 6.0):
    """A 10 x 10 mm block leaning `angle` degrees from the vertical towards +x."""
    shear = np.eye(4)
    shear[0, 2] = math.tan(math.radians(angle))
    return box((0, 0, 0), (10, 10, height)).transformed(shear)


@pytest.fixture(scope="module")
def bridged(tmp_path_factory):
    s = PrintSettings(**S, fan_speed=50, fan_below_layer_time=0)
    pp = plan(bridge_part(), s, workers=1)
    path = tmp_path_factory.mktemp("bridge") / "bridge.gcode"
    write_gcode(pp, path)
    return s, pp, path.read_text()


def test_a_deck_between_pillars_is_bridged_across_the_gap(bridged):
    s, pp, _ = bridged
    k = int(round(6.0 / s.layer_height))  # the deck's first layer, 6.0 - 6.25 mm
    lp = pp.layers[k]
    lines = [q for kind, q, _ in lp.rows({"bridge"})]
    assert lines, lp.kinds()
    seg = np.concatenate([np.diff(q, axis=0) for q in lines])
    length = np.hypot(*seg.T)
    along = np.abs(np.degrees(np.arctan2(seg[:, 1], seg[:, 0])))
    along = np.minimum(along, 180 - along)  # 0: along x, across the gap
    # Most of the bridge's length runs across the gap (the short links between lines do not).
    assert length[along < 10].sum() > 0.8 * length.sum()
    # The bridge lines cover the gap between the pillars, not the pillars' tops.
    pts = np.concatenate(lines)
    assert pts[:, 0].min() < 6 and pts[:, 0].max() > 24
    bridged_len = length.sum()
    assert bridged_len * s.line_width == pytest.approx(20 * 10, rel=0.25)  # the gap's area, about
    assert pp.overhangs["bridges"][k] == 1
    # Held on both sides: nothing reported as unsupported.
    assert [w["code"] for w in pp.warnings()] == []
    # The layers below and above the deck's first layer have no bridge.
    assert "bridge" not in pp.layers[k - 1].kinds() and "bridge" not in pp.layers[k + 2].kinds()


def test_bridge_gcode_has_its_type_speed_flow_and_fan(bridged):
    s, pp, text = bridged
    blocks = text.split(";TYPE:")
    bridge = [b for b in blocks if b.startswith("Bridge infill")]
    assert bridge
    for b in bridge:
        assert f"G1 F{60 * s.bridge_speed:.0f}" in b
    # The fan goes to full for each bridge and back to the layer's setting after it.
    fan = f"M106 S{int(255 * s.fan_speed / 100)}"
    for b in blocks:
        if b.startswith("Bridge infill"):
            b = b.split(";LAYER_CHANGE")[0]  # a layer's last block runs on to the next layer
            assert b.splitlines()[1] == "M106 S255"
            assert b.rstrip().endswith(fan), b[-200:]


@pytest.mark.parametrize("angle, unsupported", [(30, False), (45, False), (60, True)])
def test_only_steep_overhangs_are_reported(angle, unsupported):
    s = PrintSettings(**S)
    pp = plan(ramp(angle), s, workers=1)
    codes = [w["code"] for w in pp.warnings()]
    assert ("unsupported_overhang" in codes) == unsupported, (angle, pp.overhangs["area"].sum())
    # A leaning wall's sliver over nothing, held on one side, lies within its edge band: no bridge.
    assert pp.overhangs["bridges"].sum() == 0
    if unsupported:
        # Every layer above the first leans out by h tan(60) = 0.43 mm, beyond h tan(50) = 0.30 mm.
        assert (pp.overhangs["area"][1:] > 0).mean() > 0.9
        w = next(w for w in pp.warnings() if w["code"] == "unsupported_overhang")
        # The angle measured from the masks: the layer's reach beyond the one below, to a pixel.
        reach = pp.overhangs["angle"][1:]
        assert np.median(reach) == pytest.approx(60, abs=math.degrees(math.atan(0.1 / 0.25)))
        assert w["steepest_deg"] >= 55 and "up to" in w["message"]
        assert pp.overhangs["x"][1:][np.isfinite(pp.overhangs["x"][1:])].min() > 9.0  # on the leaning +x side


@pytest.mark.parametrize("pixel", [None, 0.1])
def test_the_threshold_holds_at_the_default_pixel_size(pixel):
    # A wall leaning `angle` steps out h tan(angle) a layer, and what lies beyond the h tan(50)
    # a 50-degree threshold lets it reach hangs: a strip that wide along the ramp's 10 mm, on
    # every layer but the first. The default pixel is half a line (0.2 mm), wider than the strip
    # at 60 degrees (0.11 mm): the pixels whose centres fall in it add up to its area all the same.
    h = 0.2
    for angle in (40, 45, 60, 70):
        pp = plan(ramp(angle), PrintSettings(layer_height=h, first_layer_height=h, skirt_loops=0, pixel_size=pixel),
                  workers=1)
        strip = max(h * math.tan(math.radians(angle)) - h * math.tan(math.radians(50)), 0.0)
        assert pp.overhangs["area"][1:].sum() == pytest.approx(strip * 10 * (len(pp.layers) - 1), rel=0.1, abs=1e-9), angle


def test_a_steeper_threshold_lets_the_ramp_hold():
    pp = plan(ramp(60), PrintSettings(**S, overhang_threshold=70), workers=1)
    assert pp.warnings() == []


def _tee():
    """A 4 x 20 mm stem 6 mm tall under a 20 x 20 x 2 mm bar: arms 8 mm out on each side, a T."""
    occ = np.zeros((20, 20, 8), bool)
    occ[8:12, :, :6] = True
    occ[:, :, 6:] = True
    return voxels(occ)


def test_a_cantilever_is_bridged_out_from_its_anchor_but_for_its_edges():
    s = PrintSettings(**S)
    pp = plan(_tee(), s, workers=1)
    k = int(round(6.0 / 0.25))
    assert pp.overhangs["bridges"][k] == 2  # each arm is bridged out from the stem
    seg = np.concatenate([np.diff(q, axis=0) for kind, q, _ in pp.layers[k].rows({"bridge"})])
    length = np.hypot(*seg.T)
    assert length[np.abs(seg[:, 1]) < 1e-6].sum() > 0.8 * length.sum()  # along x: out from the stem
    # Unheld: a band of the perimeters and EDGE_MARGIN along each arm's three free sides (the
    # arm hangs from a wall's reach, h tan(50), beyond the stem).
    b = s.n_perimeters * s.line_width + EDGE_MARGIN
    arm = 8 - 0.25 * math.tan(math.radians(50))
    assert pp.overhangs["area"][k] == pytest.approx(2 * (2 * b * arm + b * (20 - 2 * b)), rel=0.1)
    assert "unsupported_overhang" in [w["code"] for w in pp.warnings()]


def test_without_dont_support_bridges_a_cantilever_is_an_overhang_not_a_bridge():
    pp = plan(_tee(), PrintSettings(**S, dont_support_bridges=False), workers=1)
    k = int(round(6.0 / 0.25))
    assert pp.overhangs["bridges"][k] == 0
    # About the two arms' area, less the reach a wall holds and a pixel at each edge.
    assert pp.overhangs["area"][k] == pytest.approx(2 * 8 * 20, rel=0.1)
    assert "bridge" not in pp.layers[k].kinds()
    assert "unsupported_overhang" in [w["code"] for w in pp.warnings()]


def test_an_island_that_starts_in_mid_air_is_named():
    part = concat(box((0, 0, 0), (10, 10, 6)), box((15, 0, 3), (20, 5, 6)))
    pp = plan(part, PrintSettings(**S), workers=1)
    k = int(round(3.0 / 0.25))
    assert pp.overhangs["mid_air"][k] == 1 and pp.overhangs["mid_air"][:k].sum() == 0 and pp.overhangs["mid_air"][k + 1:].sum() == 0
    w = {w["code"]: w for w in pp.warnings()}
    assert w["mid_air"]["islands"] == 1 and w["mid_air"]["first_z"] == pytest.approx(3.25)


def test_slice_says_what_will_not_print(tmp_path):
    part = concat(box((0, 0, 0), (10, 10, 6)), box((15, 0, 3), (20, 5, 6)))
    f = tmp_path / "floating.stl"
    slicelab.save(part, f)
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(f), "-o", str(tmp_path / "o.gcode"),
                        "--pixel-size", "0.1", "--workers", "1"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "mid-air" in r.stderr and "z = 3.2" in r.stderr
    assert (tmp_path / "o.gcode").read_text().count(";LAYER_CHANGE") == 30


def test_bad_overhang_threshold_is_refused():
    with pytest.raises(ValueError, match="overhang_threshold"):
        PrintSettings(overhang_threshold=95)


def test_several_files_print_side_by_side_on_one_bed(tmp_path):
    a, b = tmp_path / "a.stl", tmp_path / "b.stl"
    slicelab.save(box((0, 0, 0), (20, 20, 4)), a)
    slicelab.save(box((-50, 30, 2), (-40, 60, 10)), b)  # 10 x 30 x 8, off in space
    out = tmp_path / "two.gcode"
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(a), str(b), "-o", str(out),
                        "--pixel-size", "0.1", "--workers", "1", "--skirt-loops", "0"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "2 parts on one bed" in r.stdout
    from test_plan import parse_gcode
    moves, zs, _, _ = parse_gcode(out.read_text())
    ext = np.array([(layer, x1, y1) for layer, z, x0, y0, x1, y1, e, word, role in moves if e > 0 and layer >= 0])
    assert len(zs) == 40  # both stand on the bed: the taller, 8 mm, sets the layers
    assert ext[:, 1].min() >= 0 and ext[:, 1].max() <= 250 and ext[:, 2].min() >= 0 and ext[:, 2].max() <= 210
    first = ext[ext[:, 0] == 0][:, 1:]
    gaps = [np.diff(np.sort(first[:, i])).max() for i in (0, 1)]
    assert max(gaps) >= 5.0 - 0.4  # two islands, the spacing between them (less a line width)
    top = ext[ext[:, 0] == 35][:, 1:]  # 7.0 - 7.2 mm: the second part only, upright as given
    size = np.sort(top.max(axis=0) - top.min(axis=0))
    assert np.allclose(size, [10 - 0.4, 30 - 0.4], atol=0.05)
    big = [tmp_path / f"big{i}.stl" for i in range(3)]
    for f in big:
        slicelab.save(box((0, 0, 0), (200, 150, 5)), f)
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", *map(str, big), "-o", str(tmp_path / "x.gcode")],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "need 3 beds" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "x.gcode").exists()


def mushroom():
    """A 4 x 4 mm stem 6 mm tall under a 16 x 16 x 2 mm cap: the cap hangs 6 mm out all round."""
    return concat(box((6, 6, 0), (10, 10, 6)), box((0, 0, 6), (16, 16, 8)))


def _support_rows(pp):
    return {k: [(kind, q) for kind, q, _ in lp.rows({"support", "support_interface"})]
            for k, lp in enumerate(pp.layers)}


def test_supports_hold_the_cap_of_a_mushroom(tmp_path):
    s = PrintSettings(**S, support="auto", dont_support_bridges=False)
    pp = plan(mushroom(), s, workers=1)
    rows = _support_rows(pp)
    cap = int(round(6.0 / s.layer_height))  # the cap's first layer
    top = cap - 1 - s.support_z_gap_layers  # the supports' last layer: one empty layer under the cap
    assert all(rows[k] for k in range(0, top + 1)) and not any(rows[k] for k in range(top + 1, len(rows)))
    stem = np.array([[6, 6], [10, 10]])
    for k in range(top + 1):
        pts = np.concatenate([q for _, q in rows[k]])
        # Under the cap, around the stem, never within the XY gap of it (less a support pixel).
        assert pts.min() >= -0.21 and pts.max() <= 16.21  # the cap's footprint, to a support pixel
        d = np.maximum(np.maximum(stem[0] - pts, pts - stem[1]), 0)
        assert np.hypot(*d.T).min() >= s.support_xy_gap - 0.25
        kinds = {kind for kind, _ in rows[k]}
        assert kinds == ({"support_interface"} if k > top - s.support_interface_layers else {"support"}), (k, kinds)
    # Sparse lines about support_spacing apart: the length laid is about area / spacing.
    # Sparse lines a gap of support_spacing apart, plus a line (along x on even layers): the length
    # laid along them is about the area over that pitch (the links along the outline left out).
    loops = [q for kind, q in rows[2] if kind == "support" and np.array_equal(q[0], q[-1])]
    seg = np.concatenate([np.diff(q, axis=0) for kind, q in rows[2] if kind == "support" and
                          not np.array_equal(q[0], q[-1])])
    along = np.abs(seg[:, 1]) < 1e-9
    area = 16 * 16 - (4 + 2 * s.support_xy_gap) ** 2
    assert np.abs(seg[along, 0]).sum() == pytest.approx(area / (s.support_spacing + s.line_width), rel=0.2)
    # Every layer of the column (those two apart draw the same lines): along x on even layers, y on odd.
    for k in range(top + 1 - s.support_interface_layers):
        d = np.concatenate([np.diff(q, axis=0) for kind, q in rows[k] if kind == "support" and
                            not np.array_equal(q[0], q[-1])])
        long = np.hypot(*d.T) > 4  # (the links between lines are a pitch, 2.9 mm, long)
        assert np.all(np.abs(d[long, 1 if k % 2 == 0 else 0]) < 1e-9), k
    # A sheath: a loop along the cap's outline and one around the stem's gap (none when asked).
    from slicelab.geometry.polygons import signed_area
    assert sorted(abs(signed_area(q)) for q in loops) == [pytest.approx((4 + 2 * s.support_xy_gap) ** 2, rel=0.25),
                                                          pytest.approx(16 * 16, rel=0.1)]
    bare = plan(mushroom(), PrintSettings(**S, support="auto", dont_support_bridges=False, support_sheath=False),
                workers=1)
    assert not [q for kind, q in _support_rows(bare)[2] if kind == "support" and np.array_equal(q[0], q[-1])]
    assert {k: len(v) for k, v in _support_rows(bare).items() if v} == \
        {k: len([r for r in v if not (r[0] == "support" and np.array_equal(r[1][0], r[1][-1]))])
         for k, v in rows.items() if v}
    assert pp.warnings() == []  # held
    # Supports reach a support pixel past the cap: the plan's extent (the SVGs' page) holds them.
    every = np.concatenate([q for lp in pp.layers for q in lp.paths])
    assert every.min() < 0 and np.all((every >= pp.extent[:2]) & (every <= pp.extent[2:]))
    path = tmp_path / "m.gcode"
    write_gcode(pp, path)
    text = path.read_text()
    assert ";TYPE:Support material\n" in text and ";TYPE:Support material interface\n" in text
    assert f"F{60 * s.support_speed:.0f}" in text


def test_supports_hold_only_the_edges_of_a_bridged_cap(tmp_path):
    s = PrintSettings(**S, support="auto")
    pp = plan(mushroom(), s, workers=1)
    cap = int(round(6.0 / s.layer_height))
    assert "bridge" in pp.layers[cap].kinds() and pp.overhangs["bridges"][cap] == 1
    rows = _support_rows(pp)
    top = cap - 1 - s.support_z_gap_layers
    assert all(rows[k] for k in range(0, top + 1)) and not any(rows[k] for k in range(top + 1, len(rows)))
    b = s.n_perimeters * s.line_width + EDGE_MARGIN
    for k in range(top + 1):
        pts = np.concatenate([q for _, q in rows[k]])
        edge = np.minimum(np.minimum(pts, 16 - pts).min(axis=1), 99)  # distance in from the cap's outline
        assert edge.min() >= -0.21 and edge.max() <= b + 0.41, (k, edge.max())  # a support pixel, a line
    # The band holds a loop on each side and lines across it: more than the two loops' lengths.
    path = tmp_path / "m.gcode"
    write_gcode(pp, path)
    text = path.read_text()
    assert ";TYPE:Support material\n" in text and ";TYPE:Bridge infill\n" in text
    length = sum(float(np.hypot(*np.diff(q, axis=0).T).sum()) for _, q in rows[2])
    assert length > 4 * 16 + 4 * (16 - 2 * b)  # a sheath around the band and across it
    assert pp.warnings() == []


@pytest.mark.parametrize("pixel", [0.1, 0.2])
def test_supports_only_where_needed(pixel):
    # At 0.2 mm pixels, what a 60-degree wall hangs beyond its reach (0.14 mm a layer) is a strip
    # thinner than a pixel: the supports stand under all of each layer's step, which join up.
    for angle, wanted in ((30, False), (60, True)):
        pp = plan(ramp(angle), PrintSettings(**{**S, "pixel_size": pixel}, support="auto"), workers=1)
        got = any(_support_rows(pp).values())
        assert got == wanted, angle
    # A mid-air block beside a tower: its supports reach down to the bed.
    part = concat(box((0, 0, 0), (10, 10, 6)), box((15, 0, 3), (20, 5, 6)))
    pp = plan(part, PrintSettings(**S, support="auto"), workers=1)
    first = np.concatenate([q for _, q in _support_rows(pp)[0]])
    assert first[:, 0].min() > 14 and first[:, 0].max() < 21


def test_supports_on_the_bed_only_skip_what_stands_on_the_part():
    # A shelf under the cantilever: "auto" stands supports on the shelf, "bed" makes none there.
    part = concat(box((0, 0, 0), (4, 10, 8)), box((4, 0, 6), (14, 10, 8)), box((0, 0, 0), (14, 10, 2)))
    auto = plan(part, PrintSettings(**S, support="auto"), workers=1)
    bed = plan(part, PrintSettings(**S, support="bed"), workers=1)
    assert any(_support_rows(auto).values()) and not any(_support_rows(bed).values())
    shelf_top = int(round(2.0 / 0.25))
    assert not any(_support_rows(auto)[k] for k in range(shelf_top))  # standing on the shelf
    assert "only on the bed" in bed.warnings()[0]["message"]


@pytest.mark.parametrize("pixel", [0.1, 0.2])
@pytest.mark.parametrize("angle", [30, 60])
def test_perimeters_over_nothing_print_as_overhang_perimeters(angle, pixel, tmp_path):
    # At 0.2 mm pixels (the default) a mask's pixel centre lies up to 0.14 mm from a point:
    # the layer below's section decides near its boundary.
    s = PrintSettings(**{**S, "pixel_size": pixel})
    pp = plan(ramp(angle), s, workers=1)
    pieces = [(k, kind, q) for k, lp in enumerate(pp.layers) for kind, q, _ in lp.pieces()]
    hang = [(k, q) for k, kind, q in pieces if kind == "overhang"]
    if angle == 30:  # steps of 0.14 mm a layer: the extrusions stand on the layer below
        assert not hang
        return
    # Steps of 0.43 mm: on every layer above the first, the outer wall's leaning side hangs, and
    # only it (x = 10 + z tan(60), less half a line).
    layers = {k for k, _ in hang}
    assert layers == set(range(1, len(pp.layers)))
    for k, q in hang:
        z = pp.layers[k].z - s.layer_height / 2
        assert np.allclose(q[:, 0], 10 + z * math.tan(math.radians(60)) - s.line_width / 2, atol=0.1)
    # The pieces of a loop join up: the table's loops are unchanged.
    for lp in pp.layers:
        assert sum(len(q) - 1 for _, q, _ in lp.pieces()) == sum(len(q) - 1 for q in lp.paths)
    path = tmp_path / "ramp.gcode"
    write_gcode(pp, path)
    blocks = [b for b in path.read_text().split(";TYPE:") if b.startswith("Overhang perimeter")]
    assert len(blocks) == len(pp.layers) - 1
    assert all(f"G1 F{60 * s.bridge_speed:.0f}" in b for b in blocks)


def test_center_places_the_part_and_is_checked(tmp_path):
    f = tmp_path / "cube.stl"
    slicelab.save(box((0, 0, 0), (20, 20, 2)), f)
    out = tmp_path / "c.gcode"
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(f), "-o", str(out), "--center", "40,150",
                        "--skirt-loops", "0", "--workers", "1"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    from test_plan import parse_gcode
    moves, *_ = parse_gcode(out.read_text())
    xy = np.array([(x1, y1) for layer, z, x0, y0, x1, y1, e, word, role in moves if e > 0 and layer >= 0])
    assert np.allclose(xy.min(axis=0), [30.2, 140.2], atol=0.05) and np.allclose(xy.max(axis=0), [49.8, 159.8],
                                                                                    atol=0.05)
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(f), "-o", str(out), "--center", "5,100"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "bed" in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_mid_air_counts_each_island_of_a_layer():
    # Three squares far apart on one layer (one tile): under the first lies material, under the
    # second a square that misses it, under the third nothing. Two islands start in mid-air.
    from layer_shapes import rect, section_of

    from slicelab.printing.steps.overhangs import layer_overhangs
    from slicelab.printing.grid.raster import rasterize
    layer = rasterize(section_of([rect(0, 0, 4, 4), rect(30, 0, 34, 4), rect(0, 40, 4, 44)]), 0.2)
    below = rasterize(section_of([rect(1, 1, 3, 3), rect(40, 0, 44, 4)]), 0.2).combined()
    assert len(layer.tiles) == 1 and len(layer.island_boxes) == 3
    ov = layer_overhangs(layer.combined(), below, 0.2, islands=layer)
    assert ov.mid_air == 2
    assert layer_overhangs(layer.combined(), None, 0.2, islands=layer).mid_air == 3
    on_all = rasterize(section_of([rect(1, 1, 3, 3), rect(31, 1, 33, 3), rect(1, 41, 3, 43)]), 0.2).combined()
    assert layer_overhangs(layer.combined(), on_all, 0.2, islands=layer).mid_air == 0


def test_grid_supports_hold_what_snug_ones_hold_and_keep_off_the_part():
    # Two caps a little apart on two stems: "snug" supports follow each cap's underside; "grid"
    # ones fill the 2 mm gap between them into one column (PrusaSlicer's grid style) and still hold
    # every overhang (coverage) without entering the part or its XY gap (containment).
    from slicelab.printing.supports import SUPPORTS
    part = concat(box((4, 4, 0), (6, 6, 4)), box((0, 0, 4), (10, 10, 5)),
                  box((16, 4, 0), (18, 6, 4)), box((12, 0, 4), (22, 10, 5)))
    got = {}
    for style in SUPPORTS:
        s = PrintSettings(**S, support="auto", support_style=style, dont_support_bridges=False)
        pp = plan(part, s, workers=1)
        rows = _support_rows(pp)
        # Points every 0.1 mm along the support lines of the two lowest layers.
        pts = np.concatenate([a + (b - a) * t[:, None] for k in range(2) for _, q in rows[k]
                              for a, b in zip(q[:-1], q[1:]) for t in [np.linspace(0, 1, 2 + int(np.hypot(*(b - a)) / 0.1))]])
        for stem in ((4, 6), (16, 18)):  # containment: never within the XY gap of a stem (less a pixel)
            dx = np.maximum(np.maximum(stem[0] - pts[:, 0], pts[:, 0] - stem[1]), 0)
            dy = np.maximum(np.maximum(4 - pts[:, 1], pts[:, 1] - 6), 0)
            # (the XY gap, less a support pixel where a loop cuts the gap's rounded corner)
            assert np.hypot(dx, dy).min() >= s.support_xy_gap - 0.25, style
        # coverage: support lines under both caps, up to their outlines (a support pixel)
        assert pts[:, 0].min() < 0.5 and pts[:, 0].max() > 21.5 and pts[:, 1].min() < 0.5 and pts[:, 1].max() > 9.5
        assert pts.min() >= -0.21 and pts[:, 0].max() <= 22.21 and pts[:, 1].max() <= 10.21  # under the caps
        between = (pts[:, 0] > 10.5) & (pts[:, 0] < 11.5)  # the gap between the caps
        got[style] = bool(between.any())
        assert pp.warnings() == [], style
    assert got == {"snug": False, "grid": True}
