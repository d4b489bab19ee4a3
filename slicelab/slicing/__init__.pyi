"""The names ``slicelab.slicing`` re-exports, each from its submodule: read by static tools and by
`slicelab._lazy.attach_stub`, which loads a submodule the first time one of its names is used."""

from .sections import (
    Section as Section,
    section as section,
    slice_layers as slice_layers,
    layer_heights as layer_heights,
    section_from_distances as section_from_distances,
)
from .split import (
    Split as Split,
    split_facets as split_facets,
    classify as classify,
    corner_distances as corner_distances,
    PATTERNS as PATTERNS,
)
from .cap import (
    Cap as Cap,
    plane_edges as plane_edges,
    cap_segments as cap_segments,
    triangle_min_angles as triangle_min_angles,
)
from .cut import Cut as Cut, CutReport as CutReport, CutWarning as CutWarning
from .stair import (
    stair_cut as stair_cut,
    StairCut as StairCut,
    StairCutError as StairCutError,
    axis_plane as axis_plane,
)
from .partition import (
    Joint as Joint,
    Piece as Piece,
    PartitionReport as PartitionReport,
    Partition as Partition,
)
from .placement import (
    fit_rotation as fit_rotation,
    Placement as Placement,
    place_for_printing as place_for_printing,
    flat_faces as flat_faces,
    DIRECTIONS as DIRECTIONS,
)
from .plates import Plate as Plate, Plates as Plates, arrange as arrange, footprint as footprint
