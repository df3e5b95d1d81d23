"""Prototype fabrication: OSB layers of a scaled statue and their CNC files.

Modules: ``layers`` (section heights and cross-sections of a closed mesh),
``dxf`` (one CNC-ready DXF per layer).
"""
