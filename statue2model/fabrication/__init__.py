"""Prototype fabrication: a scaled statue as glued boards, and its CNC files.

The pipeline, one module per idea (``slicing.slice_body`` runs it, ``output``
writes the files; ``statue2model slice`` on the command line):

    spec        SliceSpec: scale, board, glue, tool, rod, sheet, ... (frozen, SI)
    layers      section heights and cross-sections of a closed mesh (islands, holes)
    toolcheck   inside corners, narrow openings, thin features; tool compensation
    rods        alignment rods through the stack, per island group
    labels      engraved single-stroke part numbers and front arrows
    nesting     true-shape nesting of the parts on panels
    dxf         CNC-ready DXF (R2010, mm; CUT_OUTSIDE, CUT_INSIDE, DRILL, ENGRAVE)
    prototype   the stack as built: closed-form mass properties, STL
    slicing     the whole computation -> SliceResult
    output      layer and sheet DXF, previews, BOM, assembly order, JSON
    robust      shapely/GEOS operations retried on cleaned polygons (make_valid,
                snapped to 1e-9 / 1e-6 m), else one named error
"""
