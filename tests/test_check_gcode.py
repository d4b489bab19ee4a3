"""scripts/check_gcode.py, the independent G-code checker: slicelab's own G-code, read back from disk,
passes every check, and each mutation of it fails exactly the check it breaks, at its line."""
from __future__ import annotations

import importlib.util
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "check_gcode.py"
_spec = importlib.util.spec_from_file_location("check_gcode", SCRIPT)
cg = importlib.util.module_from_spec(_spec)
sys.modules["check_gcode"] = cg  # its dataclasses look their module up
_spec.loader.exec_module(cg)

PARTS = {"cube": ("cube_with_hole.stl", []), "pot": ("pot.stl", ["--layer-height", "0.3"]),
         "mushroom": ("mushroom.stl", ["--support", "auto"])}


@pytest.fixture(scope="module")
def sliced(tmp_path_factory):
    """The three parts' G-code as `slicelab slice` writes it."""
    out = tmp_path_factory.mktemp("gcode")
    for name, (stl, args) in PARTS.items():
        r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(ROOT / "data" / stl), "-o",
                            str(out / f"{name}.gcode"), *args], cwd=ROOT, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr[-2000:]
    return out


def _failing(report) -> set:
    return {c.name for c in report.checks if c.status == "fail"}


@pytest.mark.parametrize("name", list(PARTS))
def test_slicelab_gcode_passes_every_check(sliced, name):
    r = cg.check_gcode(sliced / f"{name}.gcode", ROOT / "data" / PARTS[name][0])
    assert [c.status for c in r.checks] == ["pass"] * 7, [c for c in r.checks if c.status != "pass"]
    assert r.passed and r["inside_part"].checked > 1000 and r["retraction"].checked > 1000
    if name == "mushroom":  # its support lies outside the part, exempt
        assert re.search(r"; ([1-9]\d*) skirt/brim/support", r["inside_part"].detail)
    if name == "pot":
        print(f"pot at 0.3 mm: {r.n_lines} lines, {r.n_layers} layers checked in {r.seconds:.2f} s")
        assert r.seconds < 30


# ---------------------------------------------------------------------- mutations of the cube's G-code
def _layer(lines: list, k: int) -> range:
    """Indices of layer k's block, from its ;LAYER_CHANGE to the next one."""
    starts = [i for i, t in enumerate(lines) if t == ";LAYER_CHANGE"]
    return range(starts[k], starts[k + 1])


def _template(lines):
    # A multi-line header value: its second and later lines are live (as --printer prusa-mk3 once wrote).
    i = next(i for i, t in enumerate(lines) if t.startswith("; slicelab offset")) + 1
    lines[i:i] = ["; start_gcode = M140 S{bed_temperature:.0f}", "M104 S{nozzle_temperature:.0f}",
                  "M109 S{nozzle_temperature:.0f}", "G28 ; home"]
    return lines, [i + 2, i + 3]


def _nan(lines):
    i = next(i for i in _layer(lines, 50) if lines[i].startswith("G1 X"))
    lines.insert(i + 1, "G1 X10 Ynan")
    return lines, [i + 2]


def _outside(lines):
    """The outer wall's corner at the largest x (the cube spans 115-135 on the bed), 2 mm further out."""
    block = _layer(lines, 50)
    kind, best = None, None
    for i in block:
        t = lines[i]
        kind = t[6:] if t.startswith(";TYPE:") else kind
        if kind == "External perimeter" and t.startswith("G1 X") and lines[i - 1].startswith("G1 X") \
                and lines[i + 1].startswith("G1 X"):
            x, y = (float(v) for v in re.findall(r"[XY]([-\d.]+)", t))
            if best is None or x > best[1]:
                best = (i, x)
    i, x = best
    lines[i] = lines[i].replace(f"X{x:.3f}", f"X{x + 2:.3f}")
    return lines, [i + 1, i + 2]


def _z_down(lines):
    block = _layer(lines, 50)
    z = lines[block.start + 1][3:]  # ;Z:10.200
    for i in block:
        lines[i] = re.sub(rf"Z{re.escape(z)}\b", f"Z{float(z) - 0.6:.3f}", lines[i])
    return lines, [next(i + 1 for i in block if lines[i].startswith("G1 X") and " E" in lines[i])]


