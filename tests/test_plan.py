"""Whole-part planning and G-code (issue 6): the written G-code is parsed back and checked."""
import subprocess
import sys

import numpy as np
import pytest

import slicelab
from slicelab.gcode.writer import write_gcode
from slicelab.gcode.layer_svgs import write_svgs
from slicelab.printing.planner import PrintSettings, layer_bounds, plan
from slicelab.viz.layers import preview_png
from slicelab.samples import cube_with_hole, voxels

shapely = pytest.importorskip("shapely")

FAST = dict(pixel_size=0.1, layer_height=0.4, first_layer_height=0.4, nozzle_diameter=0.6)  # coarse: fast


def parse_gcode(text):
    """A small G-code reader: absolute XYZ, relative E (M83), layers and ;TYPE: roles.

    Returns the moves as a structured list: (layer, z, x0, y0, x1, y1, e, kind, code, type).
    """
    x = y = z = 0.0
    layer, role, offset = -1, None, np.zeros(3)
    relative_e = False
    moves, zs, heights = [], [], []
    for line in text.splitlines():
        if line.startswith("; slicelab offset = "):
            offset = np.array([float(v) for v in line.split("=")[1].split(",")])
        elif line.startswith(";LAYER:"):
            layer = int(line[7:])
        elif line.startswith(";Z:"):
            zs.append(float(line[3:]))
        elif line.startswith(";HEIGHT:"):
            heights.append(float(line[8:]))
        elif line.startswith(";TYPE:"):
            role = line[6:]
        code = line.split(";")[0].strip()
        if not code:
            continue
        word = code.split()[0]
        if word == "M83":
            relative_e = True
        elif word == "M82":
            relative_e = False
        if word not in ("G0", "G1"):
            continue
        args = dict((t[0], float(t[1:])) for t in code.split()[1:])
        nx, ny, nz = args.get("X", x), args.get("Y", y), args.get("Z", z)
        e = args.get("E", 0.0)
        assert relative_e, "this reader expects relative extrusion"
        moves.append((layer, nz, x, y, nx, ny, e, word, role))
        x, y, z = nx, ny, nz
    return moves, np.array(zs), np.array(heights), offset


@pytest.fixture(scope="module")
def cube_plan(tmp_path_factory):
    mesh = cube_with_hole(8.0, 2.0, 32)
    settings = PrintSettings(**FAST, solid_infill_below_area=0.0)  # (its 36 mm2 of infill stay sparse)
    pp = plan(mesh, settings, workers=1)
    out = tmp_path_factory.mktemp("g") / "cube.gcode"
    write_gcode(pp, out)
    return mesh, settings, pp, out.read_text()


def test_layer_heights_and_count(cube_plan):
    mesh, s, pp, text = cube_plan
    _, zs, heights, _ = parse_gcode(text)
    expected = layer_bounds(8.0, s.layer_height, s.first_layer_height)
    assert len(zs) == len(pp.layers) == len(expected) == 20  # 0.4 mm layers in 8 mm
    np.testing.assert_allclose(zs, s.first_layer_height + s.layer_height * np.arange(len(zs)), atol=5e-4)
    np.testing.assert_allclose(heights, s.layer_height, atol=5e-4)


def test_first_layer_height_is_its_own():
    s = PrintSettings(pixel_size=0.1, layer_height=0.25, first_layer_height=0.4, nozzle_diameter=0.6)
    b = layer_bounds(2.0, s.layer_height, s.first_layer_height)
    np.testing.assert_allclose(b[:, 1], [0.4, 0.65, 0.9, 1.15, 1.4, 1.65, 1.9])  # middles inside
    pp = plan(slicelab.samples.box((0, 0, 0), (4, 4, 2)), s, workers=1)
    np.testing.assert_allclose(pp.heights, np.diff(np.concatenate([[0], b[:, 1]])))


