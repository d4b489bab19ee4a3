"""What a print is told: settings in groups, each field declared with its range; printer profiles
and settings files; the bed.

==========================  =====================================================
``config.fields``           a setting's help, unit, range and choices, and its check
``config.settings``         `PrintSettings` in groups (extrusion, infill, skins, motion, ...)
``config.printers``         printer profiles, TOML settings files, start and end G-code
``config.bed``              `check_bed`: does the part fit the printer
==========================  =====================================================
"""
