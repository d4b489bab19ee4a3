"""Clean paths and the G-code a printer can trust: simplification, patterns, skirt and brim, fan,
the print-time estimate and the bed, all read back from written files."""
import re
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import slicelab
from slicelab.gcode.writer import layer_fan, layer_texts, write_gcode
from slicelab.geometry.polygons import Polygon
from slicelab.samples import box, cube_with_hole
from slicelab.printing.config.bed import check_bed
from slicelab.gcode.estimate import MachineLimits, format_duration, machine_limits, move_times
from slicelab.printing.pipeline import layer_paths
from slicelab.printing.fill import PATTERNS, fill_pattern
from slicelab.printing.fill.gyroid import GYROID_LENGTH
from slicelab.printing.planner import PrintSettings, layer_bounds, plan
from slicelab.printing.roles import KINDS, STYLES
from slicelab.printing.steps.simplify import simplify_paths, simplify_rings
from layer_shapes import SHAPES, circle, section_of

shapely = pytest.importorskip("shapely")

FAST = dict(pixel_size=0.1, layer_height=0.4, first_layer_height=0.4, nozzle_diameter=0.6)  # coarse: fast


# ---------------------------------------------------------------------- reading G-code back
def read_gcode(text):
    """Every G0/G1 move of a file with its state: absolute XYZ (G90), relative E (M83), modal F.

    Returns a dict of arrays: start, end (n, 3), e, feed (mm/s), layer, type (the ;TYPE: in force),
    and the commands (M, G28...) in order with the layer they come in.
    """
    pos = np.zeros(3)
    feed = 0.0
    layer, role = -1, None
    start, end, e, feeds, layers, types, commands = [], [], [], [], [], [], []
    footer = {}
    for line in text.splitlines():
        if line.startswith(";LAYER:"):
            layer = int(line[7:])
        elif line.startswith(";TYPE:"):
            role = line[6:]
        elif line.startswith("; ") and " = " in line:
            key, _, value = line[2:].partition(" = ")
            footer[key] = value
        code = line.split(";")[0].strip()
        if not code:
            continue
        word, *args = code.split()
        assert word not in ("G91", "M82"), "relative XYZ or absolute E: this reader expects G90 and M83"
        if word not in ("G0", "G1"):
            commands.append((layer, code))
            continue
        a = {t[0]: float(t[1:]) for t in args}
        feed = a["F"] / 60 if "F" in a else feed
        new = np.array([a.get("X", pos[0]), a.get("Y", pos[1]), a.get("Z", pos[2])])
        if "E" not in a and np.array_equal(new, pos):
            continue  # a feed rate only
        start.append(pos)
        end.append(new)
        e.append(a.get("E", 0.0))
        feeds.append(feed)
        layers.append(layer)
        types.append(role)
        pos = new
    return dict(start=np.array(start), end=np.array(end), e=np.array(e), feed=np.array(feeds),
                layer=np.array(layers), type=np.array(types, dtype=object), commands=commands, footer=footer)


def _seconds(text):
    """A PrusaSlicer duration (``1h 2m 3s``) in seconds."""
    units = {"d": 86400, "h": 3600, "m": 60, "s": 1}
    return sum(int(n) * units[u] for n, u in re.findall(r"(\d+)([dhms])", text))


@pytest.fixture(scope="module")
def cube(tmp_path_factory):
    mesh = cube_with_hole(20.0, 5.0, 32)
    s = PrintSettings(pixel_size=0.1, layer_height=0.5, first_layer_height=0.5, max_layer_ratio=1.25, skirt_loops=2,
                      skirt_distance=4.0, brim_width=1.2, fan_off_layers=2, fan_speed=50)
    pp = plan(mesh, s, workers=1)
    out = tmp_path_factory.mktemp("g") / "cube.gcode"
    totals = write_gcode(pp, out)
    text = out.read_text()
    return mesh, s, pp, text, read_gcode(text), totals


# ---------------------------------------------------------------------- clean paths
def _check_simplified(original, simple, tol):
    assert len(simple) >= 2
    np.testing.assert_array_equal(simple[0], original[0])
    np.testing.assert_array_equal(simple[-1], original[-1])
    j = 0
    for p in simple:  # a subsequence of the original vertices, in order
        while j < len(original) and not np.array_equal(original[j], p):
            j += 1
        assert j < len(original)
        j += 1
    line = shapely.LineString(simple) if len(np.unique(simple, axis=0)) > 1 else shapely.Point(simple[0])
    d = shapely.distance(line, shapely.points(original))
    assert d.max() <= tol + 1e-9, (d.max(), tol)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.integers(2, 400), st.sampled_from([0.0125, 0.05, 0.3]))