def test_every_extrusion_lies_in_its_layer(cube_plan):
    mesh, s, pp, text = cube_plan
    moves, zs, _, offset = parse_gcode(text)
    bounds = layer_bounds(8.0, s.layer_height, s.first_layer_height)
    regions = {}
    checked = 0
    for layer, z, x0, y0, x1, y1, e, word, role in moves:
        if e <= 0 or (x0 == x1 and y0 == y1) or role == "Skirt/Brim":
            continue
        if layer not in regions:
            mid = bounds[layer].mean() - offset[2]
            sec = slicelab.section(mesh, (0, 0, mid), (0, 0, 1))
            regions[layer] = sec.to_shapely().buffer(s.line_width / 2 + 1e-3)
        line = shapely.LineString([(x0 - offset[0], y0 - offset[1]), (x1 - offset[0], y1 - offset[1])])
        assert regions[layer].covers(line), (layer, role, line)
        checked += 1
    assert checked > 1000


@pytest.fixture(scope="module")
def big_plan(tmp_path_factory):
    # Big enough for sparse filling to mean something (an 8 mm part has room for a few lines).
    mesh = cube_with_hole(20.0, 5.0, 32)
    s = PrintSettings(pixel_size=0.2, layer_height=0.5, first_layer_height=0.5, max_layer_ratio=1.25)
    pp = plan(mesh, s, workers=1)
    out = tmp_path_factory.mktemp("g") / "big.gcode"
    write_gcode(pp, out)
    return s, pp, out.read_text()


def test_extruded_volume_matches_the_prediction(big_plan):
    s, pp, text = big_plan
    mesh = cube_with_hole(20.0, 5.0, 32)
    moves, *_ = parse_gcode(text)
    e = np.array([m[6] for m in moves])
    xy_move = np.array([(m[2], m[3]) != (m[4], m[5]) for m in moves])
    filament = e[xy_move & (e > 0)].sum()  # retractions and primes cancel out, they move no XY
    volume = filament * s.filament_area / s.extrusion_multiplier
    assert volume == pytest.approx(pp.extruded_volume, rel=1e-3)  # G-code rounding only
    assert volume == pytest.approx(pp.predicted_volume(), rel=0.05)
    # And the part itself: shells + 20% of the inside is well under the part's volume.
    part = slicelab.check(mesh).volume
    assert 0.3 * part < volume < part


def test_top_and_bottom_layers_are_solid(cube_plan):
    mesh, s, pp, text = cube_plan
    moves, *_ = parse_gcode(text)
    n = len(pp.layers)
    fill_types = {}
    for layer, z, x0, y0, x1, y1, e, word, role in moves:
        if e > 0 and (x0, y0) != (x1, y1) and role and "infill" in role:
            fill_types.setdefault(layer, set()).add(role)
    for k in range(s.bottom_layers):
        assert fill_types[k] == {"Solid infill"}, (k, fill_types[k])
    # The skin's first layer over the sparse infill bridges it (PrusaSlicer's internal bridge),
    # the next ones are solid infill, under the top surface.
    assert fill_types[n - s.top_layers] == {"Bridge infill"}
    for k in range(n - s.top_layers + 1, n - 1):
        assert fill_types[k] == {"Solid infill"}, (k, fill_types[k])
    assert fill_types[n - 1] == {"Top solid infill"}  # the surface itself, as PrusaSlicer types it
    for k in range(s.bottom_layers, n - s.top_layers):
        assert fill_types[k] == {"Internal infill"}, (k, fill_types[k])


def test_solid_layers_are_covered(big_plan):
    # The first and last layers' filling (with gap fill) extrudes about the whole inner area.
    s, pp, _ = big_plan
    for k in (0, len(pp.layers) - 1):
        total, inner, solid, _ = pp.areas[k]
        assert solid == pytest.approx(inner)
        lp = pp.layers[k]
        fill = sum(np.hypot(*np.diff(q, axis=0).T).sum() for q in lp.filling_segments) * s.line_width
        gaps = sum((np.hypot(*np.diff(q, axis=0).T) * (w[1:] + w[:-1]) / 2).sum()
                   for q, w in zip(lp.gap_fill_segments, lp.gap_fill_widths))
        assert fill + gaps == pytest.approx(inner, rel=0.05), (fill, gaps, inner)


