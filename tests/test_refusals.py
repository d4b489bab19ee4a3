"""Work no machine could finish, and inputs that are not files, end in one line and exit status 2, fast."""
from __future__ import annotations

import os
import subprocess
import sys
import time

import pytest

import slicelab
from slicelab.samples import box, figure_eight_prism

CASES = {
    "pixels of 10 nm": (["slice", "{pot}", "-o", "{out}/p.gcode", "--pixel-size", "1e-5"], "--pixel-size"),
    "layers of 1 nm": (["layers", "{pot}", "--layer-height", "1e-9", "-o", "{out}/l"], "--layer-height"),
    "print layers of 1 um": (["slice", "{pot}", "-o", "{out}/p.gcode", "--layer-height", "1e-6"], "--layer-height"),
    "100000 perimeters": (["slice", "{pot}", "-o", "{out}/p.gcode", "--perimeters", "100000"], "--perimeters"),
    "100000 planes": (["profile", "{pot}", "--planes", "100000", "-o", "{out}/p.svg"], "--planes"),
    "stair steps of 1 nm": (["partition", "{pot}", "--volume", "80x80x80", "--joint", "stair",
                             "--step", "1e-6,1e-6", "-o", "{out}/parts"], "--step"),
    "a build volume for ants": (["partition", "{pot}", "--volume", "1x1x1", "-o", "{out}/parts"], "--volume"),
    "a FIFO to inspect": (["inspect", "{fifo}"], "not a regular file"),
    "a FIFO to section": (["section", "{fifo}", "--z", "1", "-o", "{out}/s.svg"], "not a regular file"),
    "an open solid to partition": (["partition", "{open}", "--volume", "20x20x20", "-o", "{out}/parts"],
                                   "not watertight"),
    "5 um pixels on a 20 mm cube": (["slice", "{cube}", "-o", "{out}/p.gcode", "--pixel-size", "0.005"],
                                    "or coarser (--pixel-size)"),
    "20000 layers of a 200 mm part": (["slice", "{cube}", "-o", "{out}/p.gcode", "--scale", "10",
                                       "--layer-height", "0.01", "--first-layer-height", "0.01",
                                       "--bed-size", "1000x1000", "--max-height", "1000"], "(--layer-height)"),
    "a billion top layers": (["slice", "{cube}", "-o", "{out}/p.gcode", "--top-layers", "1000000000"],
                             "--top-layers must be a whole number from 0 to 100 layers"),
}


@pytest.fixture
def files(tmp_path, data_dir):
    fifo = tmp_path / "pipe.stl"
    os.mkfifo(fifo)
    opened = box((0, 0, 0), (50, 10, 10))
    slicelab.save(slicelab.Mesh(opened.triangles[1:]), tmp_path / "open.stl")
    slicelab.save(box((0, 0, 0), (20, 20, 20)), tmp_path / "cube.stl")
    return {"pot": data_dir / "pot.stl", "out": tmp_path / "out", "fifo": fifo, "open": tmp_path / "open.stl",
            "cube": tmp_path / "cube.stl"}


@pytest.mark.parametrize("case", CASES)
def test_impossible_work_is_refused_up_front(case, files):
    args, words = CASES[case]
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "slicelab", *(a.format(**files) for a in args)],
                       capture_output=True, text=True, timeout=120)
    took = time.perf_counter() - t0
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2, r.stderr
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in r.stderr, r.stderr
    assert took < 60  # refused before any work (seconds, not the minutes the work would take)
    assert not files["out"].exists() or not any(files["out"].rglob("*.stl"))  # nothing half-written


def test_a_part_too_thin_for_any_line_is_refused_and_a_pillar_a_line_wide_prints(tmp_path):
    # A 0.3 mm pillar holds no 0.4 mm line: the planner finds nothing but its skirt, and the command
    # says so in one line, writing neither G-code nor previews; a 1 mm pillar prints its perimeter.
    from slicelab.printing import PrintSettings, plan
    with pytest.raises(ValueError, match=r"^nothing to print: the part \(0.3 x 0.3 x 2 mm\) is too thin"):
        plan(box((0, 0, 0), (0.3, 0.3, 2)), PrintSettings(), workers=1)
    for side, code in ((0.3, 2), (1.0, 0)):
        slicelab.save(box((0, 0, 0), (side, side, 2)), tmp_path / f"{side}.stl")
        out = tmp_path / f"out{side}"
        r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(tmp_path / f"{side}.stl"), "-o",
                            str(out / "p.gcode"), "--preview", str(out)], capture_output=True, text=True, timeout=120)
        assert r.returncode == code, r.stderr
        if code:
            assert len(r.stderr.strip().splitlines()) == 1 and "nothing to print" in r.stderr
            assert not out.exists() or not any(out.iterdir())
        else:
            text = (out / "p.gcode").read_text()
            assert text.count(";LAYER_CHANGE") == 10 and ";TYPE:External perimeter" in text
            assert len(list(out.glob("layer_*.svg"))) == 10


def test_negative_coordinates_can_be_typed_the_usual_way(tmp_path, data_dir):
    r = subprocess.run([sys.executable, "-m", "slicelab", "cut", str(data_dir / "pot.stl"), "--origin", "-3,2,60",
                        "--normal", "0.1,-0.2,1", "--no-preview", "-o", str(tmp_path / "c")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert slicelab.check(slicelab.load(tmp_path / "c" / "rear.stl")).watertight


def test_cut_of_a_self_intersecting_part_is_closed_on_disk_and_names_the_loop(tmp_path):
    slicelab.save(figure_eight_prism(), tmp_path / "eight.stl")
    r = subprocess.run([sys.executable, "-m", "slicelab", "cut", str(tmp_path / "eight.stl"), "--z", "5",
                        "--no-preview", "-o", str(tmp_path / "c")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "crosses itself near (12, 4.8)" in r.stdout + r.stderr
    for name in ("rear", "front"):
        assert slicelab.check(slicelab.load(tmp_path / "c" / f"{name}.stl")).watertight


def test_a_fin_inside_a_part_is_refused_in_one_line_naming_how_to_remove_it(tmp_path):
    # A third facet on an edge of a closed cube (a fin into the part) is no hole to fill and no
    # winding to mend: the refusal says so and names the fix, writing nothing.
    import numpy as np
    cube = box((0, 0, 0), (20, 20, 20))
    a, b = cube.triangles[0][0], cube.triangles[0][1]
    fin = np.array([[a, b, [10.0, 10.0, 10.0]]])
    slicelab.save(slicelab.Mesh(np.concatenate([cube.triangles, fin])), tmp_path / "fin.stl")
    out = tmp_path / "fin.gcode"
    r = subprocess.run([sys.executable, "-m", "slicelab", "slice", str(tmp_path / "fin.stl"), "-o", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "non-manifold" in r.stderr and "mesh editor" in r.stderr and not out.exists()
