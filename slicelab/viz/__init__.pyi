"""The names ``slicelab.viz`` re-exports, each from its submodule: read by static tools and by
`slicelab._lazy.attach_stub`, which loads a submodule the first time one of its names is used."""

from .plates import save_plate_png as save_plate_png
from .layers import (
    plot_raster as plot_raster,
    plot_distance as plot_distance,
    plot_toolpath as plot_toolpath,
    plot_coverage as plot_coverage,
    plan_3d as plan_3d,
    preview_png as preview_png,
)
from .depth import render_depth as render_depth
from .preview import draw_split as draw_split, save_split_preview as save_split_preview
from .partition import (
    plot_exploded as plot_exploded,
    exploded_image as exploded_image,
    save_exploded_png as save_exploded_png,
)
from .profile import profile_png as profile_png
from .rims import RimChart as RimChart, rim_chart as rim_chart, rim_chart_png as rim_chart_png