def test_retraction_before_every_long_travel(cube_plan):
    mesh, s, pp, text = cube_plan
    moves, *_ = parse_gcode(text)
    long_travels = 0
    for i, (layer, z, x0, y0, x1, y1, e, word, role) in enumerate(moves):
        if word != "G0" or layer < 0:
            continue
        d = np.hypot(x1 - x0, y1 - y0)
        if d > s.retract_min_travel:
            long_travels += 1
            before = [m for m in moves[max(0, i - 3):i] if m[6] != 0]
            after = [m for m in moves[i + 1:i + 4] if m[6] != 0]
            assert before and before[-1][6] == pytest.approx(-s.retraction_length), moves[i - 3:i + 1]
            assert after and after[0][6] == pytest.approx(s.retraction_length)
            assert z == pytest.approx(moves[i + 1][1] + s.z_lift)  # travels lifted, then lowered
        else:
            assert e == 0
    assert long_travels > len(pp.layers)


def test_skins_are_found_by_mask_differences():
    # A 10 x 10 x 2 slab with a 4 x 4 x 2 tower: the slab's top layers are skin outside the
    # tower's footprint and sparse inside it.
    occ = np.zeros((10, 10, 4), bool)
    occ[:, :, :2] = True
    occ[3:7, 3:7, 2:] = True
    mesh = voxels(occ)
    s = PrintSettings(pixel_size=0.1, layer_height=0.25, first_layer_height=0.25, top_layers=2,
                      bottom_layers=2, infill_density=0.2, solid_infill_below_area=0.0,
                      ensure_vertical_shell_thickness=False)  # (the tower's walls would reach down into the slab)
    pp = plan(mesh, s, workers=1)
    tower = shapely.box(3, 3, 7, 7)
    k = 6  # 1.5 - 1.75 mm: the tower stands 2 layers above
    lp = pp.layers[k]
    kinds = np.array(lp.filling_kinds)
    # Skin under the slab's top surface (layer 7): its first layer, over sparse infill, a bridge.
    assert {"bridge", "sparse"} <= set(kinds) and "top" not in kinds
    assert "top" in pp.layers[7].filling_kinds
    for q, kind in zip(lp.filling_segments, kinds):
        line = shapely.LineString(q)
        if kind in ("solid", "top", "bridge"):
            assert line.intersection(tower.buffer(-0.3)).length < 1e-6
        else:
            assert tower.buffer(0.3).covers(line)
    # A middle layer of the slab, with two layers of slab above and below: no skin.
    assert set(pp.layers[3].filling_kinds) == {"sparse"}


def test_parallel_plan_gives_the_same_gcode(tmp_path):
    mesh = cube_with_hole(8.0, 2.0, 32)
    s = PrintSettings(**FAST)
    a, b = plan(mesh, s, workers=1), plan(mesh, s, workers=2)
    write_gcode(a, tmp_path / "a.gcode")
    write_gcode(b, tmp_path / "b.gcode")
    assert (tmp_path / "a.gcode").read_text() == (tmp_path / "b.gcode").read_text()


def test_runs_handed_out_in_groups_give_the_same_gcode(tmp_path):
    """Serially the runs of 20 layers go five to a call, to two workers one to a call: each call
    rasterises a layer once for all its runs, and the nozzle starts afresh at every run, so the
    files written are the same byte for byte whatever the grouping."""
    from slicelab.samples import sphere
    mesh = sphere(9.0, 24, 48)  # 18 mm: 90 layers of 0.2 mm, five runs
    s = PrintSettings(pixel_size=0.2, skirt_loops=1, seam_position="nearest")  # seams follow the nozzle
    texts = []
    for workers in (1, 2, 3):
        pp = plan(mesh, s, workers=workers)
        assert len(pp.layers) == 90 and all(len(lp) for lp in pp.layers)
        write_gcode(pp, tmp_path / f"{workers}.gcode")
        texts.append((tmp_path / f"{workers}.gcode").read_text())
    assert texts[0].count(";LAYER_CHANGE") == 90
    assert texts[0] == texts[1] == texts[2]


def test_a_pool_leaves_the_garbage_collector_as_it_found_it():
    """The pool freezes the collector's objects before it forks (so workers do not walk them) and
    unfreezes them after: a notebook's session is not left with objects it can never collect."""
    import gc
    before, enabled = gc.get_freeze_count(), gc.isenabled()
    from slicelab.samples import sphere
    pp = plan(sphere(9.0, 16, 32), PrintSettings(**FAST), workers=2)  # 45 layers: three runs, a pool
    assert len(pp.layers) == 45
    assert gc.get_freeze_count() == before and gc.isenabled() == enabled


