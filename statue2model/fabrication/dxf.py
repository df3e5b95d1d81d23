"""CNC-ready DXF: R2010, millimetres, one drawing layer per machining operation.

Layers of the drawing (the names CAM post-processors are set up for):

    CUT_OUTSIDE  closed LWPOLYLINE, outer contour of each part (cut outside it)
    CUT_INSIDE   closed LWPOLYLINE, a hole through a part (cut inside it)
    DRILL        CIRCLE, an alignment-rod hole (drilled, or helix-milled)
    ENGRAVE      open LWPOLYLINE, the part's label and front arrow (single strokes)

Coordinates are in mm ($INSUNITS = 4, $MEASUREMENT = 1); the geometry handed in
is in metres like the rest of the package.

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

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from ..io.files import atomic_write

CUT_OUTSIDE = "CUT_OUTSIDE"
CUT_INSIDE = "CUT_INSIDE"
DRILL = "DRILL"
ENGRAVE = "ENGRAVE"
LAYER_COLOURS = {CUT_OUTSIDE: 1, CUT_INSIDE: 5, DRILL: 3, ENGRAVE: 2}
MM = 1000.0


@dataclass(frozen=True)
class Drawing:
    """What is machined on one part, in metres, already where it goes on the drawing.

    outline : the part (exterior -> CUT_OUTSIDE, interiors -> CUT_INSIDE)
    holes   : (n, 2) centres of the rod holes (DRILL circles of diameter ``hole``)
    engrave : open polylines (k, 2) for the ENGRAVE layer
    """

    outline: object
    holes: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    hole: float = 0.0
    engrave: tuple = ()


def new_document(title: str = ""):
    """An empty R2010 drawing in mm with the four machining layers."""
    import ezdxf

    doc = ezdxf.new("R2010", setup=False)
    doc.header["$INSUNITS"] = 4       # millimetres
    doc.header["$MEASUREMENT"] = 1    # metric
    for name, colour in LAYER_COLOURS.items():
        doc.layers.add(name, color=colour)
    if title:
        doc.header["$PROJECTNAME"] = title
    return doc


def add_drawing(msp, drawing: Drawing) -> None:
    """Add one part's entities to a modelspace."""
    for poly in shapely.get_parts(drawing.outline):
        if not isinstance(poly, Polygon) or poly.is_empty:
            continue
        msp.add_lwpolyline(_ring_mm(poly.exterior.coords), close=True, dxfattribs={"layer": CUT_OUTSIDE})
        for hole in poly.interiors:
            msp.add_lwpolyline(_ring_mm(hole.coords), close=True, dxfattribs={"layer": CUT_INSIDE})
    for x, y in np.asarray(drawing.holes).reshape(-1, 2):
        msp.add_circle((x * MM, y * MM), 0.5 * drawing.hole * MM, dxfattribs={"layer": DRILL})
    for line in drawing.engrave:
        msp.add_lwpolyline([tuple(p) for p in np.asarray(line) * MM], close=False, dxfattribs={"layer": ENGRAVE})


def write_dxf(path, drawings, title: str = "") -> Path:
    """Write ``drawings`` (iterable of Drawing) to one DXF file at ``path``, atomically."""
    doc = new_document(title)
    msp = doc.modelspace()
    for d in drawings:
        add_drawing(msp, d)
    return atomic_write(path, lambda p: doc.saveas(p))


def read_dxf(path) -> Drawing:
    """Read a drawing back (all parts merged): outlines, DRILL circles, ENGRAVE strokes (m)."""
    import ezdxf

    doc = ezdxf.readfile(str(path))
    msp = doc.modelspace()
    outline = read_section_dxf(path, doc=doc)
    circles = [e for e in msp.query("CIRCLE") if e.dxf.layer == DRILL]
    holes = np.array([(c.dxf.center.x, c.dxf.center.y) for c in circles]).reshape(-1, 2) / MM
    hole = 2 * circles[0].dxf.radius / MM if circles else 0.0
    strokes = tuple(np.array([(x, y) for x, y, *_ in e.get_points()]) / MM
                    for e in msp.query("LWPOLYLINE") if e.dxf.layer == ENGRAVE)
    return Drawing(outline=outline, holes=holes, hole=hole, engrave=strokes)


def _ring_mm(coords) -> list[tuple[float, float]]:
    pts = np.asarray(coords)[:-1] * MM        # shapely repeats the first point
    return [tuple(p) for p in pts]


def write_section_dxf(path, section: MultiPolygon, label: str = "") -> Path:
    """Write the parts of one layer (section in m, nothing else) to ``path`` (mm), atomically."""
    return write_dxf(path, [Drawing(outline=section)], title=label)


def read_section_dxf(path, doc=None) -> MultiPolygon:
    """Read the cut contours of a DXF back into a MultiPolygon in m (outer contours minus holes)."""
    import ezdxf
    from . import robust

    doc = doc or ezdxf.readfile(str(path))
    outer, inner = [], []
    for e in doc.modelspace().query("LWPOLYLINE"):
        if e.dxf.layer not in (CUT_OUTSIDE, CUT_INSIDE):
            continue
        pts = np.array([(x, y) for x, y, *_ in e.get_points()]) / MM
        (outer if e.dxf.layer == CUT_OUTSIDE else inner).append(Polygon(pts))
    what = f"reading the contours of {path}"
    shape = robust.union_all(outer, what=what)
    if inner:
        shape = robust.difference(shape, robust.union_all(inner, what=what), what=what)
    return MultiPolygon(robust.polygons(shape))


def audit(path) -> list[str]:
    """Errors ezdxf's audit finds in the file (empty when clean)."""
    import ezdxf

    doc = ezdxf.readfile(str(path))
    auditor = doc.audit()
    return [str(e.message) for e in auditor.errors]