def test_simplification_keeps_every_point_within_the_tolerance(seed, n, tol):
    rng = np.random.default_rng(seed)
    walk = np.cumsum(rng.normal(size=(n, 2)) * rng.choice([0.01, 0.1, 1.0]), axis=0)
    t = np.linspace(0, 2 * np.pi, n)
    wobbly = np.c_[20 * np.cos(t), 20 * np.sin(t)] + rng.normal(scale=0.005, size=(n, 2))
    closed = np.vstack([wobbly[:-1], wobbly[:1]])
    paths = [walk, wobbly, closed]
    out = simplify_paths(paths, tol)
    for p, q in zip(paths, out):
        _check_simplified(p, q, tol)
    if n > 300:  # vertices under 0.6 mm apart on a 20 mm circle: some go
        assert len(out[2]) < len(closed)


def test_simplification_keeps_corners_and_paths_that_double_back():
    # A path that runs 5 mm on and comes 3 mm back: the line's distance would drop the turn.
    back = np.array([[0, 0], [1, 0], [5, 0], [2, 0]], float)
    assert simplify_paths([back], 0.05)[0].tolist() == [[0, 0], [5, 0], [2, 0]]
    sq = np.array([[0, 0], [2, 0], [4, 0], [4, 4], [0, 4]], float)
    assert simplify_rings([sq], 0.01)[0].tolist() == [[0, 0], [4, 0], [4, 4], [0, 4]]
    # Gap-fill widths follow their vertices.
    pts, w = simplify_paths([np.array([[0, 0], [1, 0], [2, 0]], float)], 0.01, [np.array([0.3, 0.4, 0.5])])
    assert pts[0].tolist() == [[0, 0], [2, 0]] and w[0].tolist() == [0.3, 0.5]


@pytest.mark.parametrize("name", list(SHAPES))
def test_simplified_perimeters_stay_within_0025_of_exact_offsets(name):
    loops = SHAPES[name]
    lp = layer_paths(section_of(loops), PrintSettings(pixel_size=0.05))
    poly = shapely.Polygon(loops[0], loops[1:])
    exact = shapely.union_all([poly.buffer(-level, quad_segs=64).boundary for level in (0.2, 0.6)])
    ours = shapely.MultiLineString(lp.external_contour_segments + lp.internal_contour_segments)
    assert shapely.hausdorff_distance(ours, exact, densify=0.01) <= 0.025


def test_no_move_shorter_than_the_geometry_needs():
    # A disc of radius 30 sampled every 0.05 mm: its perimeters need chords of about
    # sqrt(8 r tol) = 1.7 mm to stay within 0.0125 mm of it.
    loops = [circle(30.0, 3770, (0.013, 0.021))]
    lp = layer_paths(section_of(loops), PrintSettings(pixel_size=0.05))
    seg = np.concatenate([np.hypot(*np.diff(q, axis=0).T) for _, q, _ in lp.ordered()])
    assert np.median(seg) > 1.0 and np.mean(seg < 0.1) < 0.01, (np.median(seg), np.mean(seg < 0.1))
    raw = layer_paths(section_of(loops), PrintSettings(pixel_size=0.05, gcode_resolution=0.0))
    assert sum(len(q) for _, q, _ in raw.ordered()) > 1.5 * sum(len(q) for _, q, _ in lp.ordered())


# ---------------------------------------------------------------------- infill patterns
def _disc_with_hole(r=40.0):
    t = np.linspace(0, 2 * np.pi, 256, endpoint=False)
    return Polygon(np.c_[r * np.cos(t), r * np.sin(t)], (np.c_[8 * np.cos(t) + 3, 8 * np.sin(t)][::-1],), 0)


@pytest.mark.parametrize("name", sorted(PATTERNS))
@pytest.mark.parametrize("density", [0.2, 0.5])
def test_pattern_covers_its_region_at_its_density_and_stays_inside(name, density):
    disc = _disc_with_hole()
    region = shapely.Polygon(disc.exterior, disc.holes)
    w = 0.4
    spacing = w / density
    # Gyroid's density holds over a period of z; a layer is within -6 / +23 %.
    zs = np.linspace(0, 2 * np.pi * spacing * GYROID_LENGTH, 8, endpoint=False)
    densities = []
    for k, z in enumerate(zs):
        lines = fill_pattern(name, [disc], spacing, 45.0, layer_index=k, z=z)
        pts = np.concatenate(lines)
        assert shapely.distance(region, shapely.points(pts)).max() <= 1e-6
        densities.append(sum(np.hypot(*np.diff(q, axis=0).T).sum() for q in lines) * w / region.area)
    assert np.mean(densities) == pytest.approx(density, rel=0.10), densities


def test_patterns_through_the_plan(tmp_path):
    mesh = cube_with_hole(12.0, 3.0, 32)
    for name in ("concentric", "gyroid", "triangles"):
        s = PrintSettings(**FAST, infill_pattern=name, solid_infill_below_area=0.0)  # (65 mm2 of infill)
        pp = plan(mesh, s, workers=1)
        write_gcode(pp, tmp_path / f"{name}.gcode")
        g = read_gcode((tmp_path / f"{name}.gcode").read_text())
        _extrusions_inside_the_material(mesh, s, g)
        sparse = g["type"] == "Internal infill"
        assert (g["e"][sparse] > 0).sum() > 100


def test_unknown_pattern_is_refused():
    with pytest.raises(ValueError, match="^infill_pattern must be one of concentric, gyroid, rectilinear, triangles"):
        PrintSettings(infill_pattern="honeycomb")


