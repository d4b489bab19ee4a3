"""Top and bottom skins: a layer's material that the layers above or below leave exposed.

Layer masks share one world-anchored pixel grid, so a skin is a plain mask
difference: the part of layer k not under all of the `top_layers` layers above
(or over all of the `bottom_layers` below) is filled solid. Where the surface
slopes, that leaves the shell thinner than the skins, measured across it: the
layers within the skins' reach have their perimeters over this layer's sparse
infill. Those parts are filled solid too (`vertical_shell`, PrusaSlicer's
"ensure vertical shell thickness"). Masks are held by blocks along their
boundaries (`slicelab.printing.grid.masks.BlockMask`), so the differences and the
opening cost what the boundaries do.

See Also
--------
slicelab.printing.planner.plan : finds every layer's skins this way.
slicelab.printing.pipeline.layer_paths : fills them solid (``solid``) and types the top surface (``top``).
"""
from __future__ import annotations

from functools import reduce
from operator import and_, or_

from ..grid.masks import dilate_mask, open_mask, reach_disc
from .overhangs import Bridge
from ..config.settings import Skins

__all__ = ["layer_skins", "vertical_shell", "internal_bridge"]


def layer_skins(k: int, masks: dict, skins: Skins, line_width: float, shell=None):
    """Skins of layer k: (solid, top), the skin and the part of it the next layer leaves exposed.

    Parameters
    ----------
    k : int
        The layer.
    masks : dict
        Layer index -> its material mask (None for an empty layer), holding at least the
        layers from ``k - skins.bottom_layers`` to ``k + skins.top_layers`` that exist: a
        missing index lies beyond the part (nothing there).
    skins : Skins
        How many layers make a skin above and below.
    line_width : float
        Slivers narrower than a line (a sloped wall's edge) are left to the perimeters.
    shell : mask, optional
        More of the layer to fill solid (`vertical_shell`); it is not top skin.

    Returns
    -------
    solid, top : mask or None
        None where there is no skin.

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab.printing.grid.masks import GridMask
    >>> slab = GridMask(np.ones((40, 40), bool), 0, 0, 0.1)
    >>> tower = GridMask(np.pad(np.ones((10, 10), bool), 15), 0, 0, 0.1)
    >>> masks = {0: slab, 1: slab, 2: slab, 3: slab, 4: tower, 5: tower}
    >>> solid, top = layer_skins(3, masks, Skins(top_layers=2, bottom_layers=2), 0.4)
    >>> round(solid.area, 2), round(top.area, 2)     # the slab's top, all but under the tower
    (15.0, 15.0)
    >>> solid, top = layer_skins(0, masks, Skins(top_layers=2, bottom_layers=2), 0.4)
    >>> round(solid.area, 2), top                     # the bottom: all of it, nothing exposed above
    (16.0, None)
    >>> layer_skins(5, masks, Skins(top_layers=0, bottom_layers=2), 0.4)   # no top skins asked for
    (None, None)
    """
    mine = masks.get(k)
    if mine is None:
        return None, None
    parts = []
    for rng in (range(k + 1, k + 1 + skins.top_layers), range(k - 1, k - 1 - skins.bottom_layers, -1)):
        others = [masks.get(j) for j in rng]  # the few neighbouring layers on this side
        if any(o is None for o in others):  # one is empty (or beyond the part): all of it is skin
            parts.append(mine)
        else:  # skin is what they do not all hold (with none asked for, nothing)
            parts.append(mine - reduce(and_, others) if others else mine - mine)
    top, bottom = parts
    skin = top | bottom
    if shell is not None:
        skin = skin | shell
    if skin.area == 0:
        return None, None
    radius = max(1, int(round(0.5 * line_width / mine.pixel_size)))
    solid = open_mask(skin, radius)
    if solid is None:  # the exposed part lies in the skin, and opening a smaller set keeps less
        return None, None
    # The top surface proper: what the very next layer leaves exposed (the skin under it is
    # solid infill, as PrusaSlicer types it).
    above = masks.get(k + 1)
    exposed = top if above is None else top - above
    return solid, (open_mask(exposed, radius) if exposed.area > 0 else None)


