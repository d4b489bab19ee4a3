"""Batch runs: statuses and reasons, no lost report, resumable reruns; pool and Dask give the same summary;
the command line and a batch write the same files for the same job; each input its own output folder;
pipes and devices reported unread; a time limit per file."""
import csv
import hashlib
import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import slicelab
from slicelab import Mesh, samples
from slicelab.cli import main
from slicelab.tasks import ParameterError, batch, run_jobs
from slicelab.tasks.batch import find_mesh_files, run_batch, task_parameters

EXPECTED = {  # file -> (status, reason codes) for the profile task
    "pot.stl": ("ok", []),
    "vessels/bowl.stl": ("ok", []),
    "vessels/deep/cup.STL": ("ok", []),
    "cube.stl": ("warn", ["upside_down_risk", "not_revolution"]),  # no base, no rim: up from the centre of mass
    "open_pot.stl": ("warn", ["not_watertight"]),
    "nested.stl": ("warn", ["several_shells", "upside_down_risk", "sealed", "not_revolution"]),
    "pot_in_metres.stl": ("warn", ["units?"]),
    "broken/truncated.stl": ("fail", ["unreadable"]),
    "broken/photo.stl": ("fail", ["unreadable"]),
    "broken/empty.stl": ("fail", ["unreadable"]),
    # A ring of wall broken below a whole lip: its sections are now closed across the break (a fail,
    # "no closed section", before); with no base, up from the opening is said to be a guess (it is
    # upside down: the break is taken for the rim) and no capacity is given.
    "broken/no_closed_section.stl": ("warn", ["not_watertight", "upside_down_risk", "open_rim"]),
}


