"""Plain-array geometry kernels with public names, shared by every stage.

==========================  =====================================================
``geometry.planes``         a plane's 2-D `Frame`, exact signed distances, edge crossings
``geometry.topology``       exact vertex ids, edge tables, shells, edge-manifold counts
``geometry.chains``         chaining keyed segments into loops, joining open chains
``geometry.polygons``       signed area, loop edges, point in ring, hole hierarchy, polygons
``geometry.triangles``      edge cross products, winding normals, areas
``geometry.ragged``         groups of varying length, expanded without a Python loop
``geometry.contours``       marching squares, ring simplification, skeleton tracing
``geometry.spatial``        segments cut into pieces, exact nearest distances to segments
``geometry.blocks``         square blocks of a pixel grid: held near a boundary, packed with halos
``geometry.graphs``         connected components of graphs, thinning pixel sets to skeletons
``geometry.regions``        valid shapely regions, overlays that snap-round rather than fail
``geometry.march_kernels``  compiled marching squares over blocks, and chaining segments into rings
``geometry.slice_kernels``  compiled cut of every facet/plane pair of a mesh's layers
``geometry.kernels``        compiled loops of the layer hot paths (numba), loaded on first use
==========================  =====================================================
"""
from __future__ import annotations

from .chains import Chains, chain_segments, join_open_chains
from .blocks import EMPTY, FULL, BlockGrid, blocks_near
from .graphs import GUO_HALL, graph_components, thin, thinning_table
from .contours import crossed_cells, march, march_blocks, simplify_ring, skeleton_neighbours, trace_skeleton
from .planes import NEXT_CORNER, Frame, crossing_edges, edge_points, plane_distances
from .polygons import (
    Polygon,
    build_polygons,
    loop_edges,
    loop_hierarchy,
    points_in_ring,
    signed_area,
)
from .ragged import expand_ranges, group_starts, within_group
from .spatial import SegmentIndex, join_collinear, simplify_chains, split_segments
from .topology import EdgeCounts, edge_counts, edge_table, exact_ids, manifold_summary, shells, weld
from .triangles import edge_cross, triangle_areas, winding_normals
from .._lazy import attach

# The compiled kernels load numba: only when a layer needs them.
_KERNELS = ("fill_blocks", "sample_blocks", "combine_blocks", "winding_rows", "warm")
_MARCH_KERNELS = ("march_cells", "closed_cycles")
_SEGMENT_KERNELS = ("nearest_in_buckets", "band_distances", "cut_at_crossings", "winding_at", "douglas_peucker",
                    "mark_blocks_near", "row_crossings", "bucket_boxes")
_SLICE_KERNELS = ("cut_planes",)
_REGIONS = ("valid_region", "overlay", "SNAP_GRID")  # shapely, loaded on first use
__getattr__, __dir__ = attach(__name__, {**{name: "kernels" for name in _KERNELS},
                                         **{name: "march_kernels" for name in _MARCH_KERNELS},
                                         **{name: "slice_kernels" for name in _SLICE_KERNELS},
                                         **{name: "regions" for name in _REGIONS},
                                         **{name: "segment_kernels" for name in _SEGMENT_KERNELS}}, globals())

__all__ = ["Frame", "NEXT_CORNER", "crossing_edges", "edge_points", "plane_distances", "exact_ids", "weld", "edge_table", "shells", "EdgeCounts", "edge_counts", "manifold_summary", "Chains", "chain_segments", "join_open_chains", "signed_area", "loop_edges", "points_in_ring", "loop_hierarchy", "Polygon", "build_polygons", "edge_cross", "winding_normals", "triangle_areas", "group_starts", "within_group", "expand_ranges", "graph_components", "thin", "thinning_table", "GUO_HALL", "crossed_cells", "march", "march_blocks", "simplify_ring", "skeleton_neighbours", "trace_skeleton", "split_segments", "join_collinear", "simplify_chains", "SegmentIndex", "EMPTY", "FULL", "BlockGrid", "blocks_near", *_KERNELS, *_MARCH_KERNELS, *_SEGMENT_KERNELS, *_SLICE_KERNELS, *_REGIONS]
