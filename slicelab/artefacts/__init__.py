"""Archaeological artefacts: vessel axis, profiles, measurements and drawings.

==========================  =====================================================
``artefacts.profiles``      `align`, `profile`, `Measurements`
``artefacts.drawing``       the profile drawing (layout, SVG, PNG)
==========================  =====================================================
"""
from __future__ import annotations

import importlib

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"Alignment": "profiles", "align": "profiles", "rotation_to_z": "profiles", "HalfProfile": "profiles", "Measurements": "profiles", "Profile": "profiles", "profile": "profiles", "half_profiles": "profiles", "pappus_volume": "profiles", "clip_ring": "profiles", "layout": "drawing", "profile_svg": "drawing", "profile_png": "drawing"}


__all__ = ["Alignment", "align", "rotation_to_z", "HalfProfile", "Measurements", "Profile", "profile", "half_profiles", "pappus_volume", "clip_ring", "layout", "profile_svg", "profile_png"]


def __getattr__(name):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
