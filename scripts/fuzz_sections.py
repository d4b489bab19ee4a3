"""Robustness: sections through vertices, edges and along facet planes never leave open chains.

    python scripts/fuzz_sections.py [--seed S] [--planes N]
    python scripts/fuzz_sections.py --cuts [--planes N]

Cuts the watertight samples in data/ (some in random poses) by planes chosen to be degenerate: through a
vertex with a random normal, axis-aligned through a vertex, through two vertices, through a facet's edge.
On a watertight mesh every chain must close; prints the planes that did not (none expected).

``--cuts`` instead cuts (`slicelab.cut`) the nested shells and the cube with a hole, each turned at
random, by planes x, y or z = const through corners in exact arithmetic only (a fifth, three eighths,
... of the way across, where a cavity's corner or the hole's edge lies): in floating point the
corner comes out an ulp off the plane. Both parts must be closed (each edge used by two facets);
prints the cuts whose parts were not (none expected). Cost: linear in the planes.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import slicelab  # noqa: E402
from slicelab.samples import random_motion  # noqa: E402

NAMES = ["torus", "sphere", "pot", "cube_with_hole", "nested_shells", "staircase", "overlapping_cubes"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--planes", type=int, default=700)
    ap.add_argument("--cuts", action="store_true", help="cut through corners an ulp off the plane instead")
    args = ap.parse_args(argv)
    if args.cuts:
        return _cuts(args.planes)
    rng = np.random.default_rng(args.seed)
    meshes = {n: slicelab.load(ROOT / "data" / f"{n}.stl") for n in NAMES}
    bad = tried = 0
    for it in range(args.planes):
        name = NAMES[it % len(NAMES)]
        m = meshes[name] if it % 3 else meshes[name].transformed(random_motion(rng))
        t = m.triangles
        v = t[rng.integers(len(t)), rng.integers(3)]
        kind = it % 4
        if kind == 0:
            n = rng.normal(size=3)
        elif kind == 1:
            n = np.eye(3)[rng.integers(3)] * rng.choice([-1, 1])
        elif kind == 2:
            n = np.cross(t[rng.integers(len(t)), rng.integers(3)] - v, rng.normal(size=3))
        else:
            f = t[rng.integers(len(t))]
            v, n = f[0], np.cross(f[1] - f[0], rng.normal(size=3))
        if not np.any(n):
            continue
        tried += 1
        s = slicelab.section(m, v, n, max_gap=0)
        if s.open_chains:
            bad += 1
            print(f"OPEN: {name} plane kind {kind}, origin {v.tolist()}, normal {n.tolist()}: "
                  f"{len(s.open_chains)} open chains")
    print(f"{tried} degenerate planes, {bad} with open chains")
    return 1 if bad else 0


def _cuts(planes: int) -> int:
    """Cuts by axis planes through corners in exact arithmetic, after random rotations: parts closed?"""
    import warnings

    from slicelab.geometry.topology import manifold_summary
    from slicelab.samples import cube_with_hole, nested_shells
    cases = ((nested_shells(), "nested shells", (0.2, 0.8, 0.375, 0.625)),
             (cube_with_hole(20, 5, 16), "cube with a hole", (0.25, 0.75, 0.5)))
    bad = tried = 0
    for it in range(planes):  # over cuts
        mesh, name, fractions = cases[it % 2]
        rng = np.random.default_rng(it)
        turned = mesh.transformed(random_motion(rng))
        lo, hi = turned.bounds
        normal = np.eye(3)[rng.integers(3)]
        t = fractions[(it // 2) % len(fractions)]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            parts = slicelab.cut(turned, lo + t * (hi - lo), normal)
        tried += 1
        open_parts = [s for s, p in (("rear", parts.rear), ("front", parts.front))
                      if len(p) and not manifold_summary(p.triangles).closed]
        if open_parts:
            bad += 1
            print(f"OPEN: {name} turned by seed {it}, normal {normal.tolist()}, {t} of the way: {open_parts}")
    print(f"{tried} cuts through corners an ulp off the plane, {bad} with open parts")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
