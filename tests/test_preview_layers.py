"""The slice preview a user reads: which layers it draws (`--preview-layers`, and the default
choice), the legend of the roles drawn, and the oblique view of every layer."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from slicelab.printing import PrintSettings, plan
from slicelab.printing.roles import STYLES
from slicelab.samples import voxels
from slicelab.viz.layers import default_preview_layers, pick_preview_layers, preview_layers, preview_png


def _rgb(kind: str) -> np.ndarray:
    c = STYLES[kind].plot_colour
    return np.array([int(c[j:j + 2], 16) for j in (1, 3, 5)])


def _read(path) -> np.ndarray:
    import cv2
    return cv2.imread(str(path))[..., ::-1].astype(int)  # read back from disk: RGB


def _near(img, kind: str, tol: int = 12) -> np.ndarray:
    return np.abs(img - _rgb(kind)).max(axis=2) <= tol


@pytest.fixture(scope="module")
def bridge_plan(data_dir):
    """data/bridge.stl: two pillars 23 mm tall carrying a deck; the deck's first layer is bridged."""
    import slicelab
    return plan(slicelab.load(data_dir / "bridge.stl"), PrintSettings(), workers=2)


def _bridge_area(lp) -> float:
    return sum(float(np.hypot(*np.diff(q, axis=0).T).sum()) * w for _, q, w in lp.rows(("bridge",)))


