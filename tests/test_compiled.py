"""The kernels built ahead of time: the same results as numba's, only for the types they were built for."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from slicelab.geometry import compiled
from slicelab.geometry.segment_kernels import douglas_peucker

ROOT = Path(__file__).resolve().parents[1]
BUILT = (Path(compiled.__file__).parent / f"{compiled.EXTENSION}.json").exists()
needs_built = pytest.mark.skipif(not BUILT, reason="kernels not built ahead of time here (no C compiler?)")


@pytest.fixture
def restore_kernels():
    yield
    compiled.select()


@needs_built
def test_the_built_module_is_the_sources_now():
    # Built from other sources (a kernel edited since `make`), it would not be used: rebuild.
    assert compiled.status() == "loaded", "run `make` (or slicelab.geometry.compiled.build()) again"


@needs_built
def test_a_slice_from_built_kernels_is_the_slice_from_numba(tmp_path):
    # The whole command, once from the built module and once from numba's forms alone
    # (SLICELAB_JIT=1): the G-code files read back are the same byte for byte, and the
    # command that used the built module never imported numba.
    # (Said by an exit handler: the command ends its process once it is done, exit handlers run.)
    probe = ("import atexit, runpy, sys; sys.argv = sys.argv[1:]; "
             "atexit.register(lambda: print('numba imported:', 'numba' in sys.modules)); "
             "runpy.run_module('slicelab', run_name='__main__')")
    outs = {}
    for mode in ("0", "1"):
        out = tmp_path / f"jit{mode}.gcode"
        env = {k: v for k, v in os.environ.items() if k != "SLICELAB_JIT"} | {"SLICELAB_JIT": mode}
        r = subprocess.run([sys.executable, "-c", probe, "slicelab", "slice", str(ROOT / "data" / "nested_shells.stl"),
                            "-o", str(out), "--workers", "1"], capture_output=True, text=True, env=env, cwd=ROOT)
        assert r.returncode == 0, r.stderr
        assert f"numba imported: {mode == '1'}" in r.stdout
        outs[mode] = out.read_bytes()
    assert outs["0"] == outs["1"] and outs["0"].count(b";LAYER_CHANGE") > 10


@needs_built
def test_arguments_of_other_types_go_to_numba(restore_kernels):
    # Built for C-contiguous float64 points: a strided view and float32 points are not in the
    # table, so numba takes them (a built function given them would read the wrong memory).
    rng = np.random.default_rng(3)
    pts = np.cumsum(rng.normal(size=(400, 2)), axis=0)
    keep = np.zeros(400, bool)
    keep[[0, -1]] = True
    wide = np.zeros((400, 4))
    wide[:, :2] = pts
    strided = wide[:, :2]
    compiled.status()  # the built module's tables loaded (run alone, no kernel has been called yet)
    assert compiled.arguments_key((strided, keep, 0.5)) not in douglas_peucker.table
    assert compiled.arguments_key((pts, keep, 0.5)) in douglas_peucker.table
    expected = douglas_peucker(pts, keep.copy(), 0.5)
    assert 3 < np.count_nonzero(expected) < 400
    assert np.array_equal(douglas_peucker(strided, keep.copy(), 0.5), expected)
    p32 = pts.astype(np.float32)
    assert np.array_equal(douglas_peucker(p32, keep.copy(), 0.5), douglas_peucker.jit()(p32, keep.copy(), 0.5))
    compiled.select(False)  # numba alone: the same answer
    assert np.array_equal(douglas_peucker(pts, keep.copy(), 0.5), expected)


def test_a_module_built_from_other_sources_is_not_used(restore_kernels, monkeypatch):
    # (restore_kernels first: torn down last, once the hash is the real one again)
    monkeypatch.setattr(compiled, "_sources_hash", lambda modules: "another version of the kernels")
    state = compiled.select()
    assert state == ("stale (built from other sources)" if BUILT else "not built")
    assert douglas_peucker.table == {}
    pts = np.array([[0, 0], [1, 0.001], [2, 0], [2, 2]], float)
    keep = np.array([True, False, False, True])
    assert douglas_peucker(pts, keep, 0.01).tolist() == [True, False, True, True]


def test_arguments_key_types_as_numba_does():
    numba = pytest.importorskip("numba")
    from numba.core import types
    a = np.zeros((4, 3), np.float32)
    frozen = np.arange(5)
    frozen.flags.writeable = False
    for value in (a, a.T, a[:, 1], frozen, np.zeros(3, bool), 7, 2.5, True, np.uint8(3), np.float32(1)):
        t = numba.typeof(value)
        if isinstance(t, types.Array):
            expected = (np.dtype(str(t.dtype)).str, t.ndim, t.layout, bool(t.mutable))
        else:
            expected = np.dtype(str(t)).str
        assert compiled.arguments_key((value,)) == (expected,), value
    assert compiled.arguments_key(([1, 2],)) is None