def test_svg_and_png_previews(cube_plan, tmp_path):
    mesh, s, pp, text = cube_plan
    files = write_svgs(pp, tmp_path / "svg")
    assert len(files) == len(pp.layers)
    assert "External perimeter" in files[0].read_text()
    preview_png(pp, tmp_path / "p.png", layers=[0, 10])
    assert (tmp_path / "p.png").read_bytes()[:4] == b"\x89PNG"


def test_png_preview_draws_the_outer_perimeter_where_it_lies(tmp_path):
    # Read back from disk, through the panel's extent: the outer perimeter's colour covers the box
    # of its centre line (0.2 mm inside a 12 mm L of 3 mm arms) and stays out of the L's notch (a
    # flipped axis would draw an arm there), and reaches the end of each arm.
    import cv2
    from slicelab.printing.roles import STYLES
    occ = np.zeros((4, 4, 1), bool)
    occ[0, :, 0] = occ[:, 0, 0] = True  # an arm up the y axis and one along the x axis
    pp = plan(voxels(occ, (3.0, 3.0, 1.0)), PrintSettings(pixel_size=0.1, skirt_loops=0), workers=1)
    layout = preview_png(pp, tmp_path / "p.png", layers=[2], pixels=300)
    img = cv2.imread(str(tmp_path / "p.png"))[..., ::-1].astype(int)  # RGB
    colour = np.array([int(STYLES["external"].plot_colour[j:j + 2], 16) for j in (1, 3, 5)])
    ys, xs = np.nonzero(np.abs(img - colour).max(axis=2) < 30)
    (px, py, w, h), (x0, x1, y0, y1) = layout["panels"][0], layout["extent"][0]
    scale = w / (x1 - x0)
    x, y = x0 + (xs - px) / scale, y1 - (ys - py) / scale  # mm, part coordinates
    assert np.allclose([x.min(), x.max(), y.min(), y.max()], [0.2, 11.8, 0.2, 11.8], atol=2 / scale)
    assert not np.any((x > 4) & (x < 11) & (y > 4) & (y < 11))  # the notch
    assert np.any((x > 11) & (y < 3)) and np.any((x < 3) & (y > 11))  # the arms' ends


def test_cli_previews_drawn_by_a_pool_are_the_serial_ones(tmp_path, data_dir):
    # `slicelab slice --preview` on all cores draws the SVGs in a pool of processes, the PNG in one
    # of them alongside: the files read back from disk are those one process draws, and the PNG
    # shows the outer perimeters in their colour.
    import cv2
    from matplotlib.colors import to_rgb

    from slicelab.printing.roles import STYLES
    folders = {}
    for workers in ("1", "2"):
        folders[workers] = tmp_path / workers
        r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(data_dir / "cube_with_hole.stl"), "-o",
                            str(tmp_path / f"{workers}.gcode"), "--layer-height", "0.2", "--pixel-size", "0.2",
                            "--workers", workers, "--preview", str(folders[workers])], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
    one, two = (sorted(folders[w].glob("layer_*.svg")) for w in ("1", "2"))
    assert len(one) == 100 and [f.name for f in one] == [f.name for f in two]  # 20 mm: more than two runs
    assert all(a.read_bytes() == b.read_bytes() for a, b in zip(one, two))
    img = cv2.imread(str(folders["2"] / "preview.png"))[..., ::-1].astype(int)  # read back: RGB
    outer = np.array(to_rgb(STYLES["external"].plot_colour)) * 255
    assert np.count_nonzero(np.abs(img - outer).max(axis=2) < 40) > 500


