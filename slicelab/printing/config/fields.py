"""What a print setting is: its help, unit, physical range and choices, and the check made of it.

Every field of the settings groups (`slicelab.printing.config.settings`) is declared
with `setting`, which stores its help text, its unit and the range a real
printer can take (or its choices) in the dataclass field's metadata, as
PrusaSlicer's ``PrintConfigDef`` does for its options. `check_field` makes
the one check every field gets when a group is made: the right type, finite,
inside its range, one of its choices. A value outside is refused with one
line naming the setting and what it may be, whether it came from the command
line, a settings file or Python. Start and end G-code are templates whose
placeholders `check_template` allows only as ``{name}`` or ``{name:spec}``
with a numeric setting and a short numeric format, so no template can reach
into an object or write a file of any size.

See Also
--------
slicelab.printing.config.settings : the groups and `PrintSettings`.
slicelab.printing.config.settings.render_gcode : the templates filled in.
"""
from __future__ import annotations

import math
import re
import string
from dataclasses import field, fields

import numpy as np

__all__ = ["setting", "check_field", "check_fields", "range_text", "check_template", "TEMPLATE_LIMIT"]

#: The longest start or end G-code template accepted (characters).
TEMPLATE_LIMIT = 65536
# A format spec for a number: fill/align, sign, '#', '0', width up to 2 digits, precision up to 2
# digits, a numeric type. Nothing else (no '>100000000', no nested fields).
_NUMERIC_SPEC = re.compile(r"(?:[^{}]?[<>=^])?[+\- ]?#?0?(?:[1-9]\d?)?(?:\.\d{1,2})?[eEfFgGd%n]?")


def setting(default, help: str, unit: str = "", low=None, high=None, *, above: bool = False,
            below: bool = False, choices=None, optional: bool = False, size: int | None = None,
            kind: type | None = None):
    """A settings field: its default and, in its metadata, what `check_field` checks.

    Parameters
    ----------
    default
        The default value (its type is the field's, unless `kind` says otherwise).
    help : str
        One sentence for ``--help`` and settings files.
    unit : str
        mm, mm/s, C, %, s, degrees, layers... ('' for a plain number or a word).
    low, high : float, optional
        The physical range (inclusive unless `above` / `below`).
    above, below : bool
        The range excludes `low` / `high`.
    choices : callable or tuple, optional
        The words the field may be (a callable returning them, for registries
        loaded on first use).
    optional : bool
        None is allowed (it means: derived from other settings).
    size : int, optional
        The field is a tuple of this many numbers, each in the range.
    kind : type, optional
        float, int, bool or str; by default the default's type.

    Examples
    --------
    >>> from dataclasses import dataclass, fields
    >>> @dataclass(frozen=True)
    ... class Demo:
    ...     speed: float = setting(40.0, "how fast", "mm/s", 0, 1000, above=True)
    >>> fields(Demo)[0].metadata["unit"], range_text(fields(Demo)[0])
    ('mm/s', 'above 0 and at most 1000 mm/s')
    """
    if kind is None:
        kind = type(default[0]) if size else type(default) if default is not None else float
    meta = {"help": help, "unit": unit, "low": low, "high": high, "above": above, "below": below,
            "choices": choices, "optional": optional, "size": size, "kind": kind}
    return field(default=default, metadata=meta)


def _choices(meta) -> tuple:
    c = meta["choices"]
    return tuple(c() if callable(c) else c)


def range_text(f) -> str:
    """What field `f` may be, in words ("from 0 to 100 %", "one of a, b").

    Examples
    --------
    >>> from slicelab.printing.config.settings import Cooling
    >>> range_text({f.name: f for f in fields(Cooling)}["fan_speed"])
    'from 0 to 100 %'
    """
    m = f.metadata
    if m["choices"] is not None:
        return "one of " + ", ".join(_choices(m))
    if m["kind"] is bool:
        return "true or false"
    if m["kind"] is str:
        return "text"
    unit = f" {m['unit']}" if m["unit"] else ""
    whole = "a whole number " if m["kind"] is int else ""
    lo, hi = m["low"], m["high"]
    if lo is not None and hi is not None:
        if m["above"] and m["below"]:
            text = f"{whole}between {lo:g} and {hi:g}{unit}, exclusive"
        elif m["above"]:
            text = f"{whole}above {lo:g} and at most {hi:g}{unit}"
        else:
            text = f"{whole}from {lo:g} to {hi:g}{unit}"
    elif lo is not None:
        text = f"{whole}{'above' if m['above'] else 'at least'} {lo:g}{unit}"
    else:
        text = f"{whole or 'a number'}".strip() + unit
    return text.strip()


