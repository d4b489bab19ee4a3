"""Shells that stay thick on slopes, small regions filled solid, top surfaces typed, bridges
anchored and laid across their shortest span, thin walls printed: each against the part's
analytic shape, through the planner (issue #37)."""
from __future__ import annotations

import numpy as np
import pytest

from slicelab.gcode.writer import write_gcode
from slicelab.printing import PrintSettings, plan
from slicelab.printing.config.printers import format_config, read_config
from slicelab.samples import oriented, revolve, ring_prism, voxels

R = 15.0  # the dome's radius (mm)


def dome():
    """A solid hemisphere of radius R on the bed."""
    t = np.linspace(0, np.pi / 2, 60)
    prof = np.c_[R * np.cos(t), R * np.sin(t)]
    prof[-1] = (0.0, R)
    return revolve(np.vstack([[0.0, 0.0], prof]), 120)


def ramp(angle=30.0, length=30.0, width=20.0):
    """A wedge: its top rises at `angle` degrees along x, from 0 to length * tan(angle)."""
    h = length * np.tan(np.radians(angle))
    xz = np.array([[0, 0], [length, 0], [length, h]])
    v = np.array([[x, y, z] for y in (0.0, width) for x, z in xz])
    f = np.array([[0, 1, 2], [3, 5, 4], [0, 3, 4], [0, 4, 1], [1, 4, 5], [1, 5, 2], [2, 5, 3], [2, 3, 0]])
    return oriented(v, f)


def _segments(pp, kinds):
    """Midpoints (x, y, z of the layer's top) and lengths of the filling's segments of these kinds."""
    mids, lengths = [], []
    for lp in pp.layers:
        for q, kind in zip(lp.filling_segments, lp.filling_kinds):
            if kind in kinds and len(q) > 1:
                q = np.asarray(q)
                mids.append(np.c_[0.5 * (q[1:] + q[:-1]), np.full(len(q) - 1, lp.z)])
                lengths.append(np.hypot(*np.diff(q, axis=0).T))
    return (np.concatenate(mids), np.concatenate(lengths)) if mids else (np.zeros((0, 3)), np.zeros(0))


@pytest.fixture(scope="module")
def dome_plans():
    s = PrintSettings(skirt_loops=0)
    return s, plan(dome(), s, workers=1), plan(dome(), PrintSettings(skirt_loops=0,
                                                                  ensure_vertical_shell_thickness=False), workers=1)


def test_a_dome_keeps_its_shell_thick_under_the_whole_surface(dome_plans):
    # No sparse infill within top_layers x layer height of the sphere (measured along its normal,
    # from the line's middle, at the top of its layer); without the vertical shell, a metre of it.
    s, pp, thin = dome_plans
    shell = s.top_layers * s.layer_height
    for p, most in ((pp, 1e-9), (thin, None)):
        mids, lengths = _segments(p, ("sparse",))
        depth = R - np.linalg.norm(mids, axis=1)
        near = lengths[depth < shell].sum()
        if most is None:
            assert near > 200, near      # the rule is what keeps it out
        else:
            assert near <= most, near


def test_a_dome_top_is_printed_as_top_solid_infill(dome_plans):
    # The surface's own lines, where the layer above leaves the layer exposed, are "top": they lie
    # within a layer of the sphere; the solid lines under them lie deeper.
    s, pp, _ = dome_plans
    mids, lengths = _segments(pp, ("top",))
    assert lengths.sum() > 10
    assert np.all(R - np.linalg.norm(mids, axis=1) < 2 * s.layer_height + s.line_width)
    solid, _ = _segments(pp, ("solid",))
    assert len(solid) and np.median(R - np.linalg.norm(solid, axis=1)) > 0


def test_a_30_degree_ramp_keeps_its_shell_thick():
    s = PrintSettings(skirt_loops=0)
    pp = plan(ramp(30.0), s, workers=1)
    mids, lengths = _segments(pp, ("sparse",))
    surface = mids[:, 0] * np.tan(np.radians(30.0))  # the ramp's top above each point
    vertical = surface - mids[:, 2]
    # Along the normal the shell is the vertical depth times cos(30): at least the skins' thickness.
    assert lengths.sum() > 100
    assert np.all(vertical * np.cos(np.radians(30.0)) >= s.top_layers * s.layer_height - 1e-6)


def test_small_regions_of_infill_are_filled_solid():
    # A tube of 6 mm across, 2 perimeters: its infill region (some 14 mm2) is under 70 mm2.
    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    circle = np.c_[np.cos(t), np.sin(t)]
    tube = ring_prism(3.0 * circle, 0.5 * circle, 0.0, 3.0)
    kinds = {k for lp in plan(tube, PrintSettings(skirt_loops=0), workers=1).layers for k in lp.filling_kinds}
    assert "sparse" not in kinds and "solid" in kinds
    kinds = {k for lp in plan(tube, PrintSettings(skirt_loops=0, solid_infill_below_area=0.0), workers=1).layers
             for k in lp.filling_kinds}
    assert "sparse" in kinds


def _deck():
    """Two 5 x 10 x 6 mm pillars 20 mm apart (x 0-5 and 25-30), a 2 mm deck across them."""
    occ = np.zeros((30, 10, 8), bool)
    occ[:5, :, :6] = occ[25:, :, :6] = True
    occ[:, :, 6:] = True
    return voxels(occ)