# ---------------------------------------------------------------------- the G-code read back
def _extrusions_inside_the_material(mesh, s, g):
    """Every extrusion but the skirt's lies in its layer's material widened by half a line."""
    height = float(mesh.bounds[1][2] - mesh.bounds[0][2])
    bounds = layer_bounds(height, s.layer_height, s.first_layer_height)
    offset = None
    moving = (g["e"] > 0) & (np.hypot(*(g["end"] - g["start"])[:, :2].T) > 0) & (g["type"] != "Skirt/Brim")
    checked = 0
    for layer in np.unique(g["layer"][moving]):
        sel = moving & (g["layer"] == layer)
        sec = slicelab.section(mesh, (0, 0, mesh.bounds[0][2] + bounds[layer].mean()), (0, 0, 1))
        region = sec.to_shapely().buffer(s.line_width / 2 + 1e-3)
        if offset is None:
            lo, hi = mesh.bounds
            offset = np.array(s.centre) - (lo[:2] + hi[:2]) / 2
        lines = shapely.linestrings(np.stack([g["start"][sel][:, :2], g["end"][sel][:, :2]], 1) - offset)
        assert shapely.covers(region, lines).all(), layer
        checked += int(sel.sum())
    assert checked > 100


def test_type_blocks_match_the_roles(cube):
    mesh, s, pp, text, g, _ = cube
    assert set(g["type"][g["e"] > 0]) <= {style.gcode_type for style in STYLES.values()}
    for k, lp in enumerate(pp.layers):  # the lengths each ;TYPE: block extrudes are its role's paths
        sel = (g["layer"] == k) & (g["e"] > 0) & (np.hypot(*(g["end"] - g["start"])[:, :2].T) > 0)
        length = np.hypot(*(g["end"] - g["start"])[sel, :2].T)
        written = {t: float(length[g["type"][sel] == t].sum()) for t in set(g["type"][sel])}
        planned = {}
        for kind, (_, q, _) in zip(lp.kinds(), lp.ordered()):
            t = STYLES[kind].gcode_type
            planned[t] = planned.get(t, 0.0) + float(np.hypot(*np.diff(q, axis=0).T).sum())
        assert written.keys() == planned.keys()
        for t in planned:
            assert written[t] == pytest.approx(planned[t], rel=1e-3, abs=0.01), (k, t)
    # Blocks come in the plan's order: the first layer starts with its skirt and brim.
    first = g["type"][(g["layer"] == 0) & (g["e"] > 0)]
    assert first[0] == "Skirt/Brim"
    assert set(KINDS) == set(STYLES)


def test_extrusions_lie_in_their_layers(cube):
    mesh, s, pp, text, g, _ = cube
    _extrusions_inside_the_material(mesh, s, g)


def test_skirt_and_brim_around_the_first_layer(cube):
    mesh, s, pp, text, g, _ = cube
    lp = pp.layers[0]
    assert len(lp.skirt_segments) == s.skirt_loops and len(lp.brim_segments) == round(s.brim_width / s.line_width)
    sel = (g["layer"] == 0) & (g["type"] == "Skirt/Brim") & (g["e"] > 0)
    lo, hi = mesh.bounds
    offset = np.array(s.centre) - (lo[:2] + hi[:2]) / 2
    sec = slicelab.section(mesh, (0, 0, lo[2] + 0.25), (0, 0, 1)).to_shapely()
    pts = np.concatenate([g["start"][sel][:, :2], g["end"][sel][:, :2]]) - offset
    d = shapely.distance(sec, shapely.points(pts))
    w = s.line_width
    brim = d < s.brim_width
    # Brim loops touch the part and reach brim_width; the skirt's inner edge is skirt_distance past it.
    assert d[brim].min() == pytest.approx(w / 2, abs=0.02) and d[brim].max() <= s.brim_width - w / 2 + 0.02
    skirt = d[~brim]
    assert skirt.min() == pytest.approx(s.brim_width + s.skirt_distance + w / 2, abs=0.02)
    assert skirt.max() <= s.brim_width + s.skirt_distance + s.skirt_loops * w + 0.02
    # The skirt prints first, then the brim, then the part.
    kinds = lp.kinds()
    assert kinds[:s.skirt_loops + 3] == ["skirt"] * s.skirt_loops + ["brim"] * 3
    assert pp.layers[1].skirt_segments == [] and "skirt" not in pp.layers[1].kinds()


