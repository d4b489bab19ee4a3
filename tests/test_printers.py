"""Printer profiles, settings files, physical checks, start and end G-code."""
from __future__ import annotations

import re
import subprocess
import sys

import pytest

import slicelab
from slicelab.gcode import gcode_lines
from slicelab.samples import box
from slicelab.printing import PRINTERS, PrintSettings, format_config, read_config, resolve_settings


def run(*args):
    return subprocess.run([sys.executable, "-m", "slicelab", *map(str, args)], capture_output=True, text=True,
                          timeout=300)


@pytest.mark.parametrize("bad, words", [
    (dict(layer_height=0.5), "layer_height 0.5 mm is more than 0.8 x the 0.4 mm nozzle"),
    (dict(line_width=5.0), "line_width 5 mm is outside 0.6 to 2.5 x the 0.4 mm nozzle"),
    (dict(nozzle_temperature=1000), "nozzle_temperature 1000 C is outside what the printer allows"),
    (dict(bed_temperature=-5), "bed_temperature must be from 0 to 1000 C, got -5"),
    (dict(gcode_flavor="sailfish"), "gcode_flavor must be one of"),
])
def test_settings_a_printer_cannot_take_are_refused(bad, words):
    with pytest.raises(ValueError, match=words.replace("(", r"\(")):
        PrintSettings(**bad)


def test_the_limits_are_settings_too():
    s = PrintSettings(layer_height=0.5, first_layer_height=0.5, max_layer_ratio=1.25)
    assert s.layer_height == 0.5
    assert PrintSettings(line_width=1.2, line_width_ratio=(0.5, 3.0)).line_width == 1.2


def test_a_settings_file_round_trips(tmp_path):
    s = PrintSettings(**resolve_settings(printer="generic-marlin-220", layer_height=0.15, infill_density=0.3))
    f = tmp_path / "printer.toml"
    f.write_text(format_config(s))
    again = PrintSettings(**resolve_settings(config=f))
    assert again == s
    assert again.bed_size == (220.0, 220.0) and again.layer_height == 0.15


def test_profile_then_file_then_flags(tmp_path):
    f = tmp_path / "p.toml"
    f.write_text('printer = "generic-klipper-300"\n[settings]\nlayer_height = 0.3\ninfill_density = 0.4\n')
    assert read_config(f)["printer"] == "generic-klipper-300"
    s = resolve_settings(config=f, infill_density=0.1)
    assert s["bed_size"] == PRINTERS["generic-klipper-300"]["bed_size"]
    assert s["layer_height"] == 0.3 and s["infill_density"] == 0.1
    with pytest.raises(ValueError, match="printer must be one of"):
        resolve_settings(printer="makerbot-9000")
    (tmp_path / "bad.toml").write_text("layer_height = [")
    with pytest.raises(ValueError, match="not a TOML settings file"):
        read_config(tmp_path / "bad.toml")


def test_start_and_end_gcode_fill_their_placeholders():
    s = PrintSettings(start_gcode="; hello {bed_size_x:g}x{bed_size_y:g}\nM190 S{bed_temperature:.0f}\n",
                      end_gcode="; bye at {max_height:g}\n", bed_temperature=55)
    pp = slicelab.plan(box((0, 0, 0), (5, 5, 0.6)), PrintSettings(**{**s.__dict__, "pixel_size": 0.1}), workers=1)
    text = "".join(gcode_lines(pp))
    assert text.index("; hello 250x210\nM190 S55\n") < text.index(";LAYER_CHANGE")
    assert text.rindex("; bye at 210\n") > text.rindex(";LAYER_CHANGE")
    assert "; flavor = marlin" in text


