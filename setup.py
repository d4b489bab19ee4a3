"""setuptools' build, one step more: the compiled kernels built ahead of time into the wheel.

After ``build_py`` has copied the package into the build folder, the kernels are compiled there
(`slicelab.geometry.compiled.build`, numba's ``pycc`` and a C compiler; a few minutes), so the
wheel carries the extension module and its table, and an installation never compiles at run
time. Where that cannot be (no numba or no C compiler in the build environment, or
``SLICELAB_BUILD_KERNELS=0``), the wheel is a pure one and the kernels are compiled by numba on
first use, cached in the user's cache folder. An editable install (``pip install -e .``, which
``make`` uses) builds nothing here: ``make`` builds the kernels beside the sources.

The build backend (build_support/backend.py) asks for numba and numpy in the build environment
only for a wheel, and only where a C compiler is found.
"""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

try:
    from setuptools.command.bdist_wheel import bdist_wheel
except ImportError:  # setuptools before 70.1
    try:
        from wheel.bdist_wheel import bdist_wheel
    except ImportError:
        bdist_wheel = None

#: The built module and its table, under the package (slicelab.geometry.compiled.EXTENSION).
BUILT = ("slicelab", "geometry", "_aot_kernels")


class BuildWithKernels(build_py):
    """build_py, then the kernels compiled ahead of time into the copy in the build folder."""

    kernels_built = False

    def run(self):
        super().run()
        folder = Path(self.build_lib, *BUILT[:-1])
        for old in folder.glob(f"{BUILT[-1]}*"):  # from an earlier build in the same folder
            old.unlink()
        if getattr(self, "editable_mode", False) or self.dry_run:
            return
        if os.environ.get("SLICELAB_BUILD_KERNELS") == "0":
            self.announce("slicelab: SLICELAB_BUILD_KERNELS=0: a pure wheel, kernels compiled on first use", 2)
            return
        if importlib.util.find_spec("numba") is None:
            print("slicelab: kernels not built ahead of time (no numba in the build environment: "
                  "no C compiler was found); numba compiles them on first use", file=sys.stderr)
            return
        self.kernels_built = build_kernels(Path(self.build_lib))


def build_kernels(build_lib: Path) -> bool:
    """Compile the kernels of the package copied under `build_lib`, in a child process that
    imports that copy (numba's disk cache, which the build also fills, goes to a temporary
    folder); say what happened on stderr; whether the module and its table were written."""
    code = "from slicelab.geometry import compiled; print(compiled.build())"
    with tempfile.TemporaryDirectory() as cache:
        env = {k: v for k, v in os.environ.items() if k != "SLICELAB_JIT"}
        env.update(NUMBA_CACHE_DIR=cache, PYTHONPATH=os.pathsep.join(
            [str(build_lib.resolve()), *filter(None, [os.environ.get("PYTHONPATH")])]))
        try:
            r = subprocess.run([sys.executable, "-c", code], cwd=build_lib, env=env,
                               capture_output=True, text=True)
        except OSError as exc:
            r = subprocess.CompletedProcess([], 1, "", str(exc))
    table = build_lib.joinpath(*BUILT[:-1], f"{BUILT[-1]}.json")
    ok = r.returncode == 0 and table.exists()
    said = (r.stdout.strip().splitlines() or [""])[-1]  # what build() returned, or nothing
    if not ok and not said.startswith("kernels not built"):  # it failed before saying why
        why = "; ".join(r.stderr.strip().splitlines()[-3:]) or f"exit status {r.returncode}"
        said = f"kernels not built ahead of time ({why}); numba compiles them on first use"
    print(f"slicelab: {said}", file=sys.stderr)
    return ok


commands = {"build_py": BuildWithKernels}
if bdist_wheel is not None:

    class WheelWithKernels(bdist_wheel):
        """bdist_wheel, tagged for this Python and platform when it carries the built kernels."""

        def run(self):
            if not self.skip_build:
                self.run_command("build")
            if self.get_finalized_command("build_py").kernels_built:
                # An extension module: platlib, and the wheel tagged for this Python and platform.
                self.distribution.has_ext_modules = lambda: True
                self.root_is_pure = False
            super().run()

    commands["bdist_wheel"] = WheelWithKernels

if __name__ == "__main__":  # (setuptools runs this file as __main__; tests import it)
    setup(cmdclass=commands)