def test_layer_svgs_drawn_while_planning_are_those_drawn_after(tmp_path):
    # The planner's workers draw each layer (layer_drawings) as `slice --preview` asks: the files
    # read back from disk are byte for byte those drawn after planning, and each path's points,
    # taken back through the page, are the plan's own (skirt included, all inside the extent).
    import xml.etree.ElementTree as ET

    from slicelab.gcode.layer_svgs import layer_drawings
    from slicelab.printing.roles import STYLES
    mesh = cube_with_hole(size=12.0, radius=3.0)
    s = PrintSettings(**FAST, skirt_loops=2, skirt_distance=3.0)
    ahead = plan(mesh, s, workers=2, layer_drawing=layer_drawings)
    after = plan(mesh, s, workers=1)
    assert sorted(ahead.drawings) == list(range(len(ahead.layers))) and not after.drawings
    a, b = write_svgs(ahead, tmp_path / "a"), write_svgs(after, tmp_path / "b", workers=1)
    assert len(a) == len(ahead.layers) and all(x.read_bytes() == y.read_bytes() for x, y in zip(a, b))
    x0, y0, x1, y1 = ahead.extent
    reach = 3.0 + 2 * s.line_width  # the skirt's outer edge: its distance and two lines
    assert np.allclose(ahead.extent, [-reach, -reach, 12 + reach, 12 + reach])
    ns = {"s": "http://www.w3.org/2000/svg"}
    for k in (0, len(a) // 2):
        root = ET.parse(a[k]).getroot()
        assert root.get("width") == f"{x1 - x0 + 4:.6g}mm"
        got = []
        for path in root.iterfind("s:path", ns):
            pts = np.array([[float(v) for v in xy.split(",")] for xy in path.get("d")[1:].split(" L")])
            got.append((path.find("s:title", ns).text, np.c_[pts[:, 0] + x0 - 2, y1 + 2 - pts[:, 1]]))
        want = list(ahead.layers[k].pieces())
        assert [t for t, _ in got] == [STYLES[kind].gcode_type for kind, _, _ in want]
        for (_, xy), (_, q, _) in zip(got, want):
            assert np.abs(xy - q).max() < 1e-3
            assert np.all((xy >= [x0, y0]) & (xy <= [x1, y1]))
    assert [t.text for t in ET.parse(a[0]).getroot().iterfind("s:path/s:title", ns)][:2] == ["Skirt/Brim"] * 2


@pytest.mark.parametrize("part", ["stepped block", "cube with a hole"])
def test_layers_that_repeat_take_the_toolpaths_two_below(part, tmp_path, monkeypatch):
    # Prismatic stretches (a 12 mm block with a 4 mm column on it; a cube with a round hole, whose
    # walls are cut where each layer meets the facets' diagonals): the planner computes the
    # toolpaths of far fewer layers than it plans, and the G-code written and read back is the one
    # every layer planned afresh gives, byte for byte, skins round the step included.
    import slicelab.printing.pipeline as pipeline
    import slicelab.printing._reuse as repeats
    if part == "stepped block":
        occ = np.zeros((3, 3, 3), bool)
        occ[:, :, :2] = True
        occ[1, 1, 2] = True
        mesh = voxels(occ, (4.0, 4.0, 4.0))
    else:
        mesh = cube_with_hole(size=12.0, radius=3.0)
    s = PrintSettings(pixel_size=0.1)
    computed = []
    real = pipeline.plan_layer
    monkeypatch.setattr(pipeline, "plan_layer", lambda sec, s, inputs, **k: computed.append(inputs.index)
                        or real(sec, s, inputs, **k))
    reused = plan(mesh, s, workers=1)  # (in this process: its layer_paths calls are counted)
    n_reused = len(reused.layers) - len(computed)
    taken = set(range(len(reused.layers))) - set(computed)
    if part == "stepped block":  # and layers with the step within their skins' reach (layer 40 starts the column)
        assert {43, 44, 45} <= taken and not {37, 38, 39, 40, 41, 42} & taken  # (those have skins, or no two below)
    write_gcode(plan(mesh, s, workers=2), tmp_path / "reused.gcode")  # the pool's workers reuse alike
    monkeypatch.setattr(repeats, "same_outline", lambda *args: False)  # every layer planned afresh
    computed.clear()
    fresh = plan(mesh, s, workers=1)
    write_gcode(fresh, tmp_path / "fresh.gcode")
    assert len(computed) == len(fresh.layers) == len(reused.layers) == 60
    assert n_reused >= 0.5 * len(fresh.layers), n_reused
    assert (tmp_path / "reused.gcode").read_bytes() == (tmp_path / "fresh.gcode").read_bytes()
    assert [lp.kinds() for lp in reused.layers] == [lp.kinds() for lp in fresh.layers]
    assert all(np.allclose(reused.areas[f], fresh.areas[f]) for f in reused.areas.dtype.names)
    assert all(np.array_equal(reused.overhangs[f], fresh.overhangs[f], equal_nan=True)
               for f in reused.overhangs.dtype.names)


def test_runs_that_start_alike_are_made_once(tmp_path, monkeypatch):
    # A 20 mm cube with a round hole: 100 layers, runs of 20. The nozzle starts afresh at each run,
    # so each run's first layers are planned anew until its toolpaths settle; the runs from 40 on
    # start as the run at 20 did (steady layers, one outline) and take those layers, made once.
    # The G-code read back is the one every layer planned afresh gives, with one worker or two.
    import slicelab.printing.pipeline as pipeline
    import slicelab.printing._reuse as repeats
    mesh = cube_with_hole(size=20.0, radius=5.0)
    s = PrintSettings(pixel_size=0.1)
    assert repeats.run_starts(dict(enumerate(slicelab.slice_layers(mesh, heights=np.arange(0.1, 20, 0.2)))), 100,
                              (4, 3), 1e-5, 20, 6) == {20: 20, 40: 20, 60: 20, 80: 20}
    computed = []
    real = pipeline.plan_layer
    monkeypatch.setattr(pipeline, "plan_layer", lambda sec, s, inputs, **k: computed.append(inputs.index)
                        or real(sec, s, inputs, **k))
    one = plan(mesh, s, workers=1)
    assert {20, 21} <= set(computed) and not {40, 41, 60, 61, 80, 81} & set(computed)
    write_gcode(one, tmp_path / "one.gcode")
    write_gcode(plan(mesh, s, workers=2), tmp_path / "two.gcode")
    monkeypatch.setattr(repeats, "same_outline", lambda *args: False)  # every layer planned afresh
    computed.clear()
    write_gcode(plan(mesh, s, workers=1), tmp_path / "fresh.gcode")
    assert len(computed) == 100
    fresh = (tmp_path / "fresh.gcode").read_bytes()
    assert (tmp_path / "one.gcode").read_bytes() == fresh == (tmp_path / "two.gcode").read_bytes()


def test_layers_of_a_prism_written_in_float32_far_from_the_origin_repeat(tmp_path, monkeypatch):
    # An STL holds float32: the cube with a hole 500 mm out has walls that lean by the coordinates'
    # rounding (layers differ by micrometre thousandths). Its layers are still taken from those
    # two below (outlines within the file's float32 rounding), and they print what every layer planned
    # afresh prints: the same rows, each perimeter within twice the G-code resolution of the fresh
    # one (a ring's simplification may keep other vertices), filling of each kind along the same
    # direction and about as long (a start a rounding away may link its zigzags otherwise), about as
    # many G-code lines and the same filament within a percent, read back.
    import slicelab.printing.pipeline as pipeline
    import slicelab.printing._reuse as repeats
    from slicelab.mesh import default_tolerance
    exact = cube_with_hole(size=12.0, radius=3.0).triangles + [500.3, 300.7, 0.1]
    exact[..., 0] += 3e-5 * exact[..., 2] / 12  # half a float32 step at the top: rounded up or down
    slicelab.save(slicelab.Mesh(exact), tmp_path / "far.stl")
    mesh = slicelab.load(tmp_path / "far.stl")
    top, bottom = mesh.triangles[..., 2] > 6, mesh.triangles[..., 2] < 6
    xs = {round(float(x), 3): set() for x in mesh.triangles[..., 0][bottom]}
    for x in mesh.triangles[..., 0][top]:
        xs.setdefault(round(float(x), 3), set()).add(float(x))
    lean = np.abs(mesh.triangles - exact).max()
    assert 0 < lean < default_tolerance(mesh)  # rounded, within the tolerance the layers are compared to
    walls = {x for x in mesh.triangles[..., 0][top]} - {x for x in mesh.triangles[..., 0][bottom]}
    assert walls  # some walls lean: their tops are not above their bottoms
    s = PrintSettings(pixel_size=0.1)
    computed = []
    real = pipeline.plan_layer
    monkeypatch.setattr(pipeline, "plan_layer", lambda *a, **k: computed.append(1) or real(*a, **k))
    reused = plan(mesh, s, workers=1)
    assert len(reused.layers) - len(computed) >= 0.5 * len(reused.layers)
    monkeypatch.setattr(repeats, "same_outline", lambda *args: False)
    fresh = plan(mesh, s, workers=1)
    for a, b in zip(reused.layers, fresh.layers):  # over layers
        assert a.kinds() == b.kinds()
        filling = {}
        for kind, p, q in zip(a.kinds(), a.paths, b.paths):  # over rows
            if kind in ("external", "internal", "hole"):  # shapely's Hausdorff distance, the oracle
                assert shapely.LineString(p).hausdorff_distance(shapely.LineString(q)) <= 0.025, kind
            else:
                filling.setdefault(kind, ([], []))
                filling[kind][0].append(np.diff(p, axis=0))
                filling[kind][1].append(np.diff(q, axis=0))
        for kind, (p, q) in filling.items():  # over filling kinds: direction and length
            (lp, ap), (lq, aq) = ((np.hypot(*d.T), np.degrees(np.arctan2(d[:, 1], d[:, 0])) % 180)
                                  for d in (np.concatenate(p), np.concatenate(q)))
            assert np.median(ap[lp > 1]) == pytest.approx(np.median(aq[lq > 1]), abs=1), kind
            assert lp.sum() == pytest.approx(lq.sum(), rel=0.1), kind
    texts = []
    for name, pp in (("reused", reused), ("fresh", fresh)):
        write_gcode(pp, tmp_path / f"{name}.gcode")
        texts.append((tmp_path / f"{name}.gcode").read_text())
    assert abs(len(texts[0].splitlines()) - len(texts[1].splitlines())) <= 0.01 * len(texts[1].splitlines())
    filament = [float(t.split("; filament used [mm] = ")[1].split()[0]) for t in texts]
    assert filament[0] == pytest.approx(filament[1], rel=0.01)


def test_cli_slice(tmp_path, data_dir):
    out = tmp_path / "c.gcode"
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(data_dir / "cube_with_hole.stl"), "-o",
                        str(out), "--layer-height", "2", "--nozzle-diameter", "2.5", "--line-width", "2",
                        "--pixel-size", "0.2", "--workers", "1",
                        "--infill-density", "15%", "--preview", str(tmp_path / "prev")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert out.read_text().count(";LAYER_CHANGE") == 10
    assert (tmp_path / "prev" / "preview.png").exists()
    for bad in (["--infill-density", "120"], ["--perimeters", "-1"], ["--workers", "0"]):
        r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(data_dir / "cube_with_hole.stl"),
                            "-o", str(out), *bad], capture_output=True, text=True)
        assert r.returncode == 2 and r.stderr.count("\n") == 1 and "Traceback" not in r.stderr


