"""One machine model for the estimate and the printer: the limits written per flavour and read back,
the planner's trapezoids and junctions against closed forms and a plain-loop planner, the limits
through settings files, and a hand-written G-code of known time. No wall-clock timing is asserted."""
from __future__ import annotations

import importlib.util
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import slicelab
from slicelab.gcode import write_gcode
from slicelab.gcode.estimate import MachineLimits, machine_limits, move_times
from slicelab.gcode.reading import file_seconds, read_moves, stated_seconds
from slicelab.gcode.writer import machine_lines
from slicelab.printing import PrintSettings, format_config, read_config, resolve_settings
from slicelab.samples import box

ROOT = Path(__file__).resolve().parents[1]

#: Limits no default has, with decimals the G-code rounds (and RepRapFirmware's mm/min turn).
ODD = dict(machine_max_acceleration_extruding=1234.567, machine_max_acceleration_retracting=987.0,
           machine_max_acceleration_travel=2345.0, machine_max_acceleration_x=3000.0, machine_max_acceleration_y=2500.0,
           machine_max_acceleration_z=150.0, machine_max_acceleration_e=4000.0, machine_max_feedrate_x=333.333,
           machine_max_feedrate_y=250.0, machine_max_feedrate_z=8.0, machine_max_feedrate_e=60.0,
           machine_max_jerk_x=7.25, machine_max_jerk_y=6.0, machine_max_jerk_z=0.333, machine_max_jerk_e=3.0)


