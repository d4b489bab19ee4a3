"""The names ``slicelab.gcode`` re-exports, each from its submodule: read by static tools and by
`slicelab._lazy.attach_stub`, which loads a submodule the first time one of its names is used."""

from .writer import (
    write_gcode as write_gcode,
    gcode_lines as gcode_lines,
    header_value as header_value,
    layer_fan as layer_fan,
    layer_texts as layer_texts,
)
from .layer_svgs import write_svgs as write_svgs, layer_drawings as layer_drawings, svg_page as svg_page
from .estimate import move_times as move_times, format_duration as format_duration
