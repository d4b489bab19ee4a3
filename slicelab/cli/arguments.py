"""What the command line's commands share: argument types, the plane, job options, messages.

Each command's parameters are its job's (`slicelab.tasks.jobs`): an option left
out on the command line is left out of the job's parameters too, so the
defaults live in one place, the job.
"""
from __future__ import annotations

import argparse
import re
import sys

import numpy as np

from ..tasks.jobs import JOBS
from ..tasks.spec import ParameterError

__all__ = ["GIVEN", "FLAGS", "command", "finish", "UsageError", "LazyChoices", "vector", "point", "number", "whole_number", "positive", "density", "volume", "pair", "default",
           "options", "add_plane_arguments", "plane", "max_gap", "no_preview", "repair_flag",
           "negative_values", "warn", "say_repair", "timings", "flag_message", "say_plates"]

#: The default of a job option: absent unless given.
GIVEN = argparse.SUPPRESS
#: Parameters whose flag is not simply --name-with-dashes.
FLAGS = {"n_perimeters": "--perimeters", "bed_center": "--center", "plane": "a plane (--z, or --origin and --normal)"}


class UsageError(ValueError):
    """A command-line argument that makes no sense (exit status 2)."""


class LazyChoices:
    """argparse ``choices`` read from a registry only when a value is checked or help is shown (so
    that building the parser, as every command does, loads no registry).

    Examples
    --------
    >>> c = LazyChoices(lambda: ("a", "b"))
    >>> "a" in c, list(c)
    (True, ['a', 'b'])
    """

    def __init__(self, choices):
        self._get = choices if callable(choices) else (lambda: tuple(choices))

    def __contains__(self, value) -> bool:
        return value in self._get()

    def __iter__(self):
        return iter(self._get())


def _numbers(text: str, seps: str, count: int, unreadable: str, wrong: str, positive: bool = False) -> tuple:
    """`count` finite numbers split at any of the characters `seps` (all above zero if `positive`);
    the messages name the form expected."""
    norm = text.lower()
    for sep in seps[1:]:
        norm = norm.replace(sep, seps[0])
    try:
        values = tuple(float(v) for v in norm.split(seps[0]))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {unreadable}, got {text!r}") from None
    if len(values) != count or not all(np.isfinite(v) and (v > 0 or not positive) for v in values):
        raise argparse.ArgumentTypeError(f"expected {wrong}, got {text!r}")
    return values


def vector(text: str) -> np.ndarray:
    return np.array(_numbers(text, ",", 3, "three numbers like 1,0,0", "three finite numbers like 1,0,0"))


def point(text: str) -> tuple:
    """A point X,Y in mm."""
    return _numbers(text, ",", 2, "X,Y in mm like 125,105", "two finite numbers X,Y like 125,105")


def number(text: str) -> float:
    """A number (its range is the setting's, checked with the others).

    Examples
    --------
    >>> number("0.25")
    0.25
    """
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def whole_number(text: str) -> int:
    """A whole number (its range is the setting's, checked with the others).

    Examples
    --------
    >>> whole_number("3")
    3
    """
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None


def positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (value > 0 and np.isfinite(value)):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return value