def test_a_skirt_goes_round_outer_loops_that_cross_themselves_and_each_other():
    """Two figure-eight prisms overlapping (a self-intersecting scan's first layer): GEOS refuses to
    unite their outer loops as given; the skirt still goes round both, its inner edge at the skirt
    distance from the material."""
    import shapely

    from slicelab.samples import figure_eight_prism
    from slicelab.printing.steps.skirt import skirt_loops
    one = figure_eight_prism()
    two = slicelab.Mesh(np.concatenate([one.triangles, one.triangles + (4, 2, 0)]))
    sec = slicelab.section(two, (0, 0, 5), (0, 0, 1))
    with pytest.raises(shapely.errors.GEOSException):
        shapely.union_all([shapely.Polygon(q.exterior) for q in sec.polygons])
    skirt, brim = skirt_loops(sec, 0.4, loops=1, distance=3.0)
    assert len(skirt) == 1 and brim == []
    ring = shapely.LinearRing(skirt[0])
    material = shapely.union_all(shapely.make_valid([shapely.Polygon(q.exterior) for q in sec.polygons]))
    assert shapely.Polygon(ring).contains(material)
    assert shapely.distance(ring, material) == pytest.approx(3.0 + 0.2, abs=0.02)


def test_fan_and_temperatures_in_order(cube):
    mesh, s, pp, text, g, totals = cube
    cmds = [c for _, c in g["commands"]]
    heat = [cmds.index(c) for c in ("M140 S60", "M104 S210", "M190 S60", "M109 S210")]
    assert heat == sorted(heat) and heat[-1] < cmds.index("G28")
    # Off from the start; from layer fan_off_layers on at 50 % (S127, PrusaSlicer's truncation),
    # raised towards full as layers get quicker than fan_below_layer_time; off at the end. A
    # layer's own fan is set at its start (bridges turn it to full for their block only).
    seconds = totals["layer_seconds"]
    want = [layer_fan(k, t, s) for k, t in enumerate(seconds)]
    code = lambda f: f"M106 S{int(255 * f / 100)}" if f else "M107"  # noqa: E731
    changes = [(k, code(f)) for k, f in enumerate(want) if f != (want[k - 1] if k else 0)]
    layers = text.split(";LAYER_CHANGE")
    assert layers[0].rstrip().endswith("M107")
    at_start = [(k, line) for k, block in enumerate(layers[1:])
                for line in block.split(";TYPE:")[0].splitlines() if line.startswith(("M106", "M107"))]
    assert at_start == changes
    for k, block in enumerate(layers[1:]):  # a bridge's full fan ends with its block
        for b in block.split(";TYPE:")[1:]:
            if b.startswith("Bridge infill"):
                assert b.splitlines()[1] == "M106 S255"
                assert b.split(";LAYER")[0].rstrip().splitlines()[-1] == code(want[k]) or want[k] == 100
    assert layers[-1].split("; end")[1].count("M107") == 1  # off at the end
    assert want[:s.fan_off_layers] == [0] * s.fan_off_layers and min(want[s.fan_off_layers:]) >= 50
    end = cmds[cmds.index(changes[0][1]):]
    assert end.index("M104 S0") < end.index("M140 S0") < end.index("M84")


def test_fan_defaults_and_no_fan(tmp_path):
    pp = plan(box((0, 0, 0), (6, 6, 1.2)), PrintSettings(**FAST, fan_speed=0), workers=1)
    write_gcode(pp, tmp_path / "a.gcode")
    assert "M106" not in (tmp_path / "a.gcode").read_text()
    pp = plan(box((0, 0, 0), (6, 6, 1.2)), PrintSettings(**FAST), workers=1)
    write_gcode(pp, tmp_path / "b.gcode")
    g = read_gcode((tmp_path / "b.gcode").read_text())
    assert [(k, c) for k, c in g["commands"] if c.startswith("M106")] == [(1, "M106 S255")]


def test_quick_layers_are_slowed_and_cooled_more(tmp_path):
    # A 6 mm square tower: each layer prints in about a second at full speed.
    s = PrintSettings(**FAST, fan_speed=30, min_layer_time=8, fan_below_layer_time=30, min_print_speed=2,
                      small_perimeter_speed=100)  # (its small loops at their own speeds: layer time alone)
    pp = plan(box((0, 0, 0), (6, 6, 2.4)), s, workers=1)
    totals = write_gcode(pp, tmp_path / "t.gcode")
    seconds = totals["layer_seconds"]
    assert all(t >= 0.97 * s.min_layer_time for t in seconds[1:]), seconds
    fast = PrintSettings(**FAST, min_layer_time=0, small_perimeter_speed=100)
    first = write_gcode(plan(box((0, 0, 0), (6, 6, 2.4)), fast, workers=1), tmp_path / "f.gcode")
    assert seconds[0] == pytest.approx(first["layer_seconds"][0])  # the first layer keeps its own speed
    text = (tmp_path / "t.gcode").read_text()
    assert "M106 S255" in text and "M106 S76" not in text  # full, never the plain 30 %
    assert max(first["layer_seconds"][1:]) < 0.6 * s.min_layer_time  # so each was slowed, by 1.6x or more


