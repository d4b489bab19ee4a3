"""A profile batch's summary read back as an EVE table, and its rim-diameter chart.

The oracle is the generator's truth (`slicelab.samples.scan`): each sherd's share of the rim and
the vessel's rim diameter; the chart's bins are recomputed here from the summary's rows."""
import csv
import json
import math
from pathlib import Path

import cv2
import numpy as np
import pytest

import slicelab
from slicelab import samples
from slicelab.tasks.batch import run_batch, task_parameters
from slicelab.tasks.summary import COUNTS, summary_columns

PIECES = {  # file -> scan() arguments
    "rims/beaker_rim.stl": dict(form="beaker", spacing=2.0, sherd="rim", span=90.0, seed=1),
    "rims/pot_rim.stl": dict(form="pot", spacing=2.0, sherd="rim", span=60.0, seed=2),
    "body/pot_body.stl": dict(form="pot", spacing=2.0, sherd="body", span=60.0, seed=3),
    "bases/beaker_base.stl": dict(form="beaker", spacing=2.0, sherd="base", span=90.0, seed=4),
    "whole/beaker.stl": dict(form="beaker", spacing=2.0, seed=5),
}
UNIT_ENDINGS = ("_mm", "_mm2", "_mm3", "_cm3", "_l", "_deg", "_percent", "_eve")


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    scans = tmp_path_factory.mktemp("finds")
    truth = {}
    for name, kw in PIECES.items():
        mesh, truth[name] = samples.scan(**kw)
        slicelab.save(mesh, scans / name)
    (scans / "broken.stl").write_bytes(b"solid nothing\n")
    out = tmp_path_factory.mktemp("out")
    result = run_batch(scans, out, "profile", task_parameters("profile", planes=4), workers=1, progress=False)
    with open(out / "summary.csv", newline="") as fh:
        rows = {r["file"]: r for r in csv.DictReader(fh)}
    return scans, out, result, rows, truth


def number(text):
    return float(text) if text != "" else None


def test_summary_is_an_eve_table_with_units_in_every_numeric_column(batch):
    _, out, result, rows, _ = batch
    with open(out / "summary.csv", newline="") as fh:
        header = next(csv.reader(fh))
    assert header == summary_columns("profile")
    for column in ("kind", "span_deg", "rim_eve", "rim_diameter_mm", "rim_diameter_sd_mm", "axis_trusted",
                   "up_from", "capacity_l", "height_mm", "wall_thickness_mean_mm"):
        assert column in header, column
    assert "capacity" not in header and "rim_diameter" not in header and "volume" not in header
    numeric = set()
    for row in rows.values():
        for k, v in row.items():
            if k not in ("file", "sha256", "report"):
                try:
                    float(v)
                    numeric.add(k)
                except ValueError:
                    pass
    assert numeric >= {"rim_eve", "rim_diameter_mm", "capacity_l", "span_deg"}
    bare = sorted(c for c in numeric if not c.endswith(UNIT_ENDINGS) and c not in COUNTS)
    assert not bare, bare


def test_a_rim_sherd_row_has_its_rim_eve_and_diameter(batch):
    _, out, _, rows, truth = batch
    for name in ("rims/beaker_rim.stl", "rims/pot_rim.stl"):
        row, t = rows[name], truth[name]
        assert (row["status"], row["kind"], row["up_from"], row["axis_trusted"]) == ("warn", "rim", "rim", "yes")
        sherd = json.loads((out / row["report"]).read_text())["results"]["sherd"]
        assert row["rim_eve"] == f"{sherd['rim_fraction']:.10g}"  # the sherd's own rim fraction
        for key in ("up_confidence", "kind_confidence", "rim_diameter_sd"):  # where its report has them
            unit, factor = ("mm", 1) if key == "rim_diameter_sd" else ("percent", 100)
            said = sherd.get(key)
            assert row[f"{key}_{unit}"] == ("" if said is None else f"{factor * said:.10g}")
        assert number(row["rim_eve"]) == pytest.approx(t["rim_fraction"], abs=0.03)  # and this sherd's
        assert number(row["rim_diameter_mm"]) == pytest.approx(t["rim_diameter"], rel=0.01)
        assert number(row["span_deg"]) == pytest.approx(t["span"], abs=2.0)
        assert row["capacity_l"] == "" and row["height_mm"] == ""  # a sherd holds neither
        assert row["orientation_uncertain"] == "no"


def test_a_body_sherd_has_no_eve_and_a_whole_vessel_counts_one(batch):
    _, out, _, rows, truth = batch
    body = rows["body/pot_body.stl"]
    assert body["kind"] == "body" and body["rim_eve"] == "" and body["rim_diameter_mm"] == ""
    assert body["up_from"] == "unknown" and body["orientation_uncertain"] == "yes"
    base = rows["bases/beaker_base.stl"]
    assert base["kind"] == "base" and base["rim_eve"] == "" and base["up_from"] == "base plane"
    whole, t = rows["whole/beaker.stl"], truth["whole/beaker.stl"]
    assert (whole["kind"], number(whole["rim_eve"]), number(whole["base_eve"])) == ("whole", 1.0, 1.0)
    assert number(whole["span_deg"]) == 360.0 and whole["axis_trusted"] == "yes"
    assert number(whole["rim_diameter_mm"]) == pytest.approx(t["rim_diameter"], rel=0.005)
    # Units converted, not just renamed: litres and cm3 against the report's mm3, and the truth.
    res = json.loads((out / whole["report"]).read_text())["results"]
    assert number(whole["capacity_l"]) == pytest.approx(res["capacity"] / 1e6, rel=1e-9)
    assert number(whole["capacity_l"]) == pytest.approx(t["capacity"] / 1e6, rel=0.01)
    assert number(whole["clay_volume_cm3"]) == pytest.approx(res["clay_volume"] / 1e3, rel=1e-9)
    assert number(whole["axis_residual_percent"]) == pytest.approx(100 * res["relative_residual"], rel=1e-9)
    broken = rows["broken.stl"]
    assert broken["status"] == "fail" and broken["kind"] == "" and broken["rim_eve"] == ""


