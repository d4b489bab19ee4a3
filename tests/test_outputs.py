"""What a command writes: never the input, never a stale or half set of files, never G-code under
another format's name; and inputs it cannot make whole are refused before anything is written."""
from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys

import pytest

import slicelab
from slicelab.samples import box, pot


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "slicelab", *map(str, args)], capture_output=True, text=True,
                          timeout=600, cwd=cwd)


def digest(path) -> str:
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


@pytest.fixture
def part(tmp_path):
    path = tmp_path / "part.stl"
    slicelab.save(box((0, 0, 0), (12, 10, 4)), path)
    return path


@pytest.mark.parametrize("args", [
    ["slice", "{part}", "-o", "{part}"],
    ["slice", "{part}", "-o", "{link}.gcode"],
    ["section", "{part}", "--z", "2", "-o", "{link}.svg"],
    ["profile", "{part}", "-o", "{link}.svg"],
    ["profile", "{part}", "-o", "{dir}/p.svg", "--png", "{link}.png"],
    ["profile", "{part}", "-o", "{dir}/p.svg", "--json", "{link}.json"],
])
def test_an_output_that_is_the_input_is_refused_and_the_input_kept(tmp_path, part, args):
    before = digest(part)
    link = tmp_path / "link"
    for ending in (".gcode", ".svg", ".png", ".json"):   # other names of the input: symbolic links
        os.symlink(part, f"{link}{ending}")
    given = [a.format(part=part, link=link, dir=tmp_path) for a in args]
    r = run(*given)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert "is the input file" in r.stderr or "writes" in r.stderr
    assert digest(part) == before and slicelab.check(slicelab.load(part)).watertight


@pytest.mark.parametrize("name", ["part.3mf", "other.stl", "part"])
def test_gcode_goes_only_to_a_gcode_name(tmp_path, part, name):
    r = run("slice", part, "-o", tmp_path / name)
    assert r.returncode == 2 and "name it .gcode" in r.stderr and r.stderr.count("\n") == 1
    assert not (tmp_path / name).exists()
    r = run("section", part, "--z", "2", "-o", tmp_path / "s.png")
    assert r.returncode == 2 and "name it .svg" in r.stderr


def test_a_rerun_leaves_exactly_its_own_files(tmp_path):
    # A partition into many pieces, then into fewer in the same folder: the earlier pieces and
    # plates go, a file of the user's stays, and the folder holds what the manifest lists.
    stl = tmp_path / "pot.stl"
    slicelab.save(pot(12, 24), stl)   # 124 x 124 x 120 mm
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    r = run("partition", stl, "--volume", "70x70x70", "--plates", "-o", out)
    assert r.returncode == 0, r.stderr
    first = {p.name for p in out.iterdir()}
    assert {"part_000.stl", "part_003.stl", "plate_01.stl", "parts.json"} <= first
    r = run("partition", stl, "--volume", "200x200x200", "-o", out)
    assert r.returncode == 0, r.stderr
    manifest = json.loads((out / ".slicelab-partition.json").read_text())
    assert sorted(p.name for p in out.iterdir()) == sorted(manifest["files"] + [".slicelab-partition.json",
                                                                                 "notes.txt"])
    assert manifest["files"] == ["exploded.png", "part_000.stl", "parts.json"]
    assert (out / "notes.txt").read_text() == "mine"
    pieces = json.loads((out / "parts.json").read_text())["pieces"]
    assert len(pieces) == 1 and slicelab.check(slicelab.load(out / "part_000.stl")).watertight
    # Another command's files in the same folder are its own set.
    assert run("cut", stl, "--z", "50", "-o", out).returncode == 0
    assert {"rear.stl", "front.stl", "part_000.stl", "notes.txt"} <= {p.name for p in out.iterdir()}


def test_a_failed_run_leaves_the_folder_as_it_was(tmp_path, part, monkeypatch):
    from dataclasses import replace

    from slicelab.tasks import jobs
    out = tmp_path / "out"
    jobs.run_job("cut", part, {"plane": ((0, 0, 2), (0, 0, 1))}, out)
    before = {p.name: digest(p) for p in out.iterdir()}
    cut = jobs.JOBS["cut"]

    def write_then_fail(value, inp, p, o):   # every part written, then the disk fills up
        cut.write(value, inp, p, o)
        raise OSError(28, "No space left on device")
    monkeypatch.setitem(jobs.JOBS, "cut", replace(cut, write=write_then_fail))
    with pytest.raises(OSError, match="No space"):
        jobs.run_job("cut", part, {"plane": ((0, 0, 1), (0, 0, 1))}, out)
    assert {p.name: digest(p) for p in out.iterdir()} == before   # the earlier set, whole
    assert not [p for p in out.iterdir() if p.name.endswith(".staging")]


def test_cut_and_partition_refuse_an_open_mesh_before_writing(tmp_path):
    plate = box((0, 0, 0), (60, 40, 3))
    slicelab.save(slicelab.Mesh(plate.triangles[:-2]), tmp_path / "open.stl")   # two facets gone: a hole
    for args in (["cut", "--z", "1"], ["partition", "--volume", "30x30x30"]):
        out = tmp_path / args[0]
        r = run(args[0], tmp_path / "open.stl", *args[1:], "-o", out)
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
        assert "not watertight" in r.stderr and "--fill-holes" in r.stderr
        assert not out.exists() or not [p for p in out.iterdir()]
