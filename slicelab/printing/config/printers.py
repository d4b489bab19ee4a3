"""Printers: bundled profiles, settings files (TOML), and the physical checks a printer imposes.

A profile is a set of `PrintSettings` values describing a machine: bed size,
height, nozzle and filament, G-code flavour, start and end G-code, the
temperatures it allows. A settings file names a profile and overrides any
field, in its group's table (as ``slicelab slice --print-config`` writes it)
or in one ``[settings]`` table::

    printer = "generic-marlin-220"
    [extrusion]
    layer_height = 0.15
    [infill]
    infill_density = 0.25

Values are resolved profile < file < command line. Start and end G-code may
use ``{field}`` placeholders of the settings (``{bed_temperature}``,
``{nozzle_temperature}``, ``{bed_size_x}``, ``{bed_size_y}``, ``{max_height}``).

See Also
--------
slicelab.printing.PrintSettings : the fields, and the checks each makes.
"""
from __future__ import annotations

import tomllib
from pathlib import Path

__all__ = ["PRINTERS", "MARLIN_START", "MARLIN_END", "resolve_settings", "read_config", "format_config"]

#: The largest settings file read (bytes): a settings file is a page of text.
CONFIG_LIMIT = 1 << 20

#: Marlin's start and end blocks, the default when the settings name none.
MARLIN_START = ("M140 S{bed_temperature:.0f}\nM104 S{nozzle_temperature:.0f}\n"
                 "M190 S{bed_temperature:.0f}\nM109 S{nozzle_temperature:.0f}\n"
                 "G21 ; millimetres\nG90 ; absolute XYZ\nM83 ; relative extrusion\nG28 ; home\n")
MARLIN_END = "M104 S0\nM140 S0\nM107\nG28 X0\nM84\n"

#: The Original Prusa i3 MK3's (and MK3S's) motion limits, as PrusaSlicer's PrusaResearch profile
#: gives them (normal mode). Its firmware reads M204 S as both the printing and the travel
#: acceleration (PrusaSlicer's "marlin" flavour writes that), so travel takes the printing value here.
PRUSA_MK3_LIMITS = dict(machine_max_acceleration_extruding=1250.0, machine_max_acceleration_retracting=1250.0,
                        machine_max_acceleration_travel=1250.0, machine_max_acceleration_x=1000.0,
                        machine_max_acceleration_y=1000.0, machine_max_acceleration_z=200.0,
                        machine_max_acceleration_e=5000.0, machine_max_feedrate_x=200.0, machine_max_feedrate_y=200.0,
                        machine_max_feedrate_z=12.0, machine_max_feedrate_e=120.0, machine_max_jerk_x=8.0,
                        machine_max_jerk_y=8.0, machine_max_jerk_z=0.4, machine_max_jerk_e=4.5)

#: Bundled printer profiles: values of `PrintSettings` fields (the generic ones keep the default motion
#: limits, PrusaSlicer's: no real machine's numbers are known for them).
PRINTERS = {
    "prusa-mk3": dict(bed_size=(250.0, 210.0), max_height=210.0, nozzle_diameter=0.4, filament_diameter=1.75,
                      gcode_flavor="marlin", max_nozzle_temperature=300.0, max_bed_temperature=120.0,
                      start_gcode=MARLIN_START, end_gcode=MARLIN_END, **PRUSA_MK3_LIMITS),
    "generic-marlin-220": dict(bed_size=(220.0, 220.0), max_height=250.0, nozzle_diameter=0.4,
                               filament_diameter=1.75, gcode_flavor="marlin", max_nozzle_temperature=260.0,
                               max_bed_temperature=100.0, start_gcode=MARLIN_START, end_gcode=MARLIN_END),
    "generic-klipper-300": dict(bed_size=(300.0, 300.0), max_height=300.0, nozzle_diameter=0.4,
                                filament_diameter=1.75, gcode_flavor="klipper", max_nozzle_temperature=300.0,
                                max_bed_temperature=110.0,
                                start_gcode=("M190 S{bed_temperature:.0f}\nM109 S{nozzle_temperature:.0f}\n"
                                             "G90\nM83\nG28\n"),
                                end_gcode="M104 S0\nM140 S0\nM107\nG28 X Y\nM84\n"),
}