def test_the_default_layers_include_the_bridge_layer(bridge_plan):
    pp = bridge_plan
    n = len(pp.layers)
    picked = default_preview_layers(pp)
    layers = [k for k, _ in picked]
    assert layers == sorted(set(layers)) and len(layers) == 4
    assert {0, n // 2, n - 1} <= set(layers)
    # The fourth is the layer laying the most bridge lines over nothing (the deck's first layer, 20 mm
    # up), not the first top skin over the deck's sparse infill (bridge lines too, over something).
    over_air = [_bridge_area(lp) if pp.overhangs["bridges"][k] else 0.0 for k, lp in enumerate(pp.layers)]
    (k, why), = [(k, why) for k, why in picked if k not in (0, n // 2, n - 1)]
    assert over_air[k] == max(over_air) > 100 and "most bridges" in why
    assert 19 < pp.layers[k].z < 21.5 and pp.z[k - 1] < 20.0 + 1e-6  # the layer just above the pillars


def test_where_the_overhang_layer_is_the_middle_one_another_is_shown():
    # A 6 mm pillar under a 12 mm cap, each 2 mm tall: 20 layers; the cap starts at layer 10, the
    # middle one. Both reasons go to that layer, and a fourth, different layer is shown.
    occ = np.zeros((3, 3, 2), bool)
    occ[1, 1, 0] = True
    occ[:, :, 1] = True
    pp = plan(voxels(occ, (4.0, 4.0, 2.0)), PrintSettings(pixel_size=0.2, skirt_loops=0), workers=1)
    n = len(pp.layers)
    assert n == 20 and pp.overhangs["area"][10] + pp.overhangs["bridges"][10] > 0
    picked = dict(default_preview_layers(pp))
    assert len(picked) == 4 and {0, 10, 19} <= set(picked)
    assert "middle" in picked[10] and "most bridges and overhangs" in picked[10]


def test_the_form_of_preview_layers():
    assert preview_layers("0, 57,z=12.5,LAST,overhang") == (0, 57, "z=12.5", "last", "overhang")
    assert preview_layers(["3", 4, "z=0"]) == (3, 4, "z=0")
    for bad in ("top", "0,,1", "-1", "z=", "z=-2", "1.5", ",".join(["0"] * 13)):
        with pytest.raises(ValueError):
            preview_layers(bad)
    tops = 0.2 * np.arange(1, 11)  # ten layers 0.2 mm thick
    # A height names the layer printed there: its bottom below, its top at or above.
    assert pick_preview_layers(("z=0", "z=0.2", "z=0.21", "z=2", "last", 9), tops) == \
        [(0, "z=0"), (1, "z=0.21"), (9, "z=2")]
    with pytest.raises(ValueError, match="10 is not a layer of this part: it has 10 layers, 0 to 9"):
        pick_preview_layers((10,), tops)
    with pytest.raises(ValueError, match="above the part's last layer"):
        pick_preview_layers(("z=2.1",), tops)


def _slice(args, tmp_path):
    return subprocess.run([sys.executable, "-m", "slicelab", "slice", *map(str, args)], capture_output=True,
                          text=True, cwd=tmp_path, timeout=120)


@pytest.mark.parametrize("layers, says", [("0,7,400", "--preview-layers 400 is not a layer of this part"),
                                          ("z=500", "--preview-layers z=500 is above the part's last layer"),
                                          ("0,top", "--preview-layers must be layer numbers")])
def test_a_layer_the_part_does_not_have_is_refused_in_one_line_writing_nothing(tmp_path, data_dir, layers, says):
    out = tmp_path / "out"
    r = _slice([data_dir / "cube_with_hole.stl", "-o", out / "c.gcode", "--preview", out / "preview",
                "--preview-layers", layers, "--pixel-size", "0.2"], tmp_path)
    assert r.returncode == 2
    assert r.stderr.startswith("slicelab: error: " + says) and r.stderr.count("\n") == 1, r.stderr
    assert "(give one of those, or last)" in r.stderr or "give a height up to 20" in r.stderr or \
           "separated by commas" in r.stderr  # the fix is named
    assert not out.exists() and r.stdout == ""


def test_the_chosen_layers_are_in_the_json_beside_the_png_and_said(tmp_path, data_dir):
    out = tmp_path / "preview"
    r = _slice([data_dir / "bridge.stl", "-o", tmp_path / "b.gcode", "--preview", out,
                "--preview-layers", "0,z=12.5,last,overhang", "--workers", "2"], tmp_path)
    assert r.returncode == 0, r.stderr
    shown = json.loads((out / "preview.json").read_text())
    n = shown["part_layers"]
    assert n == 115  # 23 mm in layers of 0.2 mm
    layers = [d["layer"] for d in shown["layers"]]
    # z = 12.5 mm is printed by layer 62 (12.4 to 12.6 mm); the bridge by the deck's first layer.
    assert layers[:3] == [0, 62, n - 1] and len(layers) == 4
    assert shown["layers"][1]["z"] == pytest.approx(12.6) and shown["layers"][1]["why"] == "z=12.5"
    assert shown["layers"][3]["why"].startswith("most bridges and overhangs")
    assert 19 < shown["layers"][3]["z"] < 21.5
    assert f"preview: layers 0, 62 (z=12.5), {n - 1} (last), {layers[3]} (most bridges" in r.stdout
    assert {"Bridge infill", "Top solid infill", "External perimeter", "Travel"} <= \
        {e["label"] for e in shown["legend"]}
    assert (out / "preview.png").read_bytes()[:4] == b"\x89PNG"


def test_the_legend_shows_the_colours_of_the_roles_drawn_and_no_others(bridge_plan, tmp_path):
    pp = bridge_plan
    deck = next(k for k, why in default_preview_layers(pp) if "bridges" in why)
    for layers, bridged in ((f"{deck}", True), ("middle", False)):  # one layer each, no oblique view
        path = tmp_path / f"{layers}.png"
        layout = preview_png(pp, path, layers, pixels=240, legend=True)
        img = _read(path)
        x, y, w, h = layout["legend_box"]
        assert all(x > px + pw for px, _, pw, _ in layout["panels"])  # right of the panels
        legend, rest = img[y:y + h, x:x + w], img[:, :x]
        # Bridge lines are drawn on the deck's first layer only: there the legend holds a stroke of
        # their colour (26 x 7 pixels), on the middle layer none.
        assert (np.count_nonzero(_near(legend, "bridge", 0)) >= 150) == bridged
        assert (np.count_nonzero(_near(rest, "bridge", 40)) > 100) == bridged
        # Every colour of a kind the layer lays (from the plan, not the picture) has its stroke in the
        # legend, and no other kind's colour is there.
        drawn = {k for k, _, _ in pp.layers[deck if bridged else len(pp.layers) // 2].pieces()}
        assert "external" in drawn and ("bridge" in drawn) == bridged
        for colour in {STYLES[k].plot_colour for k in STYLES}:
            kinds = {k for k in STYLES if STYLES[k].plot_colour == colour}
            strokes = np.count_nonzero(_near(legend, next(iter(kinds)), 0))
            assert (strokes >= 150) == bool(kinds & drawn), (kinds, strokes)
            if not kinds & drawn:
                assert not _near(legend, next(iter(kinds))).any()
        assert {k for e in layout["legend"] for k in e["kinds"]} == drawn


def test_the_oblique_view_shows_the_deck_on_the_pillars(bridge_plan, tmp_path):
    pp = bridge_plan
    layout = preview_png(pp, tmp_path / "p.png", "middle", pixels=300, legend=True, whole=True)
    img = _read(tmp_path / "p.png")
    x, y, w, h = layout["whole"]
    assert x + w < layout["panels"][0][0]  # first, left of the layer panels
    view = img[y:y + h, x:x + w]
    top = _near(view, "top", 20)  # the deck's top skin, seen from above
    walls = np.abs(view - _rgb("external")).max(axis=2) <= 120  # the outer walls, shaded
    walls &= (view[..., 0] > view[..., 2] + 60)
    assert np.count_nonzero(top) > 0.05 * w * h and np.count_nonzero(walls) > 0.1 * w * h
    rows_top, rows_walls = np.nonzero(top)[0], np.nonzero(walls)[0]
    assert np.median(rows_top) < np.median(rows_walls)  # the deck above the pillars
    # Every kind the plan lays is in the legend (the oblique view draws them all).
    kinds = {k for e in layout["legend"] for k in e["kinds"]}
    assert "bridge" in kinds and "sparse" in kinds