def _bowl():
    z = np.linspace(0, 1, 13)
    outer = np.column_stack([20 + 25 * np.sqrt(z), 40 * z])
    inner = np.column_stack([17 + 25 * np.sqrt(z[::-1]), 4 + 36 * z[::-1]])
    return samples.revolve(np.vstack([[[0, 0]], outer, inner, [[0, 4]]]), 48)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("scans")
    pot = samples.pot(30, 36)
    slicelab.save(pot, d / "pot.stl")
    slicelab.save(_bowl(), d / "vessels" / "bowl.stl")
    slicelab.save(samples.revolve([[0, 0], [30, 0], [30, 50], [27, 50], [27, 3], [0, 3]], 40),
                  d / "vessels" / "deep" / "cup.STL")
    slicelab.save(samples.box((0, 0, 0), (20, 20, 20)), d / "cube.stl")
    keep = np.linalg.norm(pot.triangles.mean(axis=1) - [0, 55, 60], axis=1) > 12
    slicelab.save(Mesh(pot.triangles[keep]), d / "open_pot.stl")
    slicelab.save(samples.nested_shells(), d / "nested.stl")
    slicelab.save(Mesh(pot.triangles / 1000), d / "pot_in_metres.stl")
    raw = (d / "pot.stl").read_bytes()
    (d / "broken").mkdir()
    (d / "broken" / "truncated.stl").write_bytes(raw[: len(raw) // 2])
    (d / "broken" / "photo.stl").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(200))
    (d / "broken" / "empty.stl").write_bytes(b"")
    upper = pot.triangles[pot.triangles[..., 2].min(axis=1) > 30]  # a ring of wall: no section closes
    slicelab.save(Mesh(upper), d / "broken" / "no_closed_section.stl")
    (d / "notes.txt").write_text("scanned 2024-05-01\n")
    (d / "vessels" / "photo.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    (d / ".hidden.stl").write_bytes(raw)
    return d


def output_files(rep):
    files = []
    for v in rep["outputs"].values():
        files += v if isinstance(v, list) else [v]
    return files


def read_summary(out):
    with open(out / "summary.csv", newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def profile_run(folder, tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    params = task_parameters("profile", planes=3)
    return out, params, run_batch(folder, out, "profile", params, workers=1, progress=False)


def test_find_mesh_files(folder):
    files, other = find_mesh_files(folder)
    assert sorted(p.relative_to(folder).as_posix() for p in files) == sorted(EXPECTED)
    assert other == 2
    kept, _ = find_mesh_files(folder, patterns=("broken/*", "*.STL"))
    assert len(kept) == len(EXPECTED) - 5


def test_profile_batch_statuses_reasons_and_reports(folder, profile_run):
    out, params, result = profile_run
    assert result.ran == len(EXPECTED) and result.skipped == 0 and result.ignored == 2
    got = {r["file"]: (r["status"], [x["code"] for x in r["reasons"]]) for r in result.reports}
    assert got == EXPECTED
    for rel, (status, _) in EXPECTED.items():
        rep = json.loads((out / f"{rel}.json").read_text())  # one report per file, none lost
        assert rep["status"] == status and rep["task"] == "profile" and rep["parameters"] == params
        assert rep["input"]["sha256"] == hashlib.sha256((folder / rel).read_bytes()).hexdigest()
        assert rep["timings"]["total"] >= 0 and all(r["message"] for r in rep["reasons"])
        for path in output_files(rep):
            assert (out / path).exists()
        if status != "fail":
            assert {Path(p).parent for p in output_files(rep)} == {Path(rel)}  # OUT/pot.stl/...
            root = ET.parse(out / rep["outputs"]["svg"]).getroot()
            assert {g.get("id") for g in root.iter("{http://www.w3.org/2000/svg}g")} >= {"section", "axis"}
    pot = json.loads((out / "pot.stl.json").read_text())["results"]
    assert pot["max_diameter"] == pytest.approx(124.0, rel=0.01)
    assert "PNG" in json.loads((out / "broken/photo.stl.json").read_text())["reasons"][0]["message"]
    rows = read_summary(out)
    assert [r["file"] for r in rows] == sorted(EXPECTED)
    assert {r["file"]: r["status"] for r in rows} == {k: v[0] for k, v in EXPECTED.items()}
    assert float(next(r for r in rows if r["file"] == "pot.stl")["rim_diameter_mm"]) == pytest.approx(97.6, rel=0.01)
    assert not (out / ".hidden.stl.json").exists()


def test_rerun_skips_finished_files_and_resumes(folder, tmp_path):
    out = tmp_path / "out"
    params = task_parameters("section")
    first = run_batch(folder, out, "section", params, workers=1, progress=False)
    stamps = {p: p.stat().st_mtime_ns for p in out.rglob("*.json")}
    summary = read_summary(out)
    again = run_batch(folder, out, "section", params, workers=1, progress=False)
    assert first.ran == len(EXPECTED) and again.ran == 0 and again.skipped == len(EXPECTED)
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*.json")} == stamps
    assert read_summary(out) == summary
    # Interrupted runs: a missing report, a missing output, a changed input are redone, nothing else.
    (out / "cube.stl.json").unlink()
    (out / "pot.stl" / "section.svg").unlink()
    slicelab.save(samples.box((0, 0, 0), (30, 20, 20)), tmp_path / "box.stl")
    bowl = folder / "vessels" / "bowl.stl"
    original = bowl.read_bytes()
    try:
        bowl.write_bytes((tmp_path / "box.stl").read_bytes())
        resumed = run_batch(folder, out, "section", params, workers=1, progress=False)
        assert resumed.ran == 3
        assert json.loads((out / "vessels/bowl.stl.json").read_text())["input"]["sha256"] == \
            hashlib.sha256(bowl.read_bytes()).hexdigest()
    finally:
        bowl.write_bytes(original)
    # Same content, new time stamp: the hash says it is unchanged.
    os.utime(folder / "cube.stl")
    assert run_batch(folder, out, "section", params, workers=1, progress=False).ran == 1  # the bowl, restored
    # Other parameters make every report stale; --retry-failed redoes failures only.
    other = task_parameters("section", origin=(0, 0, 5), normal=(0, 0, 1))
    assert run_batch(folder, out, "section", other, workers=1, progress=False).ran == len(EXPECTED)
    n_fail = sum(v[0] == "fail" for v in EXPECTED.values())  # the unreadable ones (the open ring now profiles)
    assert run_batch(folder, out, "section", other, workers=1, progress=False, retry_failed=True).ran == n_fail


def test_process_pool_gives_the_same_summary(folder, tmp_path):
    a = run_batch(folder, tmp_path / "a", "inspect", workers=1, progress=False)
    b = run_batch(folder, tmp_path / "b", "inspect", workers=2, progress=False)
    assert b.ran == len(EXPECTED)
    assert read_summary(tmp_path / "a") == read_summary(tmp_path / "b")
    assert len({r["worker"] for r in b.reports}) >= 1 and a.count("fail") == b.count("fail") == 3


def test_dask_local_cluster_gives_the_same_summary(folder, profile_run, tmp_path):
    distributed = pytest.importorskip("distributed")
    out, params, local = profile_run
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        result = run_batch(folder, tmp_path / "dask", "profile", params, scheduler=cluster.scheduler_address,
                           progress=False)
    assert result.ran == len(EXPECTED)
    assert (tmp_path / "dask" / "summary.csv").read_text() == (out / "summary.csv").read_text()
    for rep in result.reports:  # the same outputs, byte for byte
        for path in rep["outputs"].values():
            if path.endswith((".svg", ".json")):
                assert (tmp_path / "dask" / path).read_bytes() == (out / path).read_bytes()


def test_dead_workers_still_leave_a_report_each(tmp_path):
    """Workers that die (here: a script without a __main__ guard, whose workers re-run it and crash)
    cost their files a fail report each, marked transient, so the next run retries them."""
    import subprocess
    scans, out = tmp_path / "scans", tmp_path / "out"
    for k in range(3):
        slicelab.save(samples.box((0, 0, 0), (10 + k, 10, 10)), scans / f"box{k}.stl")
    script = tmp_path / "unguarded.py"
    script.write_text("from slicelab.tasks import run_batch\n"
                      f"run_batch({str(scans)!r}, {str(out)!r}, 'inspect', workers=2, progress=False)\n")
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    rows = read_summary(out)
    assert [r["file"] for r in rows] == ["box0.stl", "box1.stl", "box2.stl"]
    assert {(r["status"], r["reasons"]) for r in rows} == {("fail", "worker_lost")}
    assert "__main__" in rows[0]["messages"]
    again = run_batch(scans, out, "inspect", workers=1, progress=False)
    assert again.ran == 3 and again.count("ok") == 3


def _origin_volume(triangles):
    t = np.asarray(triangles)
    return float(np.einsum("ij,ij->", t[:, 0], np.cross(t[:, 1], t[:, 2])) / 6)


def test_split_task(folder, tmp_path):
    out = tmp_path / "out"
    result = run_batch(folder, out, "split", task_parameters("split", origin=(0, 0, 40), normal=(0, 0, 1)),
                       workers=1, progress=False)
    rep = next(r for r in result.reports if r["file"] == "pot.stl")
    assert rep["status"] == "ok"
    front, rear = slicelab.load(out / rep["outputs"]["front"]), slicelab.load(out / rep["outputs"]["rear"])
    assert front.bounds[0, 2] >= 40 - 1e-4 and rear.bounds[1, 2] <= 40 + 1e-4
    # Nothing lost: the pieces enclose the original's volume together (float32 files: loose tolerance).
    whole = slicelab.load(folder / "pot.stl")
    assert _origin_volume(front.triangles) + _origin_volume(rear.triangles) == \
        pytest.approx(_origin_volume(whole.triangles), rel=1e-5)
    assert rep["results"]["section_loops"] == 2 and rep["results"]["cut_facets"] > 0
    ET.parse(out / rep["outputs"]["svg"])


def test_layers_task(folder, tmp_path):
    result = run_batch(folder, tmp_path, "layers", task_parameters("layers", layer_height=5.0), workers=1,
                       progress=False)
    rep = next(r for r in result.reports if r["file"] == "cube.stl")
    assert rep["status"] == "ok" and rep["results"]["layers"] == 4
    data = json.loads((tmp_path / rep["outputs"]["json"]).read_text())
    assert [round(x["area"], 9) for x in data["layers"]] == [400.0] * 4


def test_cli_batch(folder, tmp_path, capsys):
    out = tmp_path / "out"
    status = main(["batch", str(folder), "-o", str(out), "--task", "section", "--z", "10", "--workers", "1",
                   "--no-progress"])
    assert status == 1  # some files failed; every one has its report
    assert len(read_summary(out)) == len(EXPECTED)
    text = capsys.readouterr().out
    assert "3 fail" in text and "summary.csv" in text
    assert main(["batch", str(folder), "-o", str(out), "--task", "layers"]) == 2
    assert main(["batch", str(folder), "-o", str(out), "--task", "profile", "--z", "3"]) == 2
    assert main(["batch", str(tmp_path / "missing"), "-o", str(out), "--task", "inspect"]) == 2
    assert main(["batch", str(folder), "-o", str(out), "--task", "inspect", "--workers", "0"]) == 2
    assert main(["batch", str(folder), "-o", str(out), "--task", "section", "--planes", "3"]) == 2
    assert "error" in capsys.readouterr().err
    assert main(["batch", str(folder), "-o", str(out), "--task", "inspect", "--timeout", "-1"]) == 2
    err = capsys.readouterr().err
    assert "--timeout" in err and len(err.strip().splitlines()) == 1


def test_batch_help_names_every_format(capsys):
    with pytest.raises(SystemExit):
        main(["batch", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert all(e in text for e in (".stl", ".ply", ".obj", ".3mf", "--timeout", "default 900 s"))
    assert "*.stl" not in text and "STL file" not in text


def _sha256(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _save_obj(mesh, path):
    path.parent.mkdir(parents=True, exist_ok=True)
    v = mesh.triangles.reshape(-1, 3)
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in v]
    lines += [f"f {3 * k + 1} {3 * k + 2} {3 * k + 3}" for k in range(len(mesh.triangles))]
    path.write_text("\n".join(lines) + "\n")


def test_each_input_gets_its_own_output_folder_and_report(tmp_path):
    """Inputs that differ by ending or by case only, and names on the batch's own summary.csv."""
    scans, out = tmp_path / "scans", tmp_path / "out"
    sides = {"dup.stl": 10, "dup.STL": 20, "dup.obj": 30, "summary.csv.stl": 40, "summary.csv/inner.stl": 50}
    for name, side in sides.items():
        box = samples.box((0, 0, 0), (side, side, 10))
        _save_obj(box, scans / name) if name.endswith(".obj") else slicelab.save(box, scans / name)
    params = task_parameters("section")
    result = run_batch(scans, out, "section", params, workers=1, progress=False)
    assert result.count("ok") == len(sides) and str(result).startswith("5 mesh files: 5 ok")
    assert (out / "summary.csv").is_file()
    rows = read_summary(out)
    # 'dup.STL' sorts first and keeps its name; 'dup.stl' would share its folder on a case-insensitive disk.
    assert {r["file"]: r["report"] for r in rows} == {
        "dup.STL": "dup.STL.json", "dup.obj": "dup.obj.json", "dup.stl": "dup.stl~2.json",
        "summary.csv.stl": "summary.csv.stl.json", "summary.csv/inner.stl": "summary.csv~2/inner.stl.json"}
    for row in rows:  # each report and each output is its own input's
        rep = json.loads((out / row["report"]).read_text())
        assert rep["file"] == row["file"] and rep["input"]["sha256"] == _sha256(scans / row["file"])
        (svg,) = output_files(rep)
        assert Path(svg).parent.as_posix() + ".json" == row["report"]  # the folder beside its report
        area = float(re.search(r"area ([0-9.e+]+) mm2", (out / svg).read_text()).group(1))
        assert area == pytest.approx(sides[row["file"]] ** 2, rel=1e-6)
    names = [p.name for p in out.iterdir()]
    assert len({n.casefold() for n in names}) == len(names)
    again = run_batch(scans, out, "section", params, workers=1, progress=False)
    assert (again.ran, again.skipped) == (0, len(sides)) and read_summary(out) == rows
    # A report whose outputs lie in a folder of the old layout, shared by dup.*, is not up to date.
    rep = json.loads((out / "dup.obj.json").read_text())
    (out / "dup").mkdir()
    shutil.copy(out / rep["outputs"]["svg"], out / "dup" / "section.svg")
    rep["outputs"]["svg"] = "dup/section.svg"
    (out / "dup.obj.json").write_text(json.dumps(rep))
    assert run_batch(scans, out, "section", params, workers=1, progress=False).ran == 1
    assert json.loads((out / "dup.obj.json").read_text())["outputs"]["svg"] == "dup.obj/section.svg"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes: POSIX")
def test_pipes_and_devices_are_reported_not_read(tmp_path):
    """Reading a named pipe that nobody writes never ends: the batch runs in a subprocess, so that a
    regression fails instead of hanging the tests."""
    scans, out = tmp_path / "scans", tmp_path / "out"
    slicelab.save(samples.box((0, 0, 0), (10, 10, 10)), scans / "cube.stl")
    os.mkfifo(scans / "pipe.stl")
    (scans / "link.stl").symlink_to(scans / "cube.stl")  # a link to a file is that file
    devices = Path("/dev/null").exists() and not Path("/dev/null").is_file()
    if devices:
        (scans / "null.obj").symlink_to("/dev/null")
    command = [sys.executable, "-m", "slicelab", "batch", str(scans), "-o", str(out), "--task", "inspect",
               "--no-progress"]
    for more in (["--workers", "1", "--timeout", "0"], ["--workers", "2"]):  # in the process, then on workers
        proc = subprocess.run(command + more, cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert proc.returncode == 1, proc.stdout[-2000:] + proc.stderr[-2000:]
        assert "fail pipe.stl: not a regular file but a named pipe (FIFO): not read" in proc.stdout
    rows = {r["file"]: r for r in read_summary(out)}
    assert (rows["pipe.stl"]["status"], rows["pipe.stl"]["reasons"]) == ("fail", "not_a_file")
    assert json.loads((out / "pipe.stl.json").read_text())["reasons"][0]["code"] == "not_a_file"
    assert rows["link.stl"]["status"] == rows["cube.stl"]["status"] == "ok"
    assert rows["link.stl"]["sha256"] == rows["cube.stl"]["sha256"] == _sha256(scans / "cube.stl")
    if devices:
        assert rows["null.obj"]["reasons"] == "not_a_file" and "character device" in rows["null.obj"]["messages"]


def test_cli_batch_time_limit_per_file(tmp_path, capsys):
    """The limit counts every file's whole run: 1 ms is too short for any real file."""
    scans, out = tmp_path / "scans", tmp_path / "out"
    slicelab.save(samples.pot(40, 120), scans / "pot.stl")
    slicelab.save(samples.pot(30, 60), scans / "small" / "pot.stl")
    args = ["batch", str(scans), "-o", str(out), "--task", "section", "--workers", "1", "--no-progress"]
    assert main(args + ["--timeout", "0.001"]) == 1
    text = capsys.readouterr().out
    assert "2 mesh files: 0 ok, 0 warn, 2 fail" in text and "time limit" in text
    rows = read_summary(out)
    assert [(r["file"], r["status"], r["reasons"]) for r in rows] == \
        [("pot.stl", "fail", "timeout"), ("small/pot.stl", "fail", "timeout")]
    rep = json.loads((out / "pot.stl.json").read_text())
    assert rep["time_limit"] == 0.001 and "0.001 s" in rep["reasons"][0]["message"]
    # The same limit: not run again; a longer one (the default, 900 s) runs them, and they pass.
    assert main(args + ["--timeout", "0.001"]) == 1 and "(0 run, 2 up to date" in capsys.readouterr().out
    assert main(args) == 0 and "2 mesh files: 2 ok" in capsys.readouterr().out
    assert [r["status"] for r in read_summary(out)] == ["ok", "ok"]


def test_bad_parameters():
    with pytest.raises(ValueError):
        task_parameters("carve")
    with pytest.raises(ValueError):
        task_parameters("section", origin=(0, 0, 0))
    with pytest.raises(ValueError):
        task_parameters("layers")
    with pytest.raises(ValueError):
        task_parameters("profile", side="middle")


def test_bad_parameters_name_the_parameter():
    for task, options, name in [("layers", {}, "layer_height"), ("profile", {"planes": 0}, "planes"),
                                ("section", {"max_gap": -1}, "max_gap"), ("split", {"visible_from": (0, 0, 0)},
                                                                          "visible_from"),
                                ("section", {"planes": 3}, "planes"), ("profile", {"origin": (0, 0, 0),
                                                                                   "normal": (0, 0, 1)}, "plane"),
                                ("inspect", {"min_size": 10, "max_size": 1}, "min_size")]:
        with pytest.raises(ParameterError) as err:
            task_parameters(task, **options)
        assert err.value.name == name and str(err.value).startswith(name)
    params = task_parameters("split", origin=(0, 0, 1), normal=(0, 0, 1), preview=False)
    assert task_parameters("split", **params) == params  # checking is idempotent


@pytest.mark.parametrize("job, cli_args, options", [
    ("split", ["--z", "40"], {"origin": (0, 0, 40), "normal": (0, 0, 1)}),
    ("layers", ["--layer-height", "20"], {"layer_height": 20}),
])
def test_cli_and_batch_write_the_same_files(tmp_path, job, cli_args, options):
    scans = tmp_path / "scans"
    slicelab.save(samples.pot(30, 36), scans / "pot.stl")
    assert main([job, str(scans / "pot.stl"), *cli_args, "-o", str(tmp_path / "cli")]) == 0
    result = run_batch(scans, tmp_path / "batch", job, task_parameters(job, **options), workers=1, progress=False)
    assert result.count("ok") == 1
    cli, bat = tmp_path / "cli", tmp_path / "batch" / "pot.stl"
    # The outputs; hidden files are the folder's own bookkeeping (a manifest), not outputs.
    names = sorted(p.name for p in cli.iterdir() if not p.name.startswith("."))
    assert names == sorted(p.name for p in bat.iterdir() if not p.name.startswith(".")) and len(names) >= 3
    assert sorted(Path(p).name for p in output_files(result.reports[0])) == names
    for name in names:
        if name.endswith((".svg", ".json")):
            assert (cli / name).read_bytes() == (bat / name).read_bytes(), name
        elif name.endswith(".stl"):
            assert np.array_equal(slicelab.load(cli / name).triangles, slicelab.load(bat / name).triangles)


def test_forkserver_preload_names_modules_that_exist():
    for name in batch._PRELOAD:
        assert importlib.util.find_spec(name) is not None, name


def test_run_jobs_reports_jobs_whose_process_died():
    """os._exit kills the worker: the pool breaks, each job is retried alone, then reported lost."""
    done = []
    run_jobs(os._exit, [(3,), (4,)], workers=2, on_done=lambda job, r, lost: done.append((job, r, lost)))
    assert sorted(job for job, _, _ in done) == [(3,), (4,)]
    assert all(r is None and "__main__" in lost for _, r, lost in done)


def test_dask_with_relative_paths_and_workers_in_another_folder(tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    scans = tmp_path / "here" / "scans"
    slicelab.save(samples.box((0, 0, 0), (10, 10, 10)), scans / "cube.stl")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=50) as cluster:
        monkeypatch.chdir(tmp_path / "here")  # the workers stay where they started
        result = run_batch(Path("scans"), Path("out"), "inspect", scheduler=cluster.scheduler_address,
                           progress=False)
    assert [r["status"] for r in result.reports] == ["ok"]


def test_a_cluster_with_no_worker_left_ends_with_a_clear_error(tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    from slicelab.tasks import executors
    monkeypatch.setattr(executors, "_NO_WORKER_WAIT", 1.0)
    scans = tmp_path / "scans"
    for k in range(3):
        slicelab.save(samples.box((0, 0, 0), (10 + k, 10, 10)), scans / f"box{k}.stl")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None,
                                  silence_logs=50) as cluster:
        with distributed.Client(cluster) as c:
            c.retire_workers(list(c.scheduler_info()["workers"]))  # every worker gone
            deadline = time.time() + 30
            while c.scheduler_info()["workers"] and time.time() < deadline:
                time.sleep(0.1)
        t0 = time.time()
        with pytest.raises(executors.NoWorkersLeft, match="no worker left"):
            run_batch(scans, tmp_path / "out", "inspect", scheduler=cluster.scheduler_address, progress=False)
        assert time.time() - t0 < 60
    rows = read_summary(tmp_path / "out")
    assert [r["status"] for r in rows] == ["fail"] * 3 and all("no worker left" in r["messages"] for r in rows)


def test_cli_batch_profile_outputs_can_be_left_out_and_none_stays_stale(tmp_path, capsys):
    """DXF and CSV by default; --no-dxf --no-csv --no-png leave them out, and a rerun so takes away
    the ones an earlier run wrote (they would no longer match the report)."""
    scans, out = tmp_path / "scans", tmp_path / "out"
    slicelab.save(samples.pot(30, 36), scans / "pot.stl")
    args = ["batch", str(scans), "-o", str(out), "--task", "profile", "--planes", "2", "--workers", "1",
            "--no-progress"]
    assert main(args) == 0
    assert "rim_diameters.png" in capsys.readouterr().out
    assert sorted(p.name for p in (out / "pot.stl").iterdir() if p.name[0] != ".") == \
        ["profile.csv", "profile.dxf", "profile.json", "profile.png", "profile.svg"]
    assert main(args + ["--no-dxf", "--no-csv", "--no-png"]) == 0
    assert sorted(p.name for p in (out / "pot.stl").iterdir() if p.name[0] != ".") == ["profile.json", "profile.svg"]
    assert sorted(json.loads((out / "pot.stl.json").read_text())["outputs"]) == ["json", "svg"]
    capsys.readouterr()
    assert main(["batch", str(scans), "-o", str(out), "--task", "section", "--no-dxf"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "dxf" in err