def test_cli_config_printer_and_print_config(tmp_path, data_dir):
    f = tmp_path / "p.toml"
    f.write_text('printer = "generic-marlin-220"\n[settings]\nlayer_height = 0.25\n')
    r = run("slice", data_dir / "cube_with_hole.stl", "-o", tmp_path / "x.gcode", "--config", f,
            "--infill-density", "35%", "--no-dont-support-bridges", "--no-support-sheath", "--print-config")
    assert r.returncode == 0, r.stderr
    shown = r.stdout
    assert "dont_support_bridges = false" in shown and "support_sheath = false" in shown
    assert "bed_size = [220.0, 220.0]" in shown and "layer_height = 0.25" in shown
    assert "infill_density = 0.35" in shown and not (tmp_path / "x.gcode").exists()
    (tmp_path / "shown.toml").write_text(shown)
    again = PrintSettings(**read_config(tmp_path / "shown.toml"))
    assert again.infill_density == 0.35 and again.dont_support_bridges is False
    for args, words in ((["--layer-height", "0.5"], "--layer-height 0.5 mm is more than"),
                        (["--line-width", "5"], "--line-width 5 mm is outside"),
                        (["--nozzle-temperature", "1000"], "--nozzle-temperature 1000 C is outside"),
                        (["--printer", "nope"], "--printer must be one of")):
        r = run("slice", data_dir / "cube_with_hole.stl", "-o", tmp_path / "y.gcode", *args)
        assert r.returncode == 2 and words in r.stderr and r.stderr.count("\n") == 1, r.stderr


def test_slice_refuses_an_open_mesh_with_what_is_wrong(tmp_path):
    plate = box((0, 0, 0), (60, 40, 3))
    slicelab.save(slicelab.Mesh(plate.triangles[::2]), tmp_path / "holes.stl")   # every other facet gone
    r = run("slice", tmp_path / "holes.stl", "-o", tmp_path / "p.gcode")
    assert r.returncode == 2 and "not watertight" in r.stderr and "open" in r.stderr
    assert r.stderr.count("\n") == 1 and not (tmp_path / "p.gcode").exists()


def test_settings_come_in_groups_and_files_keep_them(tmp_path):
    from slicelab.printing import GROUPS, Motion, settings_dict, setting_names
    s = PrintSettings(layer_height=0.3, motion=Motion(travel_speed=100.0))
    assert s.extrusion.layer_height == s.layer_height == 0.3 and s.motion.travel_speed == 100.0
    assert set(settings_dict(s)) == set(setting_names())
    assert sum(len(g.__dataclass_fields__) for g in GROUPS.values()) == len(setting_names())
    text = format_config(s)
    assert all(f"[{g}]" in text for g in GROUPS) and "[settings]" not in text
    f = tmp_path / "grouped.toml"
    f.write_text(text)
    assert PrintSettings(**resolve_settings(config=f)) == s
    f.write_text("[extrusion]\nlayer_height = 0.1\n[infill]\ninfill_density = 0.5\n")
    again = PrintSettings(**resolve_settings(config=f))
    assert (again.layer_height, again.infill_density) == (0.1, 0.5)
    for bad, words in (("[extrusion]\nspeed = 3\n", "not a print setting"), ("[nozzle]\nx = 1\n", "unknown table")):
        f.write_text(bad)
        with pytest.raises(ValueError, match=words):
            resolve_settings(config=f)
    with pytest.raises(TypeError, match="unknown settings"):
        PrintSettings(layer_hieght=0.2)


@pytest.mark.parametrize("printer", [None, *PRINTERS])
def test_the_header_holds_no_live_line_before_the_start_block(tmp_path, data_dir, printer):
    # Every line of every setting written in the header is a comment: a multi-line start or end
    # G-code among them would otherwise run, its placeholders unexpanded, before the real start.
    out = tmp_path / "p.gcode"
    args = ["--printer", printer] if printer else []
    r = run("slice", data_dir / "cube_with_hole.stl", "-o", out, "--layer-height", "0.3", *args)
    assert r.returncode == 0, r.stderr
    lines = out.read_text().splitlines()
    start = lines.index("; flavor = " + (PRINTERS[printer]["gcode_flavor"] if printer else "marlin"))
    assert all(line.startswith(";") for line in lines[:start + 1])
    live = [line.split(";")[0] for line in lines if line.split(";")[0].strip()]
    assert not any("{" in line or "}" in line for line in live)
    s = PrintSettings(**resolve_settings(printer=printer))
    if s.start_gcode:
        shown = next(line for line in lines if line.startswith("; start_gcode = "))
        assert shown[len("; start_gcode = "):].replace("\\n", "\n") == s.start_gcode