def read_config(path) -> dict:
    """A settings file as a dict: ``printer`` (a profile's name, optional) and the fields it sets.

    Raises ValueError naming the file and what is wrong.

    Examples
    --------
    >>> import tempfile, os
    >>> f = os.path.join(tempfile.mkdtemp(), "p.toml")
    >>> _ = open(f, "w").write('printer = "generic-marlin-220"\\n[settings]\\nlayer_height = 0.15\\n')
    >>> read_config(f)
    {'printer': 'generic-marlin-220', 'layer_height': 0.15}
    """
    p = Path(path)
    try:
        if p.stat().st_size > CONFIG_LIMIT:
            raise ValueError(f"{p}: {p.stat().st_size} bytes is not a settings file (at most {CONFIG_LIMIT})")
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ValueError(f"{p}: cannot be read ({exc.strerror or exc})") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{p}: not a TOML settings file ({str(exc).splitlines()[0]})") from None
    except RecursionError:  # tomllib reads nested arrays and tables by recursion
        raise ValueError(f"{p}: not a settings file (arrays or tables nested too deep)") from None
    from .settings import GROUPS, setting_names
    out = {k: v for k, v in data.items() if not isinstance(v, dict)}
    known = set(setting_names())
    for k in out:
        if k != "printer" and k not in known:
            raise ValueError(f"{p}: {k} is not a print setting")
    for table, values in data.items():
        if not isinstance(values, dict):
            continue
        if table != "settings" and table not in GROUPS:
            raise ValueError(f"{p}: unknown table [{table}] (expected [settings] or one of "
                             f"{', '.join(f'[{g}]' for g in GROUPS)})")
        for k, v in values.items():
            if k not in known:
                raise ValueError(f"{p}: [{table}] {k} is not a print setting")
            out[k] = v
    return out


def resolve_settings(*, printer: str | None = None, config=None, **given) -> dict:
    """`PrintSettings` field values: the printer profile's, then the file's, then `given`.

    Examples
    --------
    >>> s = resolve_settings(printer="generic-marlin-220", layer_height=0.1)
    >>> s["bed_size"], s["layer_height"]
    ((220.0, 220.0), 0.1)
    """
    fromfile = read_config(config) if config is not None else {}
    name = printer or fromfile.pop("printer", None)
    fromfile.pop("printer", None)
    if name is not None and name not in PRINTERS:
        raise ValueError(f"printer must be one of {', '.join(PRINTERS)}, got {name!r}")
    out = dict(PRINTERS[name]) if name else {}
    out.update(fromfile)
    out.update({k: v for k, v in given.items() if v is not None})
    return out


def format_config(settings) -> str:
    """The settings in force as a TOML settings file, a table per group (``slicelab slice --print-config``).

    Examples
    --------
    >>> from slicelab.printing import PrintSettings
    >>> print(format_config(PrintSettings()).split("\\n[walls]")[0])
    [extrusion]
    layer_height = 0.2
    first_layer_height = 0.2
    line_width = 0.4
    n_perimeters = 2
    nozzle_diameter = 0.4
    filament_diameter = 1.75
    extrusion_multiplier = 1.0
    gcode_resolution = 0.0125
    bridge_flow_ratio = 1.0
    <BLANKLINE>
    """
    from dataclasses import asdict

    from .settings import GROUPS

    def value(v):
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, (tuple, list)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    lines = []
    for g in GROUPS:
        lines += [f"[{g}]"] + [f"{k} = {value(v)}" for k, v in asdict(getattr(settings, g)).items()
                               if v is not None] + [""]
    return "\n".join(lines)
