"""slicelab's build backend: setuptools', which asks for numba and numpy in the build environment
of a wheel where a C compiler is found, so that setup.py can build the compiled kernels into it.

An sdist or an editable install asks for setuptools alone; ``SLICELAB_BUILD_KERNELS=0`` asks for a
pure wheel (the kernels then compiled by numba on first use).
"""
from __future__ import annotations

import os
import shlex
import shutil
import sys
import sysconfig

from setuptools import build_meta as _setuptools
from setuptools.build_meta import *  # noqa: F401,F403 (the hooks, as setuptools defines them)

#: What compiling the kernels needs in the build environment (as the package's dependencies).
KERNEL_REQUIRES = ["numba>=0.60", "numpy>=1.26"]


def c_compiler() -> str | None:
    """The C compiler Python's extensions are built with (``$CC``, else Python's own), if found."""
    if sys.platform == "win32":
        return "msvc"  # found by distutils itself, if installed: a failed build leaves a pure wheel
    cc = os.environ.get("CC") or sysconfig.get_config_var("CC") or "cc"
    words = shlex.split(cc)
    return shutil.which(words[0]) if words else None


def get_requires_for_build_wheel(config_settings=None):
    wanted = os.environ.get("SLICELAB_BUILD_KERNELS") != "0" and c_compiler() is not None
    return _setuptools.get_requires_for_build_wheel(config_settings) + (KERNEL_REQUIRES if wanted else [])
