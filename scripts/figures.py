"""Regenerate the figures of the notebooks and the README from the data: ``make figures``.

    .venv/bin/python scripts/figures.py                  # every stage, into results/figures/
    .venv/bin/python scripts/figures.py --stage 06_artefacts --out docs/figures
    .venv/bin/python scripts/figures.py --list

Each stage registers its figure functions with ``@figure("<notebook stem>")``.
A function takes the output folder and returns a matplotlib Figure (saved as
``<stage>_<name>.png``) or the list of files it wrote itself. The notebooks
import the same functions (``sys.path`` gets ``scripts/``), so a figure in a
notebook and its regenerated file come from one piece of code. To add a
stage: write its functions below under a new heading, decorated with its
notebook's stem.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"
sys.path.insert(0, str(ROOT))

FIGURES: dict[str, dict] = {}


def figure(stage: str):
    """Register a figure function under a stage (a notebook's stem)."""
    def register(fn):
        FIGURES.setdefault(stage, {})[fn.__name__] = fn
        return fn
    return register


def _new_figure(w: float, h: float):
    # The object API, not pyplot: no GUI backend, safe from scripts and notebooks alike.
    from matplotlib.figure import Figure
    return Figure(figsize=(w, h), layout="constrained")


# ======================================================= 06 scanned artefacts
def scanned_pot(seed: int = 8, noise: float = 0.1, sherd: bool = True):
    """data/pot.stl as a scan arrives: random pose, vertex noise, a missing sherd.

    Returns the scan and the 4x4 motion that put the pot there (the truth).
    """
    import slicelab
    from slicelab import Mesh, samples
    from slicelab.geometry.topology import weld
    pot = slicelab.load(DATA / "pot.stl")
    rng = np.random.default_rng(seed)
    v, f = weld(pot.triangles)
    v = v + rng.normal(scale=noise, size=v.shape)
    mesh = Mesh.from_vertices_faces(v, f)
    if sherd:
        c = mesh.triangles.mean(axis=1)
        mesh = Mesh(mesh.triangles[np.linalg.norm(c - [50.0, -35.0, 80.0], axis=1) > 18.0])
    motion = samples.random_motion(rng, shift=150)
    return mesh.transformed(motion), motion


def _rings(ax, section, **style):
    for loop in section.loops:
        ring = np.vstack([loop, loop[:1]])
        ax.plot(ring[:, 0], ring[:, 1], **style)
    for chain in section.open_chains:
        ax.plot(chain[:, 0], chain[:, 1], **{**style, "color": "tab:red"})


@figure("06_artefacts")
def scan_before_after(out=None):
    """Seed 000's mistake and its cure: the scan cut as it lies, then cut through its found axis."""
    import slicelab
    scan, _ = scanned_pot()
    centre = scan.bounds.mean(axis=0)
    raw = slicelab.section(scan, centre, (0, -1, 0))
    a = slicelab.align(scan)
    cut = slicelab.section(a.mesh, (0, 0, 0), (0, -1, 0))
    fig = _new_figure(9, 4.2)
    ax1, ax2 = fig.subplots(1, 2)
    _rings(ax1, raw, color="k", lw=0.8)
    ax1.set_title("scan cut as it lies (seed 000)", fontsize=10)
    _rings(ax2, cut, color="k", lw=0.8)
    ax2.axvline(0, color="0.5", lw=0.6, ls="-.")
    ax2.set_title(f"cut through the axis found by align\nresidual {a.residual:.3f} mm, rim up from the "
                  f"{a.up_from}", fontsize=10)
    for ax in (ax1, ax2):
        ax.set_aspect("equal")
        ax.set_xlabel("u (mm)")
        ax.set_ylabel("v (mm)")
    return fig


@figure("06_artefacts")
def axis_error_by_case(out=None):
    """Axis error (degrees) of align on the pot in random poses: clean, noisy, missing sherd."""
    import slicelab
    cases = [("clean", 0.0, False), ("noise 0.1", 0.1, False), ("noise 0.3", 0.3, False),
             ("sherd", 0.0, True), ("sherd + noise 0.2", 0.2, True)]
    errors = []
    for name, noise, sherd in cases:
        e = []
        for seed in range(3):
            scan, motion = scanned_pot(seed, noise, sherd)
            a = slicelab.align(scan)
            c = float(a.axis @ (motion[:3, :3] @ [0, 0, 1]))
            e.append(math.degrees(math.acos(min(1.0, c))))
        errors.append(e)
    fig = _new_figure(6.5, 3.2)
    ax = fig.subplots()
    for k, e in enumerate(errors):
        ax.scatter([k] * len(e), e, color="k", s=14)
    ax.axhline(0.5, color="tab:red", lw=0.8, ls="--", label="target 0.5 degrees")
    ax.set_yscale("log")
    ax.set_xticks(range(len(cases)), [c[0] for c in cases], fontsize=8)
    ax.set_ylabel("axis error (degrees)")
    ax.legend(fontsize=8)
    ax.set_title("align: three random poses per case", fontsize=10)
    return fig


@figure("06_artefacts")
def half_sections(out=None):
    """Every half-section of the scan, the drawn (most typical) one, and each one's distance from it."""
    import slicelab
    scan, _ = scanned_pot()
    p = slicelab.profile(scan, planes=12)
    fig = _new_figure(9, 4.2)
    ax1, ax2 = fig.subplots(1, 2, width_ratios=[1, 1.2])
    for k, h in enumerate(p.halves):
        ring = np.vstack([h.polygon, h.polygon[:1]])
        ax1.plot(ring[:, 0], ring[:, 1], color="k" if k == p.representative else "0.7",
                 lw=1.2 if k == p.representative else 0.5, zorder=3 if k == p.representative else 1)
    ax1.set_aspect("equal")
    ax1.set_xlabel("r (mm)")
    ax1.set_ylabel("z (mm)")
    ax1.set_title(f"{len(p.halves)} half-sections (drawn one in black)", fontsize=10)
    angles = np.degrees([h.angle for h in p.halves])
    ax2.bar(angles, p.spread, width=8, color="0.3")
    ax2.set_xlabel("angle of the half-plane (degrees)")
    ax2.set_ylabel("Hausdorff distance to the drawn half (mm)")
    ax2.set_title("spread: noise 0.1 mm; halves through the hole are left out", fontsize=10)
    return fig


@figure("06_artefacts")
def measurements_vs_truth(out=None):
    """Relative error of each measurement of the scanned pot against the generator's true dimensions."""
    import json

    import slicelab
    truth = json.loads((DATA / "pot.json").read_text())["dimensions"]
    keys = ["height", "rim_diameter", "max_diameter", "base_diameter", "base_thickness", "capacity",
            "clay_volume"]
    fig = _new_figure(7.5, 3.4)
    ax = fig.subplots()
    for k, (label, noise, sherd) in enumerate([("clean pose only", 0.0, False),
                                               ("noise 0.1 + sherd", 0.1, True)]):
        m = slicelab.profile(scanned_pot(8, noise, sherd)[0], planes=12).measurements
        rel = [100 * (getattr(m, key) / truth[key] - 1) for key in keys]
        ax.bar(np.arange(len(keys)) + 0.38 * (k - 0.5), rel, width=0.38, label=label,
               color=["0.2", "0.65"][k])
    ax.axhspan(-1, 1, color="tab:green", alpha=0.1, label="within 1 %")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xticks(range(len(keys)), [k.replace("_", "\n") for k in keys], fontsize=8)
    ax.set_ylabel("error (%)")
    ax.legend(fontsize=8)
    ax.set_title("measurements of the scanned pot vs the generator's true pot", fontsize=10)
    return fig


@figure("06_artefacts")
def profile_drawing(out):
    """The archaeological drawing of the scanned pot, SVG and PNG, 1:1 in mm."""
    import slicelab
    out = Path(out)
    p = slicelab.profile(scanned_pot()[0], planes=12, name="pot.stl (scanned: noise 0.1 mm, sherd missing)")
    svg, png = out / "06_artefacts_profile_drawing.svg", out / "06_artefacts_profile_drawing.png"
    p.to_svg(svg)
    p.to_png(png, dpi=100)
    return [svg, png]


# ===================================================================== runner
def render(stage: str, name: str, out: Path) -> list[Path]:
    """Make one figure and write it under `out`; return the files written."""
    from slicelab.files.atomic import atomic_path
    out.mkdir(parents=True, exist_ok=True)
    result = FIGURES[stage][name](out)
    if isinstance(result, list):
        return result
    path = out / f"{stage}_{name}.png"
    with atomic_path(path) as tmp:
        result.savefig(tmp, format="png", dpi=120)
    return [path]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--stage", action="append", help="only these stages (notebook stems); repeatable")
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "figures", help="default results/figures/")
    ap.add_argument("--list", action="store_true", help="list the figures and stop")
    args = ap.parse_args(argv)
    stages = args.stage or sorted(FIGURES)
    unknown = [s for s in stages if s not in FIGURES]
    if unknown:
        print(f"figures.py: unknown stage {', '.join(unknown)}; known: {', '.join(sorted(FIGURES))}",
              file=sys.stderr)
        return 2
    for stage in stages:
        for name, fn in FIGURES[stage].items():
            if args.list:
                print(f"{stage}/{name}: {(fn.__doc__ or '').strip().splitlines()[0]}")
                continue
            t0 = time.perf_counter()
            paths = render(stage, name, args.out)
            shown = ", ".join(str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p) for p in paths)
            print(f"{stage}/{name}: {shown} ({time.perf_counter() - t0:.1f} s)", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