def test_bridge_lines_are_anchored_onto_both_pillars():
    for anchor in (3.0, 0.0):
        s = PrintSettings(skirt_loops=0, bridge_anchor=anchor)
        pp = plan(_deck(), s, workers=1)
        k = int(np.argmin(np.abs(pp.z - 6.2)))  # the deck's first layer
        lp = pp.layers[k]
        lines = [np.asarray(q) for q, kind in zip(lp.filling_segments, lp.filling_kinds) if kind == "bridge"]
        x = np.concatenate(lines)[:, 0]  # (the part's coordinates)
        if anchor:  # at least 2 mm onto each pillar, never past what is there
            assert x.min() <= 5 - 2 and x.max() >= 25 + 2, (x.min(), x.max())
            assert x.min() >= 0 and x.max() <= 30
        else:
            assert x.min() >= 5 - 0.5 and x.max() <= 25 + 0.5, (x.min(), x.max())


def test_a_roof_over_a_hollow_is_bridged_across_its_shortest_span():
    # A closed box, 40 x 16 mm inside, walls 2 mm: its roof spans 16 mm across y, 40 along x.
    occ = np.ones((44, 20, 8), bool)
    occ[2:42, 2:18, 1:6] = False
    pp = plan(voxels(occ), PrintSettings(skirt_loops=0), workers=1)
    k = int(np.argmin(np.abs(pp.z - 6.2)))  # the roof's first layer
    lp = pp.layers[k]
    lines = [np.asarray(q) for q, kind in zip(lp.filling_segments, lp.filling_kinds) if kind == "bridge"]
    assert lines
    d = np.concatenate([np.diff(q, axis=0) for q in lines])
    d = d[np.hypot(*d.T) > 1.0]  # the lines, not the links between them
    assert np.all(np.abs(d[:, 0]) < 0.2 * np.abs(d[:, 1])), "bridge lines should run across y"


def test_a_thin_tube_wall_is_printed():
    # A tube whose wall (0.53 mm) is wider than a line and narrower than two: one line along it,
    # once around, on every layer (it used to print nothing and the part was refused).
    t = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    circle = np.c_[np.cos(t), np.sin(t)]
    pp = plan(ring_prism(4.46 * circle, 3.93 * circle, 0.0, 2.0), PrintSettings(skirt_loops=0), workers=1)
    for lp in pp.layers:
        length = sum(np.hypot(*np.diff(np.asarray(q), axis=0).T).sum() for q, kind in zip(lp.paths, lp.kind)
                     if kind not in ("skirt", "brim"))
        assert length > 0.9 * 2 * np.pi * 4.2, length


def test_new_settings_round_trip_through_a_settings_file(tmp_path):
    s = PrintSettings(bridge_anchor=1.5, ensure_vertical_shell_thickness=False, solid_infill_below_area=12.0)
    path = tmp_path / "s.toml"
    path.write_text(format_config(s))
    back = read_config(path)
    assert (back["bridge_anchor"], back["ensure_vertical_shell_thickness"], back["solid_infill_below_area"]) == \
        (1.5, False, 12.0)
    with pytest.raises(ValueError, match="bridge_anchor"):
        PrintSettings(bridge_anchor=-1.0)


def test_gcode_of_a_dome_reads_back_with_its_top_solid_infill(dome_plans, tmp_path):
    s, pp, _ = dome_plans
    write_gcode(pp, tmp_path / "dome.gcode")
    text = (tmp_path / "dome.gcode").read_text()
    assert ";TYPE:Top solid infill" in text and ";TYPE:Solid infill" in text


@pytest.mark.parametrize("nozzle, ratio", [(0.4, 1.0), (0.6, 0.8)])
def test_bridges_are_laid_as_round_strands_of_the_nozzles_bore(tmp_path, nozzle, ratio):
    # Read back from disk: each bridge move's filament per mm is a round strand's section
    # (pi d^2 / 4, times the bridge flow ratio) over the filament's, whatever the layer height and
    # line width; solid infill's is width x height.
    s = PrintSettings(skirt_loops=0, nozzle_diameter=nozzle, bridge_flow_ratio=ratio)
    pp = plan(_deck(), s, workers=1)
    write_gcode(pp, tmp_path / "deck.gcode")
    kind, x, y, per_mm = None, 0.0, 0.0, {"Bridge infill": [], "Solid infill": []}
    for line in (tmp_path / "deck.gcode").read_text().splitlines():
        if line.startswith(";TYPE:"):
            kind = line[6:]
        elif line.startswith("G1 X") and " E" in line:
            w = dict((t[0], float(t[1:])) for t in line.split(";")[0].split()[1:])
            d = np.hypot(w["X"] - x, w["Y"] - y)
            if kind in per_mm and d > 2.0:  # long moves: the 5-decimal rounding of E is nothing
                per_mm[kind].append(w["E"] / d)
            x, y = w["X"], w["Y"]
        elif line.startswith(("G0 X", "G1 X")):
            w = dict((t[0], float(t[1:])) for t in line.split(";")[0].split()[1:])
            x, y = w.get("X", x), w.get("Y", y)
    strand = np.pi * nozzle ** 2 / 4 * ratio * s.extrusion_multiplier / s.filament_area
    assert len(per_mm["Bridge infill"]) > 10
    np.testing.assert_allclose(per_mm["Bridge infill"], strand, rtol=2e-3)
    assert pp.extruded_volume > 0 and abs(np.median(per_mm["Solid infill"]) - strand) > 0.05 * strand