def test_bad_settings():
    with pytest.raises(ValueError, match="layer_height"):
        PrintSettings(layer_height=0)
    with pytest.raises(ValueError, match="infill_density"):
        PrintSettings(infill_density=2)
    with pytest.raises(ValueError, match="^dont_support_bridges must be true or false, got 'no'"):
        PrintSettings(dont_support_bridges="no")
    with pytest.raises(ValueError, match="nothing to print"):
        plan(slicelab.Mesh(np.zeros((0, 3, 3))), PrintSettings())


def test_a_part_on_a_corner_is_lowered_until_its_first_layer_prints():
    # A cube standing on a corner: its first layers are triangles too small for a line (a gap
    # fill's line fits the third), so the first extrusion would be laid in the air. The plan
    # lowers it into the bed by whole layers, says so, and prints its first layer on the bed.
    from slicelab.samples import box
    from slicelab.printing import PrintSettings, plan
    a = np.ones(3) / np.sqrt(3)
    v = np.cross(a, [0, 0, 1.0])
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    turn = np.eye(3) + vx + vx @ vx / (1 + a[2])
    corner = slicelab.Mesh(box((0, 0, 0), (10, 10, 10)).triangles @ turn.T)
    p = plan(corner, PrintSettings(), workers=1)
    assert 0 < p.sunk <= 0.6 + 1e-9 and p.sunk / 0.2 == pytest.approx(round(p.sunk / 0.2))
    assert p.offset[2] == pytest.approx(-corner.bounds[0][2] - p.sunk)
    assert [w["code"] for w in p.warnings()][0] == "lowered"
    first = p.layers[0]
    assert p.z[0] == pytest.approx(0.2) and any(k not in ("skirt", "brim") for k in first.kind)
    # A part standing on a face is not lowered.
    assert plan(box((0, 0, 0), (10, 10, 2)), PrintSettings(), workers=1).sunk == 0.0