def _heater_off(lines):
    i = _layer(lines, 50).start
    lines.insert(i, "M104 S0")
    return lines, [i + 1]


def _off_bed(lines):
    i = next(i for i in _layer(lines, 50) if lines[i].startswith("G1 E-"))
    lines.insert(i + 1, "G0 X255.000 Y100.000 F9000")
    return lines, [i + 2]


def _unretracted(lines):
    i = next(i for i in _layer(lines, 50) if lines[i].startswith("G1 E-") and lines[i + 2].startswith("G0 ")
             and lines[i + 4].startswith("G1 E0."))
    travel = lines[i + 2]
    del lines[i + 4], lines[i]
    return lines, [lines.index(travel, i) + 1]


def _in_the_air(lines):
    for i, t in enumerate(lines):
        if t.startswith(("G0 ", "G1 ")):
            lines[i] = re.sub(r"Z([\d.]+)", lambda m: f"Z{float(m.group(1)) + 0.2:.3f}", t)
    first = _layer(lines, 0)
    return lines, [next(i + 1 for i in first if lines[i].startswith("G1 X") and " E" in lines[i])]


MUTATIONS = {"syntax": [_template, _nan], "inside_part": [_outside], "z_order": [_z_down],
             "heaters": [_heater_off], "on_bed": [_off_bed], "retraction": [_unretracted],
             "first_layer": [_in_the_air]}


@pytest.mark.parametrize("check,mutate", [(c, m) for c, ms in MUTATIONS.items() for m in ms],
                         ids=lambda v: v if isinstance(v, str) else v.__name__)
def test_each_mutation_fails_its_check_alone(sliced, tmp_path, check, mutate):
    lines, where = mutate((sliced / "cube.gcode").read_text().splitlines())
    path = tmp_path / "mutated.gcode"
    path.write_text("\n".join(lines) + "\n")
    r = cg.check_gcode(path, ROOT / "data" / "cube_with_hole.stl")
    assert _failing(r) == {check}, [c for c in r.checks if c.status == "fail"]
    assert set(where) <= set(r[check].lines), (where, r[check].worst)
    if mutate is _outside:  # the centreline 0.2 mm inside the wall, moved 2 mm: 1.8 out, 1.6 past half a line
        assert r[check].value == pytest.approx(1.6, abs=0.03) and r[check].failed == 2
    if mutate is _z_down:
        assert r[check].value == pytest.approx(0.4, abs=1e-6)
    if mutate is _in_the_air:
        assert r[check].failed == r[check].checked and r[check].value == pytest.approx(0.2, abs=1e-6)


def test_layers_found_from_the_extrusions_without_layer_comments(sliced, tmp_path):
    full = (sliced / "cube.gcode").read_text().splitlines()
    moved, where = _outside(list(full))
    for src in (full, moved):
        lines = [t for t in src if not t.startswith((";LAYER_CHANGE", ";Z:", ";HEIGHT:", ";LAYER:", ";WIDTH:"))]
        (tmp_path / "bare.gcode").write_text("\n".join(lines) + "\n")
        r = cg.check_gcode(tmp_path / "bare.gcode", ROOT / "data" / "cube_with_hole.stl")
        assert r.n_layers == 100
        if src is full:
            assert [c.status for c in r.checks] == ["pass"] * 7
        else:
            assert _failing(r) == {"inside_part"}
            assert lines.index(moved[where[0] - 1]) + 1 in r["inside_part"].lines


def test_support_is_exempt_only_by_its_type(sliced, tmp_path):
    text = (sliced / "mushroom.gcode").read_text().replace(";TYPE:Support material\n", ";TYPE:Solid infill\n")
    (tmp_path / "m.gcode").write_text(text)
    r = cg.check_gcode(tmp_path / "m.gcode", ROOT / "data" / "mushroom.stl")
    assert _failing(r) == {"inside_part"} and r["inside_part"].value > 1.0
    print(f"mushroom, support as solid infill: {r['inside_part'].failed} extrusions outside in {r.seconds:.2f} s")


