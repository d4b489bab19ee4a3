"""A layer on the pixel grid: masks, rasters, the raster hole hierarchy, exact distance fields.

==========================  =====================================================
``grid.masks``              pixel masks on the world grid: whole windows, or blocks along a boundary
``grid.raster``             `rasterize` a section (or its mask alone), drawing lines
``grid.hierarchy``          the raster hole hierarchy: OpenCV's contour tree matched to the loops
``grid.distance``           the exact distance field of a layer and its level sets
==========================  =====================================================
"""