def test_time_estimate_is_the_sum_of_the_moves_read_back(cube):
    mesh, s, pp, text, g, totals = cube
    limits = machine_limits(s)
    t = move_times(g["start"], g["end"], g["e"], g["feed"], limits)
    assert t.sum() == pytest.approx(totals["seconds"], rel=1e-6)
    line = g["footer"]["estimated printing time (normal mode)"]
    assert line == format_duration(totals["seconds"]) and abs(_seconds(line) - t.sum()) <= 0.5
    # More than moving at the feed rates all the way, less than stopping at every vertex.
    length = np.linalg.norm(g["end"] - g["start"], axis=1)
    length = np.where(length > 0, length, np.abs(g["e"]))
    assert (length / g["feed"]).sum() < t.sum() < (length / g["feed"] + g["feed"] / limits.travel).sum()
    # Filament used, as the footer says it.
    xy = np.hypot(*(g["end"] - g["start"])[:, :2].T) > 0
    used = g["e"][xy & (g["e"] > 0)].sum()
    assert float(g["footer"]["filament used [mm]"]) == pytest.approx(used, abs=0.01)
    assert float(g["footer"]["filament used [cm3]"]) == pytest.approx(used * s.filament_area / 1000, abs=0.01)
    assert used == pytest.approx(pp.filament_length, rel=1e-3)


# ---------------------------------------------------------------------- the bed and the settings
def test_too_big_a_part_is_refused():
    with pytest.raises(ValueError, match=r"^bed_size 250 x 210 mm: the part's footprint is 406 x 610 mm"):
        plan(box((0, 0, 0), (406, 610, 10)), PrintSettings())
    with pytest.raises(ValueError, match=r"^max_height 210 mm: the part is 250 mm tall"):
        plan(box((0, 0, 0), (10, 10, 250)), PrintSettings())
    with pytest.raises(ValueError, match=r"^bed_size 250 x 210 mm: .* with its skirt 212.8 x 212.8 mm"):
        plan(box((0, 0, 0), (200, 200, 10)), PrintSettings())
    plan_ok = plan(box((0, 0, 0), (200, 200, 0.4)), PrintSettings(skirt_loops=0, pixel_size=0.4), workers=1)
    assert len(plan_ok.layers) == 2
    with pytest.raises(ValueError, match=r"^bed_center \(20, 20\): the part centred there"):
        check_bed(box((0, 0, 0), (50, 50, 10)), PrintSettings(bed_center=(20, 20)))
    # The part is centred on the bed.
    pp = plan(box((0, 0, 0), (6, 6, 0.8)), PrintSettings(**FAST, bed_size=(200, 180)), workers=1)
    assert pp.offset[:2].tolist() == [97.0, 87.0]


@pytest.mark.parametrize("field, value", [
    ("gcode_resolution", -0.1), ("gcode_resolution", 0.5), ("acceleration", -1), ("jerk", -1),
    ("machine_max_acceleration_travel", 0), ("machine_max_feedrate_z", 0), ("machine_max_jerk_e", -0.1),
    ("machine_limits_usage", "emit"),
    ("fan_speed", 101), ("fan_off_layers", -1), ("fan_off_layers", 1.5), ("skirt_loops", -2),
    ("skirt_distance", -1), ("brim_width", float("nan")), ("bed_size", (250,)), ("bed_size", (0, 10)),
    ("max_height", 0), ("bed_center", (300, 10)), ("infill_pattern", "lines")])
def test_bad_settings_name_the_field(field, value):
    with pytest.raises(ValueError, match=f"^{field} "):
        PrintSettings(**{field: value})


def test_cli_slice_with_the_new_settings(tmp_path, data_dir):
    out = tmp_path / "c.gcode"
    stl = str(data_dir / "cube_with_hole.stl")
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", stl, "-o", str(out), "--layer-height", "2",
                        "--nozzle-diameter", "2.5", "--line-width", "2",
                        "--pixel-size", "0.2", "--workers", "1", "--infill-pattern", "gyroid", "--skirt-loops", "2",
                        "--brim-width", "1", "--fan-speed", "40", "--fan-off-layers", "3", "--bed-size", "220x220",
                        "--fan-below-layer-time", "0",
                        "--acceleration", "1500", "--gcode-resolution", "0.02"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    text = out.read_text()
    assert "; infill_pattern = gyroid" in text and "; bed_size = (220.0, 220.0)" in text
    assert "M106 S102" in text and ";TYPE:Skirt/Brim" in text
    assert "; estimated printing time (normal mode) = " in text
    for bad, flag in ((["--bed-size", "10x10"], "--bed-size 10 x 10 mm: the part's footprint is"),
                      (["--max-height", "5"], "--max-height 5 mm: the part is"),
                      (["--fan-speed", "300"], "--fan-speed must be"),
                      (["--bed-size", "ten"], "--bed-size must be"),
                      (["--skirt-loops", "-1"], "--skirt-loops must be")):
        r = subprocess.run([sys.executable, "-m", "slicelab", "slice", stl, "-o", str(out), *bad],
                           capture_output=True, text=True)
        assert r.returncode == 2 and r.stderr.count("\n") == 1 and flag in r.stderr, r.stderr