def _check_gcode():
    spec = importlib.util.spec_from_file_location("check_gcode", ROOT / "scripts" / "check_gcode.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("check_gcode", module)  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """A small box written in each flavour with odd limits: (settings, text, totals) by flavour."""
    out = tmp_path_factory.mktemp("flavours")
    got = {}
    for flavor in ("marlin", "reprapfirmware", "klipper"):
        s = PrintSettings(pixel_size=0.1, gcode_flavor=flavor, **ODD)
        p = slicelab.plan(box((0, 0, 0), (8, 6, 1.0)), s, workers=1)
        path = out / f"{flavor}.gcode"
        totals = write_gcode(p, path, workers=1)
        got[flavor] = (s, path, path.read_text(), totals)
    return got


# ---------------------------------------------------------------------- the header, per flavour
def test_header_lines_per_flavour(written):
    live = {f: [ln.split(";")[0].strip() for ln in text.split(";LAYER_CHANGE")[0].splitlines() if ln[:1] in "GM"]
            for f, (_, _, text, _) in written.items()}
    marlin = live["marlin"]
    assert "M201 X3000 Y2500 Z150 E4000" in marlin and "M203 X333.33 Y250 Z8 E60" in marlin
    assert "M204 P1234.57 R987 T2345" in marlin and "M205 X7.25 Y6 Z0.33 E3" in marlin
    rrf = live["reprapfirmware"]  # feed rates and jerks in mm/min, no retraction acceleration
    assert "M203 X19999.98 Y15000 Z480 E3600" in rrf and "M204 P1234.57 T2345" in rrf
    assert "M566 X435 Y360 Z19.98 E180" in rrf and not any(c.startswith("M205") for c in rrf)
    klipper = live["klipper"]  # its one acceleration, nothing it would reject
    assert "M204 S1234.57" in klipper
    assert not any(c.split()[0] in ("M201", "M203", "M205", "M566") for c in klipper)
    for _, (_, _, text, _) in written.items():  # before the start G-code's heating and homing
        assert text.index("M204") < text.index("M190") < text.index(";LAYER_CHANGE")


@pytest.mark.parametrize("flavor", ["marlin", "reprapfirmware", "klipper"])
def test_the_file_read_back_states_the_estimates_limits(written, flavor):
    s, path, text, totals = written[flavor]
    f = read_moves(text)
    assert f.flavor == flavor and len(set(f.stretch.tolist())) == 1
    limits = f.limits[int(f.stretch[0])]
    want = machine_limits(s)
    if flavor == "klipper":  # the rest is the printer's own configuration: unknown to the file
        assert limits.extruding == limits.travel == limits.retracting == want.extruding == 1234.57
    else:
        for name in ("extruding", "travel", "max_acceleration", "max_feedrate", "max_jerk"):
            np.testing.assert_allclose(getattr(limits, name), getattr(want, name), rtol=1e-12, err_msg=name)
        assert limits.retracting == want.retracting == (987.0 if flavor == "marlin" else 2345.0)
        # The header's estimate is the file's, read back (the file's time under the file's limits).
        assert file_seconds(f) == pytest.approx(totals["seconds"], rel=1e-9)
        assert abs(stated_seconds(text) - totals["seconds"]) <= 0.5


def test_every_limit_line_passes_the_checker(written):
    cg = _check_gcode()
    for flavor, (_, path, text, _) in written.items():
        report = cg.check_gcode(path)
        assert report["syntax"].status == "pass", (flavor, report["syntax"])


def test_usage_time_estimate_only_and_ignore():
    quiet = PrintSettings(machine_limits_usage="time_estimate_only", **ODD)
    assert machine_lines(quiet) == ""
    assert machine_limits(quiet).extruding == 1234.567  # not rounded: nothing is written
    ignored = PrintSettings(machine_limits_usage="ignore", **ODD)
    assert machine_lines(ignored) == "" and machine_limits(ignored) == MachineLimits()


def test_acceleration_and_jerk_stand_for_the_limits_they_name():
    s = PrintSettings(acceleration=800, jerk=5, **ODD)
    m = machine_limits(s)
    assert (m.extruding, m.retracting, m.travel) == (800.0, 800.0, 800.0) and m.max_jerk[:2] == (5.0, 5.0)
    assert m.max_jerk[2:] == (0.33, 3.0)  # (Z and E keep theirs)
    assert "M204 P800 R800 T800" in machine_lines(s) and "M205 X5 Y5 Z0.33 E3" in machine_lines(s)
    defaults = machine_limits(PrintSettings())  # left at 0: the limits themselves, PrusaSlicer's defaults
    assert defaults == MachineLimits()


# ---------------------------------------------------------------------- the planner, closed forms
STILL = MachineLimits(max_jerk=(0.0, 0.0, 0.0, 0.0))  # no jerk: every move from and to a stop


@pytest.mark.parametrize("kind, d, e, a", [("travel", (100, 0, 0), 0.0, 700.0),
                                           ("printing", (60, 80, 0), 3.0, 1100.0),
                                           ("retraction", (0, 0, 0), -30.0, 450.0)])
def test_a_long_move_is_a_trapezoid_at_its_kinds_acceleration(kind, d, e, a):
    limits = STILL.replace(**{{"travel": "travel", "printing": "extruding", "retraction": "retracting"}[kind]: a})
    f, length = 40.0, float(np.linalg.norm(d)) or abs(e)
    t = move_times([[0, 0, 0]], [d], [e], [f], limits)[0]
    assert t == pytest.approx(length / f + f / a, rel=1e-12)  # L / v, plus v / a for the way up and down


def test_a_move_too_short_for_its_feed_rate_is_a_triangle():
    limits = STILL.replace(travel=1000.0)
    t = move_times([[0, 0, 0]], [[1, 0, 0]], [0.0], [50.0], limits)[0]
    assert t == pytest.approx(2 * math.sqrt(1 / 1000), rel=1e-12)  # up to sqrt(a L) halfway, and down


def test_axis_limits_cut_the_feed_rate_and_the_acceleration():
    limits = STILL.replace(max_feedrate=(500.0, 500.0, 10.0, 120.0), max_acceleration=(9000.0, 9000.0, 200.0, 1e4))
    t = move_times([[0, 0, 0]], [[0, 0, 20]], [0.0], [150.0], limits)[0]  # a Z move asked at 150 mm/s
    assert t == pytest.approx(20 / 10 + 10 / 200, rel=1e-12)
    # Diagonally, each axis runs at v / sqrt(2): X's feed rate limit binds at sqrt(2) x it.
    limits = STILL.replace(max_feedrate=(30.0, 500.0, 12.0, 120.0))
    t = move_times([[0, 0, 0]], [[100, 100, 0]], [0.0], [100.0], limits)[0]
    v = 30 * math.sqrt(2)
    assert t == pytest.approx(100 * math.sqrt(2) / v + v / 1500, rel=1e-12)


def test_jerk_starts_and_stops_a_move_at_its_safe_speed():
    limits = MachineLimits(max_jerk=(8.0, 8.0, 0.2, 2.5))
    f, a, j = 50.0, 1500.0, 8.0
    t = move_times([[0, 0, 0]], [[100, 0, 0]], [0.0], [f], limits)[0]
    assert t == pytest.approx(100 / f + (f - j) ** 2 / (a * f), rel=1e-12)
    # A right-angle corner at 50 mm/s: each axis may jump by 8 mm/s, so the corner is taken at 8.
    p = np.array([[0, 0, 0], [100, 0, 0], [100, 100, 0]], float)
    t = move_times(p[:-1], p[1:], np.zeros(2), np.full(2, f), limits)
    assert t.sum() == pytest.approx(2 * (100 / f + (f - j) ** 2 / (a * f)), rel=1e-12)
    # Straight on: no slowing at the junction.
    p = np.array([[0, 0, 0], [100, 0, 0], [200, 0, 0]], float)
    t = move_times(p[:-1], p[1:], np.zeros(2), np.full(2, f), limits)
    assert t.sum() == pytest.approx(200 / f + (f - j) ** 2 / (a * f), rel=1e-12)


def _plain_planner(start, end, e, feed, m: MachineLimits):
    """The estimate's model written with plain loops, one move and one junction at a time."""
    amax, fmax, jmax = m.max_acceleration, m.max_feedrate, m.max_jerk
    moves = []
    for s0, s1, de, f in zip(start, end, e, feed):
        d = [s1[0] - s0[0], s1[1] - s0[1], s1[2] - s0[2], de]
        xyz = math.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
        length = xyz if xyz > 0 else abs(de)
        if length == 0 or f <= 0:
            moves.append(None)
            continue
        f = max(f, m.min_travel_rate if de == 0 else m.min_extruding_rate)
        share = [abs(x) / length for x in d]
        cruise = f * min([1.0] + [fmax[i] / (share[i] * f) for i in range(4) if share[i] > 0])
        if xyz == 0:
            acc = m.retracting
        elif de > 0 and (d[0] or d[1]):
            acc = m.extruding
        else:
            acc = m.travel
        acc = min([acc] + [amax[i] / share[i] for i in range(4) if share[i] > 0])
        v = [x / length * cruise for x in d]
        safe = min([cruise] + [jmax[i] for i in range(4) if abs(v[i]) > jmax[i]])
        moves.append(dict(length=length, cruise=cruise, acc=acc, v=v, safe=safe))
    kept = [mv for mv in moves if mv is not None]
    n = len(kept)
    cap = [kept[0]["safe"] ** 2] if n else []
    for p, c in zip(kept[:-1], kept[1:]):
        vmax = min(p["cruise"], c["cruise"])
        scale = c["cruise"] / p["cruise"] if p["cruise"] > c["cruise"] else 1.0
        factor = 1.0
        for i in range(4):
            vx, vn = p["v"][i] * scale, c["v"][i]
            if vx > vn:
                jump = vx - vn if (vn > 0 or vx < 0) else max(vx, -vn)
            else:
                jump = vn - vx if (vn < 0 or vx > 0) else max(-vx, vn)
            if jump > jmax[i]:
                factor = min(factor, jmax[i] / jump)
        vj = vmax * factor
        if p["safe"] > 0.99 * vj and c["safe"] > 0.99 * vj:
            vj = c["safe"]
        cap.append(vj ** 2)
    if n:
        cap.append(kept[-1]["safe"] ** 2)
    u = list(cap)
    for j in range(1, n + 1):
        u[j] = min(u[j], u[j - 1] + 2 * kept[j - 1]["acc"] * kept[j - 1]["length"])
    for j in range(n - 1, -1, -1):
        u[j] = min(u[j], u[j + 1] + 2 * kept[j]["acc"] * kept[j]["length"])
    times, k = [], 0
    for mv in moves:
        if mv is None:
            times.append(0.0)
            continue
        f, a, L = mv["cruise"], mv["acc"], mv["length"]
        v0, v1 = math.sqrt(min(u[k], f * f)), math.sqrt(min(u[k + 1], f * f))
        k += 1
        up, down = (f * f - v0 * v0) / (2 * a), (f * f - v1 * v1) / (2 * a)
        if up + down <= L:
            times.append((f - v0) / a + (f - v1) / a + (L - up - down) / f)
        else:
            peak = math.sqrt(a * L + (v0 * v0 + v1 * v1) / 2)
            times.append((2 * peak - v0 - v1) / a)
    return np.array(times)


@pytest.mark.parametrize("seed", range(3))
def test_the_vectorised_planner_is_the_plain_one(seed):
    rng = np.random.default_rng(seed)
    n = 400
    steps = rng.normal(size=(n, 3)) * [3.0, 3.0, 0.0]
    steps[rng.random(n) < 0.05] = [0, 0, 0.2]  # Z moves
    steps[rng.random(n) < 0.05] = 0  # extrusion-only moves
    steps[rng.random(n) < 0.2] *= 0.01  # short ones
    pts = np.vstack([np.zeros(3), np.cumsum(steps, axis=0)])
    e = np.where(rng.random(n) < 0.5, 0.0, rng.exponential(0.1, n))
    e[rng.random(n) < 0.05] = -0.8
    feed = rng.choice([5.0, 25.0, 40.0, 80.0, 150.0], size=n)
    limits = MachineLimits(extruding=1250.0, retracting=900.0, travel=2000.0, max_feedrate=(200.0, 120.0, 12.0, 60.0),
                           max_acceleration=(1000.0, 1500.0, 200.0, 5000.0), max_jerk=(8.0, 10.0, 0.4, 4.5),
                           min_travel_rate=2.0)
    got = move_times(pts[:-1], pts[1:], e, feed, limits)
    np.testing.assert_allclose(got, _plain_planner(pts[:-1], pts[1:], e, feed, limits), rtol=1e-9, atol=1e-12)


# ---------------------------------------------------------------------- settings files
def test_the_limits_round_trip_through_a_settings_file(tmp_path):
    s = PrintSettings(**resolve_settings(printer="prusa-mk3"), machine_limits_usage="time_estimate_only", jerk=7.5)
    assert (s.machine_max_acceleration_x, s.machine_max_jerk_e, s.machine_max_feedrate_x) == (1000.0, 4.5, 200.0)
    f = tmp_path / "mk3.toml"
    text = format_config(s)
    f.write_text(text)
    machine = text.split("[machine]")[1].split("\n[")[0]
    assert "machine_max_acceleration_extruding = 1250.0" in machine and 'machine_limits_usage = "time_estimate_only"' \
        in machine and "acceleration = 0.0" in text.split("[motion]")[1].split("\n[")[0]
    again = PrintSettings(**read_config(f))
    assert again == s and machine_limits(again) == machine_limits(s)
    f.write_text('[machine]\nmachine_max_jerk_x = 12.5\nmachine_limits_usage = "ignore"\n[settings]\nacceleration = 2000\n')
    got = PrintSettings(**resolve_settings(config=f))
    assert got.machine_max_jerk_x == 12.5 and got.acceleration == 2000.0 and got.machine_limits_usage == "ignore"
    f.write_text("[machine]\nmachine_max_feedrate_z = 0\n")
    with pytest.raises(ValueError, match="^machine_max_feedrate_z must be above 0"):
        PrintSettings(**resolve_settings(config=f))


# ---------------------------------------------------------------------- a file of known time
def test_a_hand_written_file_of_known_time():
    text = "\n".join([
        "; flavor = marlin",
        "M201 X1000 Y1000 Z100 E5000",
        "M203 X200 Y200 Z10 E50",
        "M204 P1000 R2000 T500",
        "M205 X0 Y0 Z0 E0",  # no jerk: each move from and to a stop, on its own
        "G90", "M83",
        "M109 S210 ; heating takes no time here (nor in PrusaSlicer's estimate)",
        "G1 X100 F3000 ; travel: 100 mm at 50 mm/s, a = 500: 2 + 0.1 s",
        "G1 E-1 F3000 ; retraction: 1 mm, a = 2000, never reaching 50 mm/s: 2 sqrt(1 / 2000) s",
        "G1 Z10 F6000 ; Z: 100 mm/s cut to 10, a = 100: 1 + 0.1 s",
        "G1 X0 E5 F1200 ; printing: 100 mm at 20 mm/s, a = 1000: 5 + 0.02 s",
        "G1 F600 ; a feed rate alone is no move",
        "G92 E0",
        "G4 S2 ; a dwell: 2 s",
        "G4 P500 ; and 0.5 s",
    ]) + "\n"
    f = read_moves(text)
    assert len(f.e) == 4 and f.e.tolist() == [0.0, -1.0, 0.0, 5.0] and f.dwell == 2.5
    want = 2.1 + 2 * math.sqrt(1 / 2000) + 1.1 + 5.02 + 2.5
    assert file_seconds(f) == pytest.approx(want, rel=1e-12)
    # Absolute extrusion (M82, G92 E0) reads the same.
    absolute = text.replace("M83", "M82").replace("G1 E-1 F3000", "G1 E-1 F3000\nG92 E0")
    assert file_seconds(read_moves(absolute)) == pytest.approx(want, rel=1e-12)
    # Limits changed mid-file: the moves after run under the new ones.
    later = text.replace("G1 X0 E5 F1200", "M204 P4000\nM201 X4000\nG1 X0 E5 F1200")
    assert file_seconds(read_moves(later)) == pytest.approx(want - 5.02 + 5 + 20 / 4000, rel=1e-12)
    # RepRapFirmware states feed rates and jerks in mm/min.
    rrf = read_moves("; gcode_flavor = reprapfirmware\nM203 X12000 Y12000 Z600 E3000\nM566 X600 Y600 Z12 E120\n"
                     "G1 X1 F600\n")
    assert rrf.limits[0].max_feedrate == (200.0, 200.0, 10.0, 50.0) and rrf.limits[0].max_jerk == (10, 10, 0.2, 2)


# ---------------------------------------------------------------------- against PrusaSlicer
@pytest.mark.skipif(shutil.which("prusa-slicer") is None, reason="needs prusa-slicer")
def test_the_estimate_of_a_prusaslicer_file_is_prusaslicers(tmp_path):
    out = tmp_path / "cube.gcode"
    r = subprocess.run(["prusa-slicer", "--export-gcode", "--layer-height", "0.3", "--perimeters", "2",
                        "--fill-density", "15%", "--skirts", "0", "--machine-limits-usage", "emit_to_gcode",
                        "--gcode-flavor", "marlin2", "--machine-max-acceleration-extruding", "1000",
                        "--machine-max-jerk-x", "8", "--machine-max-jerk-y", "8", "-o", str(out),
                        str(ROOT / "data" / "cube_with_hole.stl")], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    text = out.read_text()
    assert "M204 P1000" in text
    ours, theirs = file_seconds(read_moves(text)), stated_seconds(text)
    assert ours == pytest.approx(theirs, rel=0.03)
