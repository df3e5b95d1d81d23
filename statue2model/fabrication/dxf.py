"""CNC-ready DXF of one layer: R2010, millimetres, closed LWPOLYLINEs.

Layers of the drawing: CUT_OUTSIDE (outer contours of the parts) and CUT_INSIDE
(holes through a part). Coordinates are in mm ($INSUNITS = 4).

Example
-------
>>> import tempfile, pathlib
>>> from shapely.geometry import MultiPolygon, Polygon
>>> part = Polygon([(0, 0), (0.2, 0), (0.2, 0.1), (0, 0.1)], [[(0.05, 0.03), (0.08, 0.03), (0.08, 0.06)]])
>>> out = write_section_dxf(pathlib.Path(tempfile.mkdtemp()) / "layer_001.dxf", MultiPolygon([part]))
>>> polys = read_section_dxf(out)
>>> round(polys.area * 1e6, 6)    # mm^2 back, the triangle hole removed
19550.0
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from shapely.geometry import MultiPolygon, Polygon

from ..files import atomic_write

CUT_OUTSIDE = "CUT_OUTSIDE"
CUT_INSIDE = "CUT_INSIDE"
MM = 1000.0


def _ring_mm(coords) -> list[tuple[float, float]]:
    pts = np.asarray(coords)[:-1] * MM        # shapely repeats the first point
    return [tuple(p) for p in pts]


def write_section_dxf(path, section: MultiPolygon, label: str = "") -> Path:
    """Write the parts of one layer (section in m) to ``path`` (mm), atomically."""
    import ezdxf

    doc = ezdxf.new("R2010", setup=False)
    doc.header["$INSUNITS"] = 4       # millimetres
    doc.header["$MEASUREMENT"] = 1    # metric
    doc.layers.add(CUT_OUTSIDE, color=1)
    doc.layers.add(CUT_INSIDE, color=5)
    msp = doc.modelspace()
    for poly in section.geoms:
        msp.add_lwpolyline(_ring_mm(poly.exterior.coords), close=True, dxfattribs={"layer": CUT_OUTSIDE})
        for hole in poly.interiors:
            msp.add_lwpolyline(_ring_mm(hole.coords), close=True, dxfattribs={"layer": CUT_INSIDE})
    if label:
        doc.header["$PROJECTNAME"] = label
    return atomic_write(path, lambda p: doc.saveas(p))


def read_section_dxf(path) -> MultiPolygon:
    """Read a layer DXF back into a MultiPolygon in m (outer contours minus holes)."""
    import ezdxf
    from shapely.ops import unary_union

    doc = ezdxf.readfile(str(path))
    outer, inner = [], []
    for e in doc.modelspace().query("LWPOLYLINE"):
        pts = np.array([(x, y) for x, y, *_ in e.get_points()]) / MM
        (outer if e.dxf.layer == CUT_OUTSIDE else inner).append(Polygon(pts))
    shape = unary_union(outer).difference(unary_union(inner)) if inner else unary_union(outer)
    parts = [shape] if isinstance(shape, Polygon) else list(shape.geoms)
    return MultiPolygon([p for p in parts if isinstance(p, Polygon) and p.area > 0])


def audit(path) -> list[str]:
    """Errors ezdxf's audit finds in the file (empty when clean)."""
    import ezdxf

    doc = ezdxf.readfile(str(path))
    auditor = doc.audit()
    return [str(e.message) for e in auditor.errors]