@pytest.mark.parametrize("seam", ["rear", "aligned", "nearest", "random"])
def test_seams(seam):
    from slicelab.samples import sphere
    pp = plan(sphere(10.0, 24, 48), PrintSettings(**FAST, seam_position=seam), workers=1)
    starts = []
    for lp in pp.layers:
        for kind, q, _ in lp.rows({"external", "hole", "internal"}):
            np.testing.assert_array_equal(q[0], q[-1])  # loops closed at their seam
            if kind == "external":
                starts.append(q[0])
                if seam == "rear":  # the rearmost vertex, of every loop
                    assert q[0, 1] >= q[:, 1].max() - 1e-9
    starts = np.array(starts)
    step = np.hypot(*np.diff(starts, axis=0).T)
    if seam == "aligned":
        # Each seam is the vertex nearest the one below: a seam line up the sphere, a step at most
        # about the distance between the sphere's vertices on the layer.
        assert np.median(step) < 1.0 and starts[:, 1].mean() > 5.0
    if seam == "random":
        # Spread round the sphere: seams point every way from its axis (the mean of their unit
        # directions is short), each on its loop, none carried up from the layer below.
        u = starts - starts.mean(axis=0)
        u /= np.linalg.norm(u, axis=1, keepdims=True)
        assert np.linalg.norm(u.mean(axis=0)) < 0.3 and np.median(step) > 3.0


def test_random_seams_are_the_same_in_any_order_and_by_any_number_of_workers():
    # Drawn per layer from a seed of the layer's number, not from a stream the runs share.
    from slicelab.samples import sphere
    s = PrintSettings(**FAST, seam_position="random")
    one, two = plan(sphere(10.0, 24, 48), s, workers=1), plan(sphere(10.0, 24, 48), s, workers=2)
    for a, b in zip(one.layers, two.layers, strict=True):
        for (ka, qa, _), (kb, qb, _) in zip(a.rows({"external"}), b.rows({"external"}), strict=True):
            np.testing.assert_array_equal(qa, qb)


def test_hole_walls_are_their_own_kind_printed_as_external_perimeters(cube):
    mesh, s, pp, text, g, totals = cube
    lp = pp.layers[5]
    holes = [q for _, q, _ in lp.rows({"hole"})]
    assert len(holes) == 1
    r = np.hypot(*(holes[0] - [10, 10]).T)  # the hole of radius 5, its wall half a line inside the part
    assert np.allclose(r, 5 + s.line_width / 2, atol=0.02)
    # In G-code: PrusaSlicer's word for an outer wall, at the external perimeter speed.
    i = text.index(";LAYER:5\n")
    layer = text[i:text.index(";LAYER:6\n")]
    assert layer.count(";TYPE:External perimeter") == 2
    assert f"F{60 * s.external_perimeter_speed:.0f}" in layer
    # The hole's loops are small perimeters (shorter than a 6.5 mm circle): slowed to cool.
    hole_block = [b for b in layer.split(";TYPE:")[1:] if b.startswith("External perimeter")][0]
    assert f"G1 F{60 * s.small_perimeter_speed:.0f}" in hole_block


def test_gcode_formatted_by_a_pool_is_the_serial_file(tmp_path):
    # Each layer is formatted from the nozzle position the layer before leaves: the pool's file,
    # read back from disk, is the serial one byte for byte, and its totals are the same.
    p = plan(cube_with_hole(), PrintSettings(layer_height=0.2, min_layer_time=30), workers=1)
    assert len(p.layers) > 2 * 25  # more than one run of layers for the pool
    one, two = tmp_path / "serial.gcode", tmp_path / "pool.gcode"
    t1, t2 = write_gcode(p, one, workers=1), write_gcode(p, two, workers=2)
    assert one.read_bytes() == two.read_bytes()
    assert t1["seconds"] == t2["seconds"] and t1["filament"] == t2["filament"]


@pytest.mark.parametrize("workers", [1, 2])
def test_gcode_formatted_by_the_planners_workers_is_the_writers_file(tmp_path, workers):
    # The planner's workers format each layer whose start their run of layers tells (layer_texts);
    # the writer takes those blocks and formats the others: the file read back from disk is the
    # one it writes alone, and so are its totals.
    mesh, s = cube_with_hole(), PrintSettings(layer_height=0.2, min_layer_time=30, skirt_loops=1)
    alone = plan(mesh, s, workers=workers)
    ahead = plan(mesh, s, workers=workers, layer_text=layer_texts)
    n = len(ahead.layers)
    assert not alone.texts and n - (n + 19) // 20 <= len(ahead.texts) < n  # all but each run's first
    one, two = tmp_path / "alone.gcode", tmp_path / "ahead.gcode"
    t1, t2 = write_gcode(alone, one), write_gcode(ahead, two)
    assert one.read_bytes() == two.read_bytes() and t1 == t2
    # A block formatted from another start than the writer finds is not taken.
    k = max(ahead.texts)
    (pos, at), _ = ahead.texts[k]
    ahead.texts[k] = ((pos, at + 0.5), ("G1 X0 Y0 ; formatted from elsewhere\n", 0.0, 0.0))
    assert write_gcode(ahead, tmp_path / "stale.gcode") == t1
    assert (tmp_path / "stale.gcode").read_bytes() == one.read_bytes()
    # Supports are added to the layers after the workers: nothing is formatted ahead then.
    assert plan(box((0, 0, 0), (4, 4, 1)), PrintSettings(support="auto"), workers=1, layer_text=layer_texts).texts == {}