def test_rim_chart_weights_sum_to_the_batchs_eve(batch):
    _, out, result, rows, _ = batch
    assert result.files == {"chart": out / "rim_diameters.png", "chart_data": out / "rim_diameters.csv"}
    image = cv2.imread(str(out / "rim_diameters.png"))
    assert image is not None and image.shape[0] > 100 and image.shape[1] > 100
    with open(out / "rim_diameters.csv", newline="") as fh:
        bins = list(csv.DictReader(fh))
    total = math.fsum(number(r["rim_eve"]) for r in rows.values() if r["rim_eve"])
    assert total == pytest.approx(1.0 + sum(number(rows[n]["rim_eve"]) for n in rows if "rims/" in n), abs=1e-12)
    assert math.fsum(float(b["rim_eve"]) for b in bins) == pytest.approx(total, abs=1e-8)
    # Each piece in the bin its diameter falls in, weighted by its rim EVE: recomputed from the rows.
    charted = [b for b in bins if b["charted"] == "yes"]
    width = float(charted[0]["diameter_to_mm"]) - float(charted[0]["diameter_from_mm"])
    assert width == 10.0
    expect = {}
    for r in rows.values():
        if r["rim_eve"] and r["axis_trusted"] == "yes":
            lo = math.floor(number(r["rim_diameter_mm"]) / width) * width
            expect[lo] = expect.get(lo, 0.0) + number(r["rim_eve"])
    got = {float(b["diameter_from_mm"]): float(b["rim_eve"]) for b in charted if float(b["rim_eve"]) > 0}
    assert got.keys() == expect.keys() and all(got[k] == pytest.approx(expect[k], abs=1e-8) for k in got)
    assert sum(int(b["pieces"]) for b in charted) == sum(1 for r in rows.values() if r["rim_eve"])


def test_the_chart_goes_with_its_summary(batch, tmp_path):
    """Another task into the same OUT takes the chart away; a folder of DIR on the chart's name is
    mirrored under another, and the chart keeps its own."""
    scans, out, _, _, _ = batch
    mine = tmp_path / "out"
    slicelab.save(samples.box((0, 0, 0), (10, 10, 10)), tmp_path / "in" / "rim_diameters.png" / "cube.stl")
    slicelab.save(samples.scan("beaker", spacing=3.0, seed=1)[0], tmp_path / "in" / "beaker.stl")
    first = run_batch(tmp_path / "in", mine, "profile", task_parameters("profile", planes=2, png=False),
                      workers=1, progress=False)
    assert first.files["chart"] == mine / "rim_diameters.png" and first.files["chart"].is_file()
    assert (mine / "rim_diameters.png~2" / "cube.stl.json").is_file()  # the folder's own report, beside
    with open(mine / "summary.csv", newline="") as fh:
        rows = {r["file"]: r for r in csv.DictReader(fh)}
    assert (rows["beaker.stl"]["rim_eve"], rows["beaker.stl"]["axis_trusted"]) == ("1", "yes")
    with open(first.files["chart_data"], newline="") as fh:  # the beaker in its bin, whatever the cube is
        bins = list(csv.DictReader(fh))
    d = float(rows["beaker.stl"]["rim_diameter_mm"])
    assert [(float(b["diameter_from_mm"]), float(b["rim_eve"])) for b in bins if b["charted"] == "yes"
            and float(b["diameter_from_mm"]) <= d < float(b["diameter_to_mm"])] == [(math.floor(d / 10) * 10, 1.0)]
    assert math.fsum(float(b["rim_eve"]) for b in bins) == \
        pytest.approx(math.fsum(float(r["rim_eve"]) for r in rows.values() if r["rim_eve"]), abs=1e-12)
    again = run_batch(tmp_path / "in", mine, "section", task_parameters("section"), workers=1, progress=False)
    assert again.files == {} and not first.files["chart"].exists() and not first.files["chart_data"].exists()
    assert (mine / "rim_diameters.png~2" / "cube.stl.json").is_file()
    assert not [p for p in mine.rglob("*") if p.name.endswith((".part", ".staging"))]


def test_a_batch_with_no_rim_draws_an_empty_chart(tmp_path):
    slicelab.save(samples.scan("pot", spacing=3.0, sherd="body", span=60.0, seed=3)[0], tmp_path / "in" / "b.stl")
    r = run_batch(tmp_path / "in", tmp_path / "out", "profile", task_parameters("profile", planes=2), workers=1,
                  progress=False)
    with open(r.files["chart_data"], newline="") as fh:
        assert list(csv.DictReader(fh)) == []
    assert cv2.imread(str(r.files["chart"])) is not None


def test_unit_columns_of_other_tasks(batch, tmp_path):
    scans, _, _, _, _ = batch
    r = run_batch(scans / "whole", tmp_path, "section", task_parameters("section"), workers=1, progress=False)
    with open(r.summary, newline="") as fh:
        (row,) = list(csv.DictReader(fh))
    assert {"area_mm2", "size_z_mm", "volume_mm3"} <= row.keys() and "area" not in row
    lo, hi = slicelab.load(scans / "whole" / "beaker.stl").bounds
    assert [number(row[f"size_{a}_mm"]) for a in "xyz"] == pytest.approx(list(hi - lo), rel=1e-9)
    assert number(row["area_mm2"]) > 0 and np.isfinite(number(row["volume_mm3"]))
    assert not Path(tmp_path / "rim_diameters.png").exists()
