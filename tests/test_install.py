"""An installation's kernels: numba's disk cache in the user's cache folder (never beside the
package), a line on stderr only when numba compiles, ``--version`` saying which kernels run, and
the wheel's build step (setup.py, build_support/backend.py) leaving a pure wheel when it cannot
build them. The whole build of a wheel with its kernels (minutes) is measured by
scripts/bench_install.py, not here."""
from __future__ import annotations

import importlib.util
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

import slicelab
from slicelab.geometry import compiled

ROOT = Path(__file__).resolve().parents[1]
#: One small kernel called once (slicelab.files.numbers.put_text: a second or two to compile).
PROBE = ("import numpy as np\n"
         "from slicelab.files.numbers import put_text\n"
         "out = np.zeros(8, np.uint8)\n"
         "print('position', put_text(out, 1, np.frombuffer(b'ab', np.uint8).copy()))\n")


def _load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def package_copy(tmp_path_factory) -> Path:
    """The package's sources copied into a folder then made read-only (without the built module:
    the kernels go to numba), as a system's site-packages would be."""
    root = tmp_path_factory.mktemp("site")
    shutil.copytree(ROOT / "slicelab", root / "slicelab",
                    ignore=shutil.ignore_patterns("__pycache__", f"{compiled.EXTENSION}*"))
    for path in [root, *root.rglob("*")]:
        path.chmod(path.stat().st_mode & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))
    yield root
    for path in [root, *root.rglob("*")]:
        path.chmod(path.stat().st_mode | stat.S_IWUSR)


def _run(site: Path, home: Path, *args: str, env: dict | None = None, code: str = PROBE):
    """`code` (or ``python -m slicelab ARGS``) in a child importing the package from `site`, with
    `home` as its home and no cache folder named by the environment."""
    clean = {k: v for k, v in os.environ.items()
             if k not in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME", "SLICELAB_JIT", "PYTHONPATH")}
    clean.update(HOME=str(home), PYTHONPATH=str(site), **(env or {}))
    cmd = [sys.executable, "-m", "slicelab", *args] if args else [sys.executable, "-c", code]
    r = subprocess.run(cmd, capture_output=True, text=True, env=clean, cwd=home, timeout=120)
    assert r.returncode == 0, r.stderr
    return r


def _said(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.startswith("slicelab: compiling the kernels")]


def test_cache_dir_is_numba_cache_dir_where_set(monkeypatch, tmp_path):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "mine"))
    assert compiled.cache_dir() == tmp_path / "mine"


@pytest.mark.skipif(sys.platform in ("win32", "darwin"), reason="the XDG layout")
def test_cache_dir_is_in_the_users_cache(monkeypatch, tmp_path):
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    assert compiled.cache_dir() == tmp_path / ".cache" / "slicelab" / "numba"
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert compiled.cache_dir() == tmp_path / "xdg" / "slicelab" / "numba"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/path")  # not absolute: ignored, as the spec says
    assert compiled.cache_dir() == tmp_path / ".cache" / "slicelab" / "numba"


def test_first_use_compiles_once_into_the_users_cache_and_says_so(package_copy, tmp_path):
    cache = tmp_path / ".cache" / "slicelab" / "numba"
    first = _run(package_copy, tmp_path)
    assert "position 3" in first.stdout
    assert _said(first.stderr) == [compiled.COMPILING.format(cache)], first.stderr
    assert list(cache.rglob("numbers.put_text-*.nbi")) and list(cache.rglob("*.nbc"))
    assert not [p for p in package_copy.rglob("*") if p.suffix in (".nbi", ".nbc")]  # nothing beside the package
    second = _run(package_copy, tmp_path)  # loaded from the cache: nothing said
    assert "position 3" in second.stdout and _said(second.stderr) == [], second.stderr


def test_a_cache_folder_the_user_names_is_used(package_copy, tmp_path):
    mine = tmp_path / "mine"
    r = _run(package_copy, tmp_path, env={"NUMBA_CACHE_DIR": str(mine)})
    assert _said(r.stderr) == [compiled.COMPILING.format(mine)]
    assert list(mine.rglob("numbers.put_text-*.nbi")) and not (tmp_path / ".cache").exists()


def test_numba_imported_first_still_caches_in_the_users_cache(package_copy, tmp_path):
    r = _run(package_copy, tmp_path, code="import numba\n" + PROBE)
    cache = tmp_path / ".cache" / "slicelab" / "numba"
    assert _said(r.stderr) == [compiled.COMPILING.format(cache)]
    assert list(cache.rglob("numbers.put_text-*.nbi"))