def test_the_part_as_sliced_with_its_holes_filled(tmp_path):
    """A box without one side: slicelab prints it filled; the checker sees that part with ``fill_holes``."""
    import slicelab
    from slicelab.samples import box
    t = box((0, 0, 0), (12, 10, 3)).triangles
    side = np.all(t[:, :, 0] == 12, axis=1)  # the two facets of the side x = 12
    slicelab.save(slicelab.Mesh(t[~side]), tmp_path / "open.stl")
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(tmp_path / "open.stl"), "--fill-holes",
                        "-o", str(tmp_path / "open.gcode")], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    assert cg.check_gcode(tmp_path / "open.gcode", tmp_path / "open.stl", fill_holes=True).passed
    # The header says what slicelab mended, and the checker mends its copy alike unasked ...
    text = (tmp_path / "open.gcode").read_text()
    assert "; repaired: filled 1 hole" in text
    assert cg.check_gcode(tmp_path / "open.gcode", tmp_path / "open.stl").passed
    # ... without that line, the open mesh's sections do not close.
    (tmp_path / "open.gcode").write_text(text.replace("; repaired: filled", "; (filled"))
    r = cg.check_gcode(tmp_path / "open.gcode", tmp_path / "open.stl")
    assert _failing(r) == {"inside_part"} and r["inside_part"].failed == r["inside_part"].checked
    assert "no closed section" in r["inside_part"].worst[0][2] and r.to_dict()["checks"][4]["value"] is None


# ---------------------------------------------------------------------- files without slicelab's header
PRUSA_LIKE = """; generated by another slicer
M107
M190 S60
M104 S215
M109 S215
G21
G90
M82
G92 E0
G28
;LAYER_CHANGE
;Z:0.3
;HEIGHT:0.3
G1 Z0.3 F720
G1 X10 Y10 F9000
;TYPE:External perimeter
;WIDTH:0.45
G1 X30 Y10 E1.0
G1 X30 Y30 E2.0
G1 E0.5 F2400 ; retract
G1 X60 Y60 F9000
G1 E2.0 F2400 ; prime
G1 X80 Y60 E3.0
G92 E0
;LAYER_CHANGE
;Z:0.5
;HEIGHT:0.2
G1 Z0.5
G1 X80 Y80 E1.0
M104 S0
M140 S0
G28 X0
M84 X Y E
; bed_shape = 0x0,250x0,250x210,0x210
; max_print_height = 210
; retract_before_travel = 2
; first_layer_height = 0.3
"""


def test_docstring_examples():
    import doctest
    assert doctest.testmod(cg).failed == 0


def _check_text(tmp_path, text, **options):
    path = tmp_path / "hand.gcode"
    path.write_text(text)
    return cg.check_gcode(path, **options)


def test_absolute_extrusion_and_prusaslicer_names(tmp_path):
    r = _check_text(tmp_path, PRUSA_LIKE)
    assert {c.name: c.status for c in r.checks} == {**dict.fromkeys(cg.CHECKS, "pass"), "inside_part": "skip"}
    # The travel without its retraction (absolute E: the prime's E2.0 now feeds nothing).
    r = _check_text(tmp_path, PRUSA_LIKE.replace("G1 E0.5 F2400 ; retract\n", ""))
    assert _failing(r) == {"retraction"} and r["retraction"].value == pytest.approx(42.426, abs=1e-3)
    # Retracted, never primed: the next line extrudes 1.5 mm of its 2.5 into the empty nozzle.
    r = _check_text(tmp_path, PRUSA_LIKE.replace("G1 E2.0 F2400 ; prime\n", ""))
    assert _failing(r) == {"retraction"} and r["retraction"].worst[0][1] == pytest.approx(1.5)
    # No bed in the header: the option gives it.
    bare = PRUSA_LIKE.replace("; bed_shape = 0x0,250x0,250x210,0x210\n", "")
    assert _check_text(tmp_path, bare)["on_bed"].status == "skip"
    r = _check_text(tmp_path, bare, bed=(50, 50))
    assert _failing(r) == {"on_bed"} and sorted(r["on_bed"].lines) == [21, 23, 28, 29]