def _without_fan(text: str) -> str:
    """A layer's text without its fan commands (the file sets the layer's fan, the oracle leaves a marker)."""
    return "".join(line for line in text.splitlines(True) if not line.startswith(("M106", "M107")))


@pytest.mark.parametrize("case", ["cube", "bridge", "slowed"])
def test_compiled_writer_writes_the_python_bytes(tmp_path, monkeypatch, case, data_dir):
    # The compiled writer and the Python writer, read back from disk: the same bytes (travels,
    # retractions and lifts, bridges and their fan, skirt and brim, small perimeters, layers slowed
    # for their minimum time), the same time and filament.
    if case == "cube":
        s = PrintSettings(pixel_size=0.1, layer_height=0.3, skirt_loops=2, brim_width=1.2, z_lift=0.4)
        p = plan(cube_with_hole(20.0, 5.0, 32), s, workers=1)
    elif case == "bridge":
        p = plan(slicelab.load(data_dir / "bridge.stl"), PrintSettings(layer_height=0.3, pixel_size=0.15), workers=1)
        assert any("bridge" in lp.kind for lp in p.layers)
    else:
        s = PrintSettings(**FAST, min_layer_time=8, min_print_speed=2, fan_below_layer_time=30)
        p = plan(box((0, 0, 0), (6, 6, 2.4)), s, workers=1)
    import slicelab.gcode.layer_inputs as layer_inputs
    from slicelab.gcode.writer import layer_starts, next_move
    from gcode_oracle import layer_block
    runs = []
    layer_moves = layer_inputs.layer_moves
    monkeypatch.setattr(layer_inputs, "layer_moves", lambda *a: runs.append(a[4][5]) or layer_moves(*a))
    fast = tmp_path / "compiled.gcode"
    t1 = write_gcode(p, fast, workers=1)
    assert len(runs) >= len(p.layers)  # every layer went through the compiled pass
    if case == "slowed":
        assert min(runs) < 1  # some at a slower speed (its factor)
    # The oracle's layers, each from the start the writer found, in the file read back.
    text = fast.read_text()
    starts = layer_starts(p)
    seconds = []
    for k, (lp, h) in enumerate(zip(p.layers, p.heights)):  # over layers
        block, t, used = layer_block(k, lp, float(h), p.settings, p.offset, *starts[k], next_move(p, k))
        head = text.index(f";LAYER:{k}\n")
        body = text[text.index("\n", head) + 1:]
        body = body[:body.index(";LAYER_CHANGE")] if ";LAYER_CHANGE" in body else body[:body.index("; end")]
        assert _without_fan(body) == _without_fan(block.replace("\x00FAN\x00", "")), k
        assert body.count("M106 S255") >= block.count("M106 S255")  # (bridges: the fan full)
        seconds.append(t)
    assert t1["layer_seconds"] == seconds


def test_compiled_writer_says_what_it_cannot_write():
    # A coordinate beyond what it formats (or not finite): no text (the writer refuses the layer).
    from slicelab.gcode.layer_inputs import BRIDGE, KIND_INDEX, PERIMETER_KINDS, WORD_AT, WORD_BYTES
    from slicelab.gcode.text_kernels import layer_moves
    f = np.frombuffer(b"9000", np.uint8).copy()
    for bad in (1e20, np.nan, np.inf):
        xy = np.array([[0.0, 0.0], [bad, 1.0]])
        out, size, _, _ = layer_moves(xy, np.array([2]), np.array([KIND_INDEX["external"]]), np.full(2, 0.4),
                                      np.r_[0.2, 0.2, 0.05, np.zeros(34)], np.full(len(STYLES), 50.0),
                                      PERIMETER_KINDS, BRIDGE, WORD_BYTES, WORD_AT, f, f, np.zeros(3), np.zeros(3), True)
        assert size == -1


@pytest.mark.parametrize("seed", range(4))
def test_compiled_stream_time_is_move_times_summed(seed):
    # Random streams (corners, straight runs, z moves, retractions and primes, moves of no length,
    # more than 128 moves: numpy's pairwise sum): the compiled time is numpy's, bit for bit.
    from slicelab.gcode.text_kernels import stream_seconds
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 3000))
    rows = np.c_[np.cumsum(rng.normal(0, 3, (n, 2)), axis=0), np.repeat(rng.integers(1, 4, n), 1) * 0.2,
                 rng.exponential(0.05, n), rng.choice([5.0, 25.0, 60.0, 150.0], n)]
    rows[rng.random(n) < 0.1, :2] = np.nan  # then the point before: a move of no length
    for i in np.flatnonzero(np.isnan(rows[:, 0])):
        rows[i, :2] = rows[i - 1, :2] if i else 0.0
    rows[rng.random(n) < 0.05, 3] *= -20  # retractions
    start = np.array([1.0, 2.0, 0.2])
    ends = np.round(rows[:, :3], 3)
    starts = np.vstack([start, ends[:-1]])
    limits = MachineLimits(extruding=1250.0, retracting=900.0, travel=2000.0, max_jerk=(9.0, 8.0, 0.3, 2.0),
                           max_feedrate=(500.0, 120.0, 12.0, 60.0), max_acceleration=(9000.0, 1000.0, 200.0, 5000.0))
    then = [(0.0, 0.0, 0.2, 0.0, 150.0), (0.0, 0.0, 0.0, -0.8, 35.0), (3.0, 4.0, 0.0, 0.0, 0.0)][seed % 3]
    want = float(move_times(starts, ends, np.round(rows[:, 3], 5), rows[:, 4], limits, then=then).sum())
    assert stream_seconds(rows, start, limits.vector(), np.array(then)) == want


