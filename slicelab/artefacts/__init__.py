"""Archaeological artefacts: vessel axis, profiles, measurements and drawings.

==========================  =====================================================
``artefacts.axis``          `align`, `Alignment`: axis onto +z, rim up, base at 0
``artefacts.axis_fit``      axis estimators: moments, normal lines, circles
``artefacts.axis_lines``    the axis from smoothed normal lines, for noisy scans and sherds
``artefacts.noise``         the scan's noise, from residuals to local surface fits
``artefacts.axis_search``   a sherd's axis: every direction tried
``artefacts.sherds``        sherds: recognised, set rim up, rim / base measured
``artefacts.strips``        a sherd's meridian sections as strips: faces and ends
``artefacts.lips``          the lip told from the breaks; rim diameter, EVE
``artefacts.bases``         a base sherd's base found and measured
``artefacts.outlines``      half-sections' outlines smoothed against noise, measured
``artefacts.halves``        `half_profiles`, `HalfProfile`: half-sections through the axis
``artefacts.partial``       profiles of sherds, open scans, reassembled fragments
``artefacts.profiles``      `profile`, `Profile`
``artefacts.measure``       `Measurements`, `measure_halves`, Pappus volumes
``artefacts.curves``        `clip_ring`, `resample`: plain curve tools beneath the rest
``artefacts.appendages``    handles, spouts and lugs found and measured
``artefacts.cavities``      a sealed vessel's cavity shell and its volume
``artefacts.drawing``       the profile drawing (layout, SVG)
``artefacts.drawing_png``   the same drawing as a PNG (matplotlib)
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"Alignment": "axis", "align": "axis", "rotation_to_z": "axis_fit", "surface_moments": "axis_fit", "principal_axis": "axis_fit", "normal_lines_axis": "axis_fit", "refine_axis": "axis_fit", "circle_pass": "axis_fit", "SurfaceSample": "axis_lines", "smoothed_normals": "axis_lines", "surface_noise": "noise", "noise_estimate": "noise", "NoiseEstimate": "noise", "SherdReport": "sherds", "sherd_stance": "sherds", "half_outlines": "measure", "line_complex_axis": "axis_fit", "tukey_weights": "axis_fit", "search_axis": "axis_search", "fit_axis_lines": "axis_lines", "AxisFit": "axis_lines", "angular_span": "axis_lines", "HalfProfile": "halves", "half_profiles": "halves", "Profile": "profiles", "profile": "profiles", "closing_gap": "partial", "Measurements": "measure", "measure_halves": "measure", "pappus_volume": "measure", "clip_ring": "curves", "resample": "curves", "layout": "drawing", "profile_svg": "drawing", "Appendage": "appendages", "find_appendages": "appendages", "cavity_volume": "cavities"}


__all__ = ["Alignment", "align", "rotation_to_z", "surface_moments", "principal_axis", "normal_lines_axis", "refine_axis", "circle_pass", "SurfaceSample", "smoothed_normals", "surface_noise", "noise_estimate", "NoiseEstimate", "SherdReport", "sherd_stance", "half_outlines", "line_complex_axis", "tukey_weights", "search_axis", "fit_axis_lines", "AxisFit", "angular_span", "HalfProfile", "half_profiles", "Profile", "profile", "closing_gap", "Measurements", "measure_halves", "pappus_volume", "clip_ring", "resample", "layout", "profile_svg", "Appendage", "find_appendages", "cavity_volume"]


__getattr__, __dir__ = attach(__name__, _WHERE, globals())
