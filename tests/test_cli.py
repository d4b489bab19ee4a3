"""The command line: help, version, outputs, and one-line errors with exit status 2."""
import json
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

import slicelab
from slicelab.cli import COMMANDS, build_parser, main


def run(*args):
    return subprocess.run([sys.executable, "-m", "slicelab", *map(str, args)], capture_output=True, text=True)


def test_version():
    r = run("--version")
    assert r.returncode == 0 and r.stdout.startswith(f"slicelab {slicelab.__version__} (compiled kernels: ")
    from slicelab.geometry.compiled import status
    assert ("built ahead of time" in r.stdout) == (status() == "loaded")


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_has_help(command, capsys):
    with pytest.raises(SystemExit) as exc:
        main([command, "--help"])
    assert exc.value.code == 0
    assert "usage: slicelab " + command in capsys.readouterr().out


def test_inspect_json_reports_each_file(data_dir):
    r = run("inspect", data_dir / "nested_shells.stl", data_dir / "torus.stl", "--json")
    assert r.returncode == 0
    rows = [json.loads(line) for line in r.stdout.splitlines()]
    assert [row["n_shells"] for row in rows] == [3, 1]
    assert all(row["watertight"] for row in rows)


def test_inspect_carries_on_past_a_bad_file_and_exits_2(data_dir, tmp_path):
    bad = tmp_path / "bad.stl"
    bad.write_text("not a mesh")
    r = run("inspect", bad, data_dir / "sphere.stl")
    assert r.returncode == 2 and "facets            9024" in r.stdout
    assert r.stderr.count("\n") == 1 and "bad.stl" in r.stderr


def test_section_writes_svg(data_dir, tmp_path):
    out = tmp_path / "pot.svg"
    r = run("section", data_dir / "pot.stl", "--origin", "0,0,0", "--normal", "0,-1,0", "-o", out)
    assert r.returncode == 0, r.stderr
    assert "1 loops" in r.stdout and "0 open chains" in r.stdout
    assert ET.parse(out).getroot().tag.endswith("svg")


def test_layers_writes_svgs_and_json(data_dir, tmp_path):
    r = run("layers", data_dir / "cube_with_hole.stl", "--layer-height", "5", "-o", tmp_path / "L")
    assert r.returncode == 0, r.stderr
    doc = json.loads((tmp_path / "L" / "layers.json").read_text())
    assert [round(layer["z"], 9) for layer in doc["layers"]] == [2.5, 7.5, 12.5, 17.5]
    assert all(len(layer["loops"]) == 2 for layer in doc["layers"])
    assert len(list((tmp_path / "L").glob("layer_*.svg"))) == 4


@pytest.mark.parametrize("args, message", [
    (["section", "{f}", "-o", "{o}"], "give a plane"),
    (["section", "{f}", "--z", "1", "--normal", "1,0,0", "-o", "{o}"], "not both"),
    (["section", "{f}", "--origin", "0,0,0", "--normal", "0,0,0", "-o", "{o}"], "zero vector"),
    (["section", "{f}", "--origin", "0,0", "--normal", "0,0,1", "-o", "{o}"], "three"),
    (["layers", "{f}", "--layer-height", "-1", "-o", "{o}"], "positive"),
])
def test_bad_arguments_exit_2_with_one_line(data_dir, tmp_path, args, message):
    r = run(*[a.format(f=data_dir / "torus.stl", o=tmp_path / "out") for a in args])
    assert r.returncode == 2 and message in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("text", ["20", "20%", "0.2"])
def test_infill_density_takes_a_percentage_or_a_fraction(text):
    args = build_parser().parse_args(["slice", "part.stl", "-o", "part.gcode", "--infill-density", text])
    assert args.infill_density == pytest.approx(0.2)