def _number(v, m) -> bool:
    if isinstance(v, (bool, np.bool_)):
        return False
    if m["kind"] is int:
        if not isinstance(v, (int, np.integer)):
            return False
    elif not isinstance(v, (int, float, np.integer, np.floating)):
        return False
    x = float(v)
    if not math.isfinite(x):
        return False
    lo, hi = m["low"], m["high"]
    if lo is not None and (x < lo or (m["above"] and x == lo)):
        return False
    if hi is not None and (x > hi or (m["below"] and x == hi)):
        return False
    return True


def check_field(f, v):
    """`v` checked against field `f`'s metadata and normalised (tuples of floats); ValueError naming the
    setting and its range otherwise.

    Examples
    --------
    >>> from slicelab.printing.config.settings import Motion
    >>> travel = {f.name: f for f in fields(Motion)}["travel_speed"]
    >>> check_field(travel, 150)
    150
    >>> check_field(travel, 1e308)
    Traceback (most recent call last):
    ...
    ValueError: travel_speed must be above 0 and at most 1000 mm/s, got 1e+308
    """
    m = f.metadata
    if v is None and m["optional"]:
        return None

    def refuse():
        shown = v if not isinstance(v, str) or len(v) < 60 else v[:57] + "..."
        what = f"{m['size']} numbers, each " if m["size"] else ""
        return ValueError(f"{f.name} must be {what}{range_text(f)}, got {shown!r}")

    if m["size"]:
        try:
            items = tuple(v)
        except TypeError:
            raise refuse() from None
        if len(items) != m["size"] or not all(_number(x, m) for x in items):
            raise refuse()
        return tuple(float(x) for x in items)
    if m["choices"] is not None:
        if not isinstance(v, str) or v not in _choices(m):
            raise refuse()
        return v
    if m["kind"] is bool:
        if not isinstance(v, (bool, np.bool_)):
            raise refuse()
        return bool(v)
    if m["kind"] is str:
        if not isinstance(v, str):
            raise refuse()
        return v
    if not _number(v, m):
        raise refuse()
    return v


def check_fields(group) -> None:
    """Check every field of a frozen settings group (from its ``__post_init__``), normalising in place.

    Examples
    --------
    >>> from slicelab.printing.config.settings import Skins
    >>> Skins(top_layers=1_000_000_000)
    Traceback (most recent call last):
    ...
    ValueError: top_layers must be a whole number from 0 to 100 layers, got 1000000000
    """
    for f in fields(group):
        v = getattr(group, f.name)
        checked = check_field(f, v)
        if checked is not v:
            object.__setattr__(group, f.name, checked)


def check_template(name: str, template, numbers) -> None:
    """Refuse a start or end G-code template that is not plain G-code with ``{setting}`` or
    ``{setting:spec}`` placeholders of the numeric settings `numbers`.

    A placeholder may not reach into an attribute or an item (``{layer_height.__class__}``), convert
    (``{x!r}``), nest, name an unknown setting, or ask a format wider than two digits
    (``{layer_height:>100000000}``); the template is at most `TEMPLATE_LIMIT` characters.

    Examples
    --------
    >>> check_template("start_gcode", "M104 S{nozzle_temperature:.0f}\\n", {"nozzle_temperature"})
    >>> check_template("start_gcode", "M117 {layer_height.__class__}", {"layer_height"})
    Traceback (most recent call last):
    ...
    ValueError: start_gcode: '{layer_height.__class__}' is not a placeholder: use {setting} or {setting:spec} with a numeric setting
    """
    if template is None:
        return
    if not isinstance(template, str):
        raise ValueError(f"{name} must be text (G-code lines), got {template!r}")
    if len(template) > TEMPLATE_LIMIT:
        raise ValueError(f"{name} is {len(template)} characters long (at most {TEMPLATE_LIMIT})")
    if "\x00" in template:
        raise ValueError(f"{name} holds a NUL character")
    try:
        parts = list(string.Formatter().parse(template))
    except ValueError as exc:  # a single '{' or '}'
        raise ValueError(f"{name}: {exc} (write {{{{ and }}}} for a literal brace)") from None
    for _, key, spec, conversion in parts:
        if key is None:
            continue
        shown = "{" + key + (f"!{conversion}" if conversion else "") + (f":{spec}" if spec else "") + "}"
        if conversion or not key.isidentifier() or key not in numbers:
            why = "is not a numeric setting" if key.isidentifier() and not conversion else "is not a placeholder"
            raise ValueError(f"{name}: {shown!r} {why}: use {{setting}} or {{setting:spec}} with a numeric "
                             f"setting")
        if spec and not _NUMERIC_SPEC.fullmatch(spec):
            raise ValueError(f"{name}: {shown!r} has a format other than a short numeric one (such as "
                             f":.0f or :g)")