def vertical_shell(k: int, masks: dict, band, skins: Skins):
    """The part of layer k's material, inside its own perimeters, under or over the perimeters of
    a layer within the skins' reach (`bottom_layers` below, `top_layers` above): filled solid, the
    shell of a sloped surface stays as thick as its skins and perimeters, across the slope too.

    PrusaSlicer's "ensure vertical shell thickness" makes the same region solid: on a dome, the
    perimeters of the layers above stand over this layer's sparse infill, and without it the shell
    under the surface is only as thick as the skins measured vertically, which the slope thins.

    Parameters
    ----------
    k : int
    masks : dict
        Layer index -> its material mask (None for an empty layer), as for `layer_skins`.
    band : callable
        ``band(j)``: the pixels of layer j within its perimeters' width of its outline (None for
        an empty layer), as `slicelab.printing.pipeline.LayerWindow.band` makes them.
    skins : Skins

    Returns
    -------
    mask or None
        None when the neighbours' perimeters all lie over this layer's own (a vertical wall).

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab.printing.grid.masks import GridMask
    >>> def disc(r):   # a layer of a cone: a disc of r mm on 0.1 mm pixels
    ...     y, x = np.mgrid[-60:60, -60:60] * 0.1
    ...     return GridMask(np.hypot(x, y) < r, -60, -60, 0.1)
    >>> masks = {j: disc(5.0 - 0.5 * j) for j in range(6)}
    >>> def band(j):   # its perimeters: the outer 0.8 mm
    ...     return masks[j] - disc(4.2 - 0.5 * j)
    >>> shell = vertical_shell(1, masks, band, Skins(top_layers=2, bottom_layers=2))
    >>> round(shell.area / (np.pi * (3.7 ** 2 - 2.7 ** 2)), 1)   # the ring under the next two layers' perimeters
    1.0
    """
    mine = masks.get(k)
    if mine is None:
        return None
    near = [band(j) for j in (*range(k - skins.bottom_layers, k), *range(k + 1, k + 1 + skins.top_layers))
            if masks.get(j) is not None]
    near = [b for b in near if b is not None]
    own = band(k)
    if not near or own is None:
        return None
    shell = (reduce(or_, near) & mine) - own
    return shell if shell.area > 0 else None


def internal_bridge(solid, below, below_solid, line_width: float, angle: float):
    """The part of a layer's skin laid over the sparse infill of the layer below, as a `Bridge`.

    A skin's first layer over sparse infill spans the gaps between its lines: it is printed
    as a bridge (PrusaSlicer's internal bridge), across the layer's solid angle.

    Parameters
    ----------
    solid : mask or None
        The layer's skin (`layer_skins`).
    below : mask or None
        The material of the layer below.
    below_solid : mask or None
        The skin of the layer below (solid there: nothing to bridge).
    line_width : float
        Parts narrower than two lines are left solid.
    angle : float
        Direction of the bridge's lines (degrees).

    Returns
    -------
    Bridge or None

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab.printing.grid.masks import GridMask
    >>> slab = GridMask(np.ones((40, 40), bool), 0, 0, 0.1)
    >>> half = GridMask(np.ones((40, 20), bool), 0, 0, 0.1)      # skin below, on the left half
    >>> b = internal_bridge(slab, slab, half, 0.4, 45.0)
    >>> round(b.mask.area, 1), b.angle                           # the right half bridges infill
    (8.0, 45.0)
    """
    if solid is None or below is None:
        return None
    over = solid & below
    if below_solid is not None:
        over = over - below_solid
    if over.area == 0:
        return None
    # A strip narrower than two lines (a sloped shell's step from layer to layer) has its lines
    # held at both ends: it stays solid; a skin's first layer over wide sparse infill is bridged.
    radius = max(1, int(round(line_width / solid.pixel_size)))
    kept = open_mask(over, radius)
    if kept is None:
        return None
    # The opening rounds the region's corners off: what lies within its radius of what it kept
    # is bridged too (a corner), a strip away from it is not.
    kept = over & dilate_mask(kept, reach_disc(radius * solid.pixel_size, solid.pixel_size))
    return Bridge(kept, float(angle), 0.0)