def test_version_says_which_kernels_run_and_where_they_are_cached(package_copy, tmp_path):
    cache = tmp_path / ".cache" / "slicelab" / "numba"
    total = compiled.cached_kernels()[1]
    before = _run(package_copy, tmp_path, "--version").stdout.strip()
    assert before == (f"slicelab {slicelab.__version__} (compiled kernels: numba's, compiled on first use and "
                      f"cached in {cache} (none cached yet: the first command compiles them, about a minute); "
                      "the ahead-of-time module: not built)")
    _run(package_copy, tmp_path)
    after = _run(package_copy, tmp_path, "--version", env={"SLICELAB_JIT": "1"}).stdout
    assert f"cached in {cache} (1 of {total} cached); as SLICELAB_JIT=1 asks)" in after


@pytest.mark.skipif(compiled.status() != "loaded", reason="the kernels are not built ahead of time here")
def test_version_names_the_built_module_when_it_is_used():
    r = subprocess.run([sys.executable, "-m", "slicelab", "--version"], capture_output=True, text=True,
                       env={k: v for k, v in os.environ.items() if k != "SLICELAB_JIT"})
    built = next(Path(compiled.__file__).parent.glob(f"{compiled.EXTENSION}*.so"))
    assert r.stdout.strip().endswith(f"(compiled kernels: built ahead of time, {built})")


def _fake_package(build_lib: Path, build_body: str) -> None:
    """A package whose ``slicelab.geometry.compiled.build`` runs `build_body` (in the build's child)."""
    geometry = build_lib / "slicelab" / "geometry"
    geometry.mkdir(parents=True)
    (build_lib / "slicelab" / "__init__.py").write_text("")
    (geometry / "__init__.py").write_text("")
    (geometry / "compiled.py").write_text(f"from pathlib import Path\ndef build():\n{build_body}")


def test_the_build_step_says_why_it_built_no_kernels(tmp_path, capsys):
    setup = _load("slicelab_setup", ROOT / "setup.py")
    _fake_package(tmp_path, "    return 'kernels not built ahead of time (CompileError: no cc)'\n")
    assert setup.build_kernels(tmp_path) is False
    err = capsys.readouterr().err
    assert err == "slicelab: kernels not built ahead of time (CompileError: no cc)\n"
    _fake_package(tmp_path / "other", "    raise ImportError('No module named numba')\n")
    assert setup.build_kernels(tmp_path / "other") is False
    err = capsys.readouterr().err
    assert err.startswith("slicelab: kernels not built ahead of time (") and "No module named numba" in err
    assert err.endswith("; numba compiles them on first use\n")


def test_the_build_step_reports_the_module_it_built(tmp_path, capsys):
    setup = _load("slicelab_setup", ROOT / "setup.py")
    _fake_package(tmp_path, "    (Path(__file__).parent / '_aot_kernels.json').write_text('{}')\n"
                            "    return '3 kernel forms built ahead of time into _aot_kernels.so'\n")
    assert setup.build_kernels(tmp_path) is True
    assert capsys.readouterr().err == "slicelab: 3 kernel forms built ahead of time into _aot_kernels.so\n"


def test_the_backend_asks_for_numba_only_to_build_a_wheel_with_a_compiler(monkeypatch):
    pytest.importorskip("setuptools")
    backend = _load("slicelab_backend", ROOT / "build_support" / "backend.py")
    monkeypatch.setattr(backend._setuptools, "get_requires_for_build_wheel", lambda config_settings=None: [])
    monkeypatch.delenv("SLICELAB_BUILD_KERNELS", raising=False)
    monkeypatch.setattr(backend, "c_compiler", lambda: "/usr/bin/cc")
    assert backend.get_requires_for_build_wheel() == backend.KERNEL_REQUIRES
    monkeypatch.setattr(backend, "c_compiler", lambda: None)
    assert backend.get_requires_for_build_wheel() == []
    monkeypatch.setattr(backend, "c_compiler", lambda: "/usr/bin/cc")
    monkeypatch.setenv("SLICELAB_BUILD_KERNELS", "0")
    assert backend.get_requires_for_build_wheel() == []
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.setenv("CC", "/nonexistent/cc -O2")
    assert _load("slicelab_backend2", ROOT / "build_support" / "backend.py").c_compiler() is None
