"""Filling: rectilinear lines and the infill patterns by name.

==========================  =====================================================
``fill.lines``              rectilinear filling lines, linked into zigzags
``fill.patterns``           infill patterns by name: rectilinear, concentric, gyroid
==========================  =====================================================
"""