def density(text: str) -> float:
    """A density as a fraction: ``20`` and ``20%`` are percentages, a bare number up to 1 a fraction."""
    percent = text.strip().endswith("%")
    try:
        value = float(text.strip().rstrip("%"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a percentage like 20 or 20% or a fraction like 0.2, "
                                         f"got {text!r}") from None
    return value / 100 if percent or value > 1 else value


def volume(text: str) -> tuple:
    return _numbers(text, "x,", 3, "a build volume like 200x200x200",
                    "three positive sizes like 200x200x200", positive=True)


def pair(text: str) -> tuple:
    return _numbers(text, ",", 2, "HEIGHT,DEPTH like 10,15", "two positive sizes like 10,15", positive=True)


def default(job: str, name: str):
    return JOBS[job].defaults[name]


def options(args, job: str, **more) -> dict:
    """The job's parameters given on the command line, how to read the file, and `more`."""
    reading = {n: getattr(args, n) for n in ("units", "scale") if getattr(args, n, None) is not None}
    names = set(JOBS[job].defaults)
    if job == "slice":  # its parameters are the print settings' fields
        from ..printing import setting_names
        names |= set(setting_names())
    return {**{n: getattr(args, n) for n in names if hasattr(args, n)}, **reading, **more}


def add_plane_arguments(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("plane (give --z, or --origin and --normal)")
    g.add_argument("--z", type=float, help="horizontal plane at this height (mm)")
    g.add_argument("--origin", type=vector, metavar="X,Y,Z", help="a point of the plane (mm)")
    g.add_argument("--normal", type=vector, metavar="A,B,C", help="the plane's normal")


def plane(args, required: bool = True):
    """(origin, normal) from --z or --origin/--normal; None when none is given and none is required."""
    if args.z is not None:
        if args.origin is not None or args.normal is not None:
            raise UsageError("give either --z or --origin/--normal, not both")
        return np.array([0.0, 0.0, args.z]), np.array([0.0, 0.0, 1.0])
    if args.origin is None and args.normal is None and not required:
        return None
    if args.origin is None or args.normal is None:
        raise UsageError("give a plane: --z Z, or --origin X,Y,Z and --normal A,B,C")
    return args.origin, args.normal


def max_gap(p, job: str, what: str = "chains") -> None:
    p.add_argument("--max-gap", type=float, default=GIVEN, metavar="MM",
                   help=f"join open {what} whose ends are this close "
                        f"(default {default(job, 'max_gap'):g} mm; 0 disables)")


def no_preview(p, name: str = "preview.png") -> None:
    p.add_argument("--no-preview", dest="preview", action="store_false", default=GIVEN,
                   help=f"do not draw {name}")


def repair_flag(p, default: bool = False) -> None:
    """--repair (and --no-repair where repairing is the default) and --fill-holes."""
    if default:
        p.add_argument("--repair", action=argparse.BooleanOptionalAction, default=GIVEN,
                       help="snap CAD float noise (near-coincident vertices), drop collapsed and duplicate facets, "
                            "make windings agree and turn inside-out shells outward when the mesh's check finds "
                            "any of these, as PrusaSlicer does, and say what changed (default); --no-repair "
                            "refuses such a mesh instead")
    else:
        p.add_argument("--repair", action="store_true", default=GIVEN,
                       help="first snap CAD float noise (near-coincident vertices), drop collapsed and duplicate "
                            "facets and make windings agree (slicelab.repair); the changes are reported")
    p.add_argument("--fill-holes", action="store_true", default=GIVEN,
                   help="repair, and close each hole (a loop of open edges, as a scan leaves where it saw "
                        "nothing) with a fan of facets, as PrusaSlicer does unasked; the holes and the size "
                        "of the largest are reported")


def negative_values(argv: list[str]) -> list[str]:
    """``--origin -3,2,1`` as ``--origin=-3,2,1``: argparse takes a value that starts with a minus
    sign for an option unless it is a plain number."""
    out, k = [], 0
    while k < len(argv):
        tok = argv[k]
        if (tok.startswith("--") and "=" not in tok and k + 1 < len(argv)
                and re.fullmatch(r"-[\d.][\d.eE+\-]*(,[-+]?[\d.][\d.eE+\-]*)*", argv[k + 1])):
            out.append(f"{tok}={argv[k + 1]}")
            k += 2
            continue
        out.append(tok)
        k += 1
    return out


def warn(r, skip=()) -> None:
    """Each warning the job found, as a sentence on stderr (its code is in the JSON reports)."""
    for why in r.reasons:
        if why["code"] not in skip:
            print(f"slicelab: warning: {why['message']}", file=sys.stderr)


def say_repair(r) -> None:
    rep = r.results.get("repair")
    if rep is not None:
        print("repair: " + ("; ".join(rep["changes"]) if rep["changes"] else "nothing to repair"))


def timings(r, verb: str) -> str:
    t = r.timings
    return f"load {t['load']:.2f} s, {verb} {t['compute']:.2f} s, write {t['write']:.2f} s"


def flag_message(exc: ParameterError) -> str:
    """A parameter's error in the words of the command line (``--max-gap must be ...``)."""
    return f"{FLAGS.get(exc.name, '--' + exc.name.replace('_', '-'))} {exc.problem}"


def say_plates(res: dict) -> None:
    print(f"plates: {res['pieces']} pieces on {res['plates_used']} plates (one per plate: {res['one_per_plate']}; "
          f"at least {res['lower_bound']} by area); "
          + ", ".join(f"plate {k + 1} {100 * f:.0f} % covered" for k, f in enumerate(res["fill"])))


def command(sub, name: str, docs: dict, file: bool = True) -> argparse.ArgumentParser:
    """A subcommand's parser with its help and description from `docs`, and its mesh FILE first (`file`)."""
    from pathlib import Path
    p = sub.add_parser(name, **docs[name])
    if file:
        p.add_argument("file", type=Path, metavar="FILE")
    return p


def finish(r, verb: str, tail: str) -> int:
    """The command's last lines: load, `verb` and write times with `tail`, then the job's warnings; status 0."""
    print(f"{timings(r, verb)}{tail}")
    warn(r)
    return 0
