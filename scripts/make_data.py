"""Write the sample meshes into data/ (deterministic; small ones are committed).

    python scripts/make_data.py            # data/*.stl if missing
    python scripts/make_data.py --force    # rewrite them
    python scripts/make_data.py --large    # also data/large/: 1M and 5M tori, 5M pot (git-ignored)
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from slicelab import save  # noqa: E402
from slicelab import samples  # noqa: E402
from slicelab.export.files import atomic_open  # noqa: E402

SMALL = {
    "cube_with_hole": lambda: samples.cube_with_hole(20.0, 5.0, 64),
    "torus": lambda: samples.torus(30.0, 10.0, 96, 48),
    "nested_shells": samples.nested_shells,
    "sphere": lambda: samples.sphere(20.0, 48, 96),
    "pot": lambda: samples.pot(60, 72),
    "overlapping_cubes": samples.overlapping_cubes,
    "staircase": lambda: samples.staircase(8, 2.0, 10.0, 0.2, 2),
}

LARGE = {
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