@pytest.mark.parametrize("template, words", [
    ("M117 {layer_height.__class__}", "is not a placeholder"),
    ("M117 {layer_height[0]}", "is not a placeholder"),
    ("M117 {layer_height!r}", "is not a placeholder"),
    ("M117 {layer_height:>100000000}", "short numeric"),
    ("M117 {gcode_flavor}", "is not a numeric setting"),
    ("M117 {nozzle_temp}", "is not a numeric setting"),
    ("M117 {", "Single '{'"),
    ("M104 S{nozzle_temperature:d}", "bad format"),
    ("M117 x" * 20000, "characters long"),
])
def test_templates_that_reach_into_objects_or_grow_without_bound_are_refused(template, words):
    with pytest.raises(ValueError, match=f"^start_gcode.*{re.escape(words)}"):
        PrintSettings(start_gcode=template)
    # ... and the same when it comes from a settings file, before any slicing
    s = PrintSettings(start_gcode="M104 S{nozzle_temperature:.0f} ; {{literal}} {layer_height:5.2f}")
    assert s.start_gcode.startswith("M104")


@pytest.mark.parametrize("name, value, words", [
    ("infill_angle", float("nan"), "infill_angle must be from -360 to 360 degrees, got nan"),
    ("travel_speed", 1e308, "travel_speed must be above 0 and at most 1000 mm/s, got 1e+308"),
    ("top_layers", 1_000_000_000, "top_layers must be a whole number from 0 to 100 layers"),
    ("retraction_length", float("inf"), "retraction_length must be from 0 to 20 mm"),
    ("n_perimeters", True, "n_perimeters must be a whole number"),
    ("bed_size", (250.0, float("nan")), "bed_size must be 2 numbers, each above 0"),
    ("seam_position", "random-ish", "seam_position must be one of aligned, rear, nearest"),
    ("support_sheath", "yes", "support_sheath must be true or false"),
    ("pixel_size", 0.001, "pixel_size must be from 0.005 to 10 mm"),
])
def test_every_number_is_finite_and_in_a_physical_range(tmp_path, data_dir, name, value, words):
    with pytest.raises(ValueError, match="^" + re.escape(words)):
        PrintSettings(**{name: value})
    # The same refusal, one line with the key, from a settings file through the command line
    # (TOML has nan and inf).
    if isinstance(value, float) or (isinstance(value, int) and not isinstance(value, bool)):
        f = tmp_path / "s.toml"
        f.write_text(f"[settings]\n{name} = {value!r}\n".replace("1e+308", "1e308"))
        r = run("slice", data_dir / "cube_with_hole.stl", "-o", tmp_path / "x.gcode", "--config", f)
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
        assert name.replace("_", "-") in r.stderr and "must be" in r.stderr
        assert not (tmp_path / "x.gcode").exists()


def test_a_settings_file_nested_too_deep_or_with_unknown_keys_is_one_line(tmp_path):
    f = tmp_path / "deep.toml"
    f.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    with pytest.raises(ValueError, match="nested too deep"):
        read_config(f)
    f.write_text("speed = 3\n")
    with pytest.raises(ValueError, match="speed is not a print setting"):
        read_config(f)
    f.write_text("x" * (2 << 20))
    with pytest.raises(ValueError, match="is not a settings file"):
        read_config(f)