def test_help_says_a_bare_number_up_to_1_is_a_fraction(capsys):
    with pytest.raises(SystemExit):
        main(["slice", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--infill-density" in text and "a bare number up to 1 a fraction" in text


def test_every_print_setting_flag_says_what_it_sets_and_its_default():
    """Each slice flag that sets a print setting has a help line ending in the setting's default,
    read from PrintSettings (so help and behaviour cannot drift apart)."""
    from slicelab.printing import PrintSettings, setting_names
    d = PrintSettings()
    sub = next(a for a in build_parser()._actions if a.dest == "command").choices["slice"]
    checked = 0
    for action in sub._actions:
        name = action.dest
        if name not in setting_names() or not action.option_strings or name in ("infill_density",):
            continue
        value = getattr(d, name)
        if isinstance(value, bool) or value is None:
            continue
        shown = "x".join(f"{v:g}" for v in value) if isinstance(value, tuple) else \
            (value if isinstance(value, str) else f"{value:g}")
        assert action.help and "default" in action.help, action.option_strings
        said = re.search(r"; default (.+)$", action.help % vars(action))  # as argparse shows it
        assert said and said.group(1) == shown, (action.option_strings, action.help)
        checked += 1
    assert checked >= 55   # every setting but the booleans, the texts and those derived by default


def test_a_bad_job_parameter_is_named_by_its_flag(data_dir, tmp_path):
    r = run("profile", data_dir / "pot.stl", "-o", tmp_path / "p.svg", "--planes", "0")
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert r.stderr.startswith("slicelab: error: --planes must be a whole number >= 1")
    r = run("slice", data_dir / "cube_with_hole.stl", "-o", tmp_path / "c.gcode", "--perimeters", "-1")
    assert r.returncode == 2 and "--perimeters must be" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "c.gcode").exists()


def test_layers_without_svgs(data_dir, tmp_path):
    assert main(["layers", str(data_dir / "cube_with_hole.stl"), "--layer-height", "5", "-o", str(tmp_path),
                 "--no-svg"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [".slicelab-layers.json", "layers.json"]


@pytest.mark.parametrize("good", [True, False])
def test_the_console_command_ends_quickly_but_runs_exit_handlers(data_dir, tmp_path, good):
    # The console command ends its process without the interpreter's teardown: the exit handlers
    # registered before it still run, what it printed reaches the pipe, and the status is main's.
    mesh = data_dir / "cube_with_hole.stl" if good else tmp_path / "missing.stl"
    flag = tmp_path / "handler_ran"
    code = ("import atexit, sys; from slicelab.cli import run; "
            f"atexit.register(lambda: open({str(flag)!r}, 'w').write('yes')); "
            "print('before the command', end=''); sys.argv[0] = 'slicelab'; raise SystemExit(run())")
    r = subprocess.run([sys.executable, "-c", code, "inspect", "--json", str(mesh)], capture_output=True, text=True)
    assert r.returncode == (0 if good else 2), r.stderr
    assert r.stdout.startswith("before the command") and flag.read_text() == "yes"
    if good:
        assert json.loads(r.stdout[len("before the command"):])["n_facets"] == 512
    else:
        assert r.stderr.startswith("slicelab: error:") and r.stderr.count("\n") == 1


def test_a_reader_that_leaves_early_is_no_error(data_dir):
    # `slicelab inspect ... | head -1`: the pipe closes after the first line; the command stops
    # without a word on stderr and with the status of a process ended by SIGPIPE.
    files = [str(data_dir / "cube_with_hole.stl")] * 1000  # some 330 kB: more than a pipe holds
    with subprocess.Popen([sys.executable, "-m", "slicelab", "inspect", *files], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE) as p:
        first = p.stdout.readline()
        p.stdout.close()
        err = p.stderr.read()
        status = p.wait()
    assert first.startswith(b"== ") and err == b"" and status == 141


@pytest.mark.parametrize("argv", [
    [], ["frob"], ["inspect"], ["section", "x.stl"], ["section", "x.stl", "-o", "a.svg", "--z", "high"],
    ["slice"], ["slice", "x.stl"], ["slice", "x.stl", "-o", "x.gcode", "--layer-height", "thin"],
    ["slice", "x.stl", "-o", "x.gcode", "--infill-pattern", "stars"], ["slice", "x.stl", "--perimeters", "2.5"],
    ["slice", "x.stl", "-o", "x.gcode", "--support", "sometimes"], ["partition", "x.stl", "-o", "d"],
    ["partition", "x.stl", "--volume", "1x2", "-o", "d"], ["cut", "x.stl", "--origin", "1,2", "-o", "d"],
    ["layers", "x.stl", "-o", "d"], ["profile", "x.stl", "-o", "p.svg", "--planes", "many"],
    ["batch", "d", "--task", "nothing", "-o", "o"], ["arrange", "-o", "d"], ["split", "--bogus", "x.stl"],
    ["inspect", "--units", "furlong", "x.stl"], ["slice", "x.stl", "-o", "x.gcode", "--scale", "-1"],
])
def test_every_usage_error_is_one_line_naming_the_problem_and_help(capsys, argv):
    with pytest.raises(SystemExit) as exc:
        code = main(argv)
        raise SystemExit(code)
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.count("\n") == 1, err
    assert err.startswith("slicelab") and "error:" in err and "--help" in err


def test_print_config_needs_no_output(capsys):
    assert main(["slice", "--print-config", "--printer", "generic-marlin-220", "--layer-height", "0.15"]) == 0
    shown = capsys.readouterr().out
    assert "layer_height = 0.15" in shown and "bed_size = [220.0, 220.0]" in shown


def test_an_internal_error_is_one_line_too(capsys, monkeypatch, data_dir):
    def broken(*a, **k):
        raise ZeroDivisionError("float division by zero")
    monkeypatch.setattr("slicelab.cli.analysis.run_job", broken)
    assert main(["section", str(data_dir / "cube_with_hole.stl"), "--z", "5", "-o", "x.svg"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "internal error: ZeroDivisionError" in err
