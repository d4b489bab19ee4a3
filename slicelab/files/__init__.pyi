"""The names ``slicelab.files`` re-exports, each from its submodule: read by static tools and by
`slicelab._lazy.attach_stub`, which loads a submodule the first time one of its names is used."""

from .atomic import (
    atomic_path as atomic_path,
    atomic_open as atomic_open,
    same_file as same_file,
    StagedFolder as StagedFolder,
)
from .numbers import path_data as path_data
from .svg import SvgDrawing as SvgDrawing