def test_travel_lifts_stay_under_the_printer_height(tmp_path):
    # A part whose top is the printer's height: the lift before a travel on its last layers is cut
    # to what is left, by both writers (before, they lifted the nozzle 0.2 mm past the top).
    import re

    from slicelab.gcode import write_gcode
    from slicelab.samples import sphere
    from slicelab.printing import PrintSettings, plan
    ball = sphere(8)
    p = plan(ball, PrintSettings(max_height=16.0), workers=1)
    write_gcode(p, tmp_path / "b.gcode", workers=1)
    zs = [float(z) for z in re.findall(r"^G1 Z([\d.]+)", (tmp_path / "b.gcode").read_text(), flags=re.M)]
    assert max(zs) == pytest.approx(16.0) and p.z[-1] == pytest.approx(16.0)   # (16.2 before)


def test_triangle_infill_lays_three_directions_meeting_in_a_grid():
    # Three families 60 degrees apart, through one lattice: where two lines cross, a line of the
    # third family passes too (the triangles' corners), and the pattern is the same on every layer.
    sq = Polygon(np.array([[0, 0], [40, 0], [40, 40], [0, 40]], float) + 0.3, (), 0)
    lines = fill_pattern("triangles", [sq], 2.0, 0.0, layer_index=0)
    assert [q.tolist() for q in lines] == [q.tolist() for q in fill_pattern("triangles", [sq], 2.0, 0.0,
                                                                             layer_index=1, z=7.0)]
    seg = np.concatenate([np.stack([q[:-1], q[1:]], 1) for q in lines])
    d = seg[:, 1] - seg[:, 0]
    long = np.hypot(*d.T) > 10
    assert all(len(q) == 2 for q in lines)   # straight lines, not linked along the boundary
    angles = np.round(np.degrees(np.arctan2(d[long, 1], d[long, 0])) % 180, 6)
    assert sorted(set(angles.tolist())) == [0.0, 60.0, 120.0]
    # A family is lines k * 6 mm (3 spacings) from the origin, along its direction: a point on two
    # families' lines is on the third's.
    normals = {a: np.array([-np.sin(np.radians(a)), np.cos(np.radians(a))]) for a in (0.0, 60.0, 120.0)}
    p = np.linalg.solve(np.stack([normals[0.0], normals[60.0]]), [6.0 * 2, 6.0 * 1])
    offset = p @ normals[120.0] / 6.0
    assert abs(offset - round(offset)) < 1e-9


def test_aligned_seams_run_straight_up_across_runs_of_layers_and_hide_in_concave_corners():
    # Two tubes and an L-shaped prism, 45 layers: the planner restarts the nozzle at every run of
    # 20 layers (layers 20 and 40 start runs), and the seams, found by one pass up the whole part
    # before planning, do not jog there. The L's seam sits in its concave corner.
    from slicelab.samples import concat, ring_prism, voxels
    occ = np.zeros((2, 2, 1), bool)
    occ[0, :, 0] = occ[1, 0, 0] = True
    ell = voxels(occ, (5.0, 5.0, 9.0))  # an L: 10 x 10 less the square (5..10, 5..10)
    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    circle = np.c_[np.cos(t), np.sin(t)]
    part = concat(ell, ring_prism(circle * 4 + [20, 5], circle * 2 + [20, 5], 0, 9),
                  ring_prism(circle * 3 + [32, 5], circle * 1.5 + [32, 5], 0, 9))
    s = PrintSettings(**{**FAST, "layer_height": 0.2, "first_layer_height": 0.2})
    pp = plan(part, s, workers=1)
    seams = [np.array([q[0] for kind, q, _ in lp.rows({"external"})]) for lp in pp.layers]
    assert len(pp.layers) == 45 and all(len(x) == 3 for x in seams)
    for k in range(1, 45):  # every seam within 0.1 mm of one of the layer below
        d = np.hypot(*(seams[k][:, None, :] - seams[k - 1][None, :, :]).transpose(2, 0, 1)).min(axis=1)
        assert d.max() < 0.1, (k, d)
    # The L's seam (the leftmost): on the arc the outer perimeter makes round the notch's corner
    # (5, 5), half a line from it.
    ell_seams = np.array([x[np.argmin(x[:, 0])] for x in seams])
    assert np.abs(np.hypot(*(ell_seams - [5.0, 5.0]).T) - s.line_width / 2).max() < 0.01