def test_no_heat_and_late_motors_off(tmp_path):
    text = PRUSA_LIKE.replace("M190 S60\n", "").replace("M84 X Y E\n", "").replace("M109 S215\n", "M109 S215\nM84\n")
    r = _check_text(tmp_path, text)
    assert _failing(r) == {"heaters"}
    messages = " | ".join(w[2] for w in r["heaters"].worst)
    assert "bed not heated" in messages and "motors off (M84/M18) before" in messages \
        and "motors not switched off" in messages


@pytest.mark.skipif(shutil.which("prusa-slicer") is None, reason="prusa-slicer is not installed")
def test_prusaslicer_gcode_reads(tmp_path):
    out = tmp_path / "p.gcode"
    r = subprocess.run(["prusa-slicer", "--export-gcode", str(ROOT / "data" / "pot.stl"), "-o", str(out)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    rep = cg.check_gcode(out, bed=(250, 210))
    assert all(rep[c].status == "pass" for c in ("syntax", "z_order", "on_bed"))
    assert rep["inside_part"].status == "skip"


# ---------------------------------------------------------------------- the command
def test_command_exit_status_and_independence(sliced, tmp_path):
    cube, stl = sliced / "cube.gcode", ROOT / "data" / "cube_with_hole.stl"
    # Run as a program: the report, and no planner or writer module of slicelab was loaded (slicelab.load
    # may bring the G-code number kernels with the table of compiled kernels, never the writer).
    code = ("import runpy, sys, json; sys.argv = sys.argv[1:]; "
            "rc = 0\ntry:\n runpy.run_path(sys.argv[0], run_name='__main__')\nexcept SystemExit as e:\n rc = e.code\n"
            "print(json.dumps([rc, sorted(k for k in sys.modules if k.startswith(('slicelab.printing', "
            "'slicelab.gcode.')))]))")
    r = subprocess.run([sys.executable, "-c", code, str(SCRIPT), str(cube), "--mesh", str(stl), "--json"],
                       cwd=ROOT, capture_output=True, text=True)
    report_text, _, tail = r.stdout.rpartition("\n[")
    rc, loaded = json.loads("[" + tail)
    assert rc == 0 and set(loaded) <= {"slicelab.gcode.text_kernels"}, (loaded, r.stderr)
    assert json.loads(report_text)["passed"] is True
    lines, _ = _heater_off(cube.read_text().splitlines())
    (tmp_path / "bad.gcode").write_text("\n".join(lines) + "\n")
    (tmp_path / "binary.gcode").write_bytes(b"GCDE\x01\x00\x00\x00")
    for args, status in (([str(tmp_path / "bad.gcode"), "--bed", "250x210"], 1),
                         ([str(tmp_path / "missing.gcode")], 2), ([str(tmp_path / "binary.gcode")], 2),
                         ([str(cube), "--bed", "250xq"], 2), ([str(cube), "--mesh", str(tmp_path / "no.stl")], 2)):
        r = subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True)
        assert r.returncode == status, (args, r.stdout[-1000:], r.stderr)
        if status == 2:
            assert len(r.stderr.splitlines()) == 1 and r.stderr.startswith("check_gcode: "), r.stderr
        else:
            assert "FAIL heaters" in r.stdout and "M104 S0" not in r.stderr


def test_a_layer_middle_in_a_horizontal_face_counts_either_side(tmp_path, monkeypatch):
    # A deck on two pillars whose underside is the middle of a layer (z = 2.5 mm: layers of 0.2 mm
    # from 0): slicer and checker cut it a float's rounding apart, one above the face, one below.
    # The checker counts the section on either side, as both are the part's there.
    import slicelab
    from slicelab.samples import box, concat
    part = concat(box((0, 0, 0), (5, 10, 2.5)), box((20, 0, 0), (25, 10, 2.5)), box((0, 0, 2.5), (25, 10, 4)))
    slicelab.save(part, tmp_path / "deck.stl")
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(tmp_path / "deck.stl"), "-o",
                        str(tmp_path / "deck.gcode")], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert cg.check_gcode(tmp_path / "deck.gcode", tmp_path / "deck.stl").passed
    monkeypatch.setattr(cg, "DEGENERATE", 0.0)   # one section, cut exactly at the face: a side lost
    assert _failing(cg.check_gcode(tmp_path / "deck.gcode", tmp_path / "deck.stl")) == {"inside_part"}
