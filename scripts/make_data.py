"""Write the sample meshes into data/ (deterministic; small ones are committed).

    python scripts/make_data.py            # data/*.stl if missing
    python scripts/make_data.py --force    # rewrite them
    python scripts/make_data.py --large    # also data/large/: 1M and 5M tori, 5M pot, a 100 mm block (git-ignored)
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from slicelab import save  # noqa: E402
from slicelab import samples  # noqa: E402
from slicelab.files.atomic import atomic_open  # noqa: E402

SMALL = {
    "cube_with_hole": lambda: samples.cube_with_hole(20.0, 5.0, 64),
    "torus": lambda: samples.torus(30.0, 10.0, 96, 48),
    "nested_shells": samples.nested_shells,
    "sphere": lambda: samples.sphere(20.0, 48, 96),
    "pot": lambda: samples.pot(60, 72),
    "overlapping_cubes": samples.overlapping_cubes,
    "staircase": lambda: samples.staircase(8, 2.0, 10.0, 0.2, 2),
    # Two 10 x 10 x 20 mm pillars 20 mm apart under a 3 mm deck: a bridge (1 mm cells, one shell).
    "bridge": lambda: samples.voxels(np.pad(np.ones((40, 10, 23), bool), 0)
                                     & ~((np.arange(40)[:, None, None] >= 10) & (np.arange(40)[:, None, None] < 30)
                                         & (np.arange(23)[None, None, :] < 20))),
    # A 10 x 10 x 20 mm stem under a 40 x 40 x 4 mm cap: an overhang all round, for supports.
    # A 180 x 180 x 20 mm tray, 2 mm walls and floor: large outlines, large skins.
    "tray": lambda: tray_part(),
    "mushroom": lambda: samples.voxels((np.arange(24)[None, None, :] >= 20)
                                       | ((np.abs(np.arange(40) - 19.5)[:, None, None] < 5)
                                          & (np.abs(np.arange(40) - 19.5)[None, :, None] < 5))
                                       & np.ones((40, 40, 24), bool)),
}

def tray_part(size: float = 180.0, height: float = 20.0, wall: float = 2.0):
    """A tray: a `size` mm square box `height` mm tall, its walls and floor `wall` mm thick, open at
    the top (28 facets, closed and manifold): a common print whose layers are large outlines
    and large skins."""
    from slicelab import Mesh
    a, b = wall, size - wall
    sq = lambda lo, hi, z: np.array([[lo, lo, z], [hi, lo, z], [hi, hi, z], [lo, hi, z]], float)  # noqa: E731
    o, t, i, f = sq(0, size, 0), sq(0, size, height), sq(a, b, height), sq(a, b, wall)
    tris = [(o[0], o[3], o[2]), (o[0], o[2], o[1]), (f[0], f[1], f[2]), (f[0], f[2], f[3])]  # bottom, pocket floor
    for k in range(4):  # over the sides: outer wall, rim, inner wall (outward normals)
        n = (k + 1) % 4
        tris += [(o[k], o[n], t[n]), (o[k], t[n], t[k]), (t[k], t[n], i[n]), (t[k], i[n], i[k]),
                 (f[k], i[n], f[n]), (f[k], i[k], i[n])]
    return Mesh(np.array(tris))


def block_part():
    """A 96 x 96 x 72 mm CAD-like part of 1 mm cells: a plate with four through holes, two
    bosses, two 1 mm walls and a dome (a 100 mm-class part for the slicing benchmark)."""
    import numpy as np
    x, y, z = np.meshgrid(np.arange(96) + 0.5, np.arange(96) + 0.5, np.arange(72) + 0.5, indexing="ij")
    occ = z < 20  # the plate
    for cx, cy in ((12, 12), (84, 12), (12, 84), (84, 84)):  # holes through it
        occ &= np.hypot(x - cx, y - cy) > 5
    for cx, cy in ((20, 48), (76, 48)):  # bosses
        occ |= (np.hypot(x - cx, y - cy) < 8) & (z < 50)
    occ |= (np.abs(x - 48.5) < 0.6) & (np.abs(y - 14) < 12) & (z < 60)  # thin walls, one cell (1 mm)
    occ |= (np.abs(y - 82.5) < 0.6) & (np.abs(x - 48) < 12) & (z < 60)
    occ |= np.hypot(np.hypot(x - 48, y - 48), z - 20) < 28  # the dome
    return samples.voxels(occ)


LARGE = {
    "block_100": block_part,
    "torus_1m": lambda: samples.torus(30.0, 10.0, 1000, 500),
    "torus_5m": lambda: samples.torus(30.0, 10.0, 2500, 1000),
    "pot_5m": lambda: samples.pot(1000, 1250),
}


def write(name: str, make, folder: Path, force: bool) -> None:
    path = folder / f"{name}.stl"
    if path.exists() and not force:
        return
    t0 = time.perf_counter()
    mesh = make()
    save(mesh, path)
    shown = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
    print(f"wrote {shown}: {len(mesh)} facets in {time.perf_counter() - t0:.1f} s")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--force", action="store_true", help="rewrite files that exist")
    ap.add_argument("--large", action="store_true", help="also write data/large/ for benchmarks")
    ap.add_argument("--out", type=Path, default=ROOT / "data", help="folder (default: data/)")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name, make in SMALL.items():
        write(name, make, args.out, args.force)
    dims = args.out / "pot.json"
    if args.force or not dims.exists():
        with atomic_open(dims) as fh:
            json.dump({"generator": "slicelab.samples.pot(60, 72)", "parameters": samples.POT,
                       "dimensions": samples.pot_dimensions()}, fh, indent=2)
            fh.write("\n")
    if args.large:
        (args.out / "large").mkdir(exist_ok=True)
        for name, make in LARGE.items():
            write(name, make, args.out / "large", args.force)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
