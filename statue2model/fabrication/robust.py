"""Geometry-library (shapely/GEOS) operations that survive nearly degenerate polygons.

A scan's cross-sections at nearly tangent planes hold slivers, nearly coincident
edges and rings that touch themselves; the polygons built from them are valid by
GEOS's own test, yet an overlay or offset of them can still fail with
``GEOSException: TopologyException`` ("found non-noded intersection", "side
location conflict"), and an *invalid* polygon makes GEOS raise or, worse, return
a wrong answer without a word (a buffer of a self-crossing ring loses area). GEOS's
own offsets are not always valid either: the closing (outward then inward offset)
of some sections of the bundled scans crosses itself by a few nanometres, and the
difference with the section then raises "found non-noded intersection" (the
class of the Lucy scan at 1:2); :func:`buffer` makes its result valid.

Every shapely operation of the fabrication code that can raise goes through
:func:`safe_op`: it runs the operation as asked and, only when GEOS raises, runs it
again on cleaned copies of its geometry arguments, each step more forceful than
the one before (:data:`CLEANING`):

    1. ``make_valid`` (polygons rebuilt from their own linework; nothing moves)
    2. coordinates snapped to a 1e-9 m grid (``shapely.set_precision``), made valid
    3. snapped to a 1e-6 m grid (1 um: far below a cutter's or a board's accuracy)
    4. snapped to 1e-6 m and ``buffer(0)``

The first step that works gives the result. When none does the operation is
refused with a :class:`GeometryError` (an :class:`~statue2model.errors.InputError`:
one line, no traceback) that names what was being done; the slicing code names
the layer and its height in it.

:func:`as_multipolygon` turns any result into a valid MultiPolygon of its areal
parts (nested collections included: ``make_valid`` may return a collection that
holds a MultiPolygon next to the collapsed lines).

Example
-------
>>> from shapely.geometry import Polygon, box
>>> bowtie = Polygon([(0, 0), (1, 1), (1, 0), (0, 1)])      # crosses itself at (0.5, 0.5)
>>> round(safe_op(shapely.difference, bowtie, box(0, 0, 0.2, 0.2), what="a test").area, 6)   # GEOS alone raises
0.48
>>> round(as_multipolygon(bowtie).area, 6), len(as_multipolygon(bowtie).geoms)
(0.5, 2)
"""
from __future__ import annotations

import re
from collections.abc import Callable

import numpy as np
import shapely
from shapely.errors import GEOSException
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.base import BaseGeometry

from ..errors import InputError

SNAP_GRIDS = (1e-9, 1e-6)
"""Grids (m) the coordinates are snapped to when an operation fails on the polygons as
they are: the finer first; 1e-6 m is the coarsest, well below the tool's accuracy."""
CLEANING = ("make_valid", "snap 1e-09 m", "snap 1e-06 m", "snap 1e-06 m + buffer(0)")
"""The cleaning steps of :func:`safe_op`, in the order they are tried."""


class GeometryError(InputError):
    """A polygon operation that fails even on cleaned polygons (see module)."""


def polygons(geom) -> list[Polygon]:
    """The polygons (area > 0) of any geometry or collection, nested ones included."""
    if geom is None:
        return []
    out: list[Polygon] = []
    stack = list(shapely.get_parts(geom))
    while stack:
        g = stack.pop(0)
        if isinstance(g, Polygon):
            if not g.is_empty and g.area > 0:
                out.append(g)
        elif g.geom_type in ("MultiPolygon", "GeometryCollection"):
            stack[:0] = list(shapely.get_parts(g))
    return out


def _valid(geom):
    """``geom`` made valid: areal inputs stay areal (collapsed bits dropped)."""
    if geom is None or geom.is_empty or geom.is_valid:
        return geom
    if shapely.get_dimensions(geom) == 2:
        fixed = shapely.make_valid(geom, method="structure", keep_collapsed=False)
        return MultiPolygon(polygons(fixed)) if not isinstance(fixed, (Polygon, MultiPolygon)) else fixed
    return shapely.make_valid(geom)


def as_multipolygon(geom, what: str = "cleaning an outline") -> MultiPolygon:
    """A valid MultiPolygon of the areal parts of ``geom`` (made valid first when it
    is not: a ring that crosses itself keeps both lobes); ``what`` names it in a
    :class:`GeometryError`."""
    if geom is None or geom.is_empty:
        return MultiPolygon()
    if isinstance(geom, MultiPolygon) and geom.is_valid and all(p.area > 0 for p in geom.geoms):
        return geom
    if isinstance(geom, Polygon) and geom.is_valid and geom.area > 0:
        return MultiPolygon([geom])
    parts = polygons(safe_op(_valid, geom, what=what) if not geom.is_valid else geom)
    out = MultiPolygon(parts)
    if not out.is_valid:             # valid parts that overlap or share edges: merge them
        out = MultiPolygon(polygons(safe_op(shapely.union_all, np.array(parts, dtype=object), what=what)))
    return out


def clean(geom, step: int):
    """``geom`` after cleaning step ``step`` (0-based index into :data:`CLEANING`);
    arrays and lists of geometries element by element; anything else unchanged."""
    if isinstance(geom, (list, tuple, np.ndarray)):
        return np.array([clean(g, step) for g in geom], dtype=object)
    if not isinstance(geom, BaseGeometry) or geom.is_empty:
        return geom
    if step == 0:
        return _valid(geom)
    grid = SNAP_GRIDS[0] if step == 1 else SNAP_GRIDS[1]
    try:
        base = _valid(geom)
    except GEOSException:            # snapping may still mend what make_valid cannot
        base = geom
    snapped = _valid(shapely.set_precision(base, grid, mode="valid_output"))
    if step >= 3 and shapely.get_dimensions(snapped) == 2:
        snapped = _valid(snapped.buffer(0))
    return snapped


def _geometric(a) -> bool:
    if isinstance(a, BaseGeometry):
        return True
    if isinstance(a, (list, tuple, np.ndarray)):
        return len(a) > 0 and all(isinstance(g, BaseGeometry) or g is None for g in a)
    return False


def short_reason(exc: BaseException) -> str:
    """The first clause of a GEOS message, without coordinates: 'TopologyException:
    found non-noded intersection', 'TopologyException: side location conflict'."""
    text = (str(exc).splitlines() or [""])[0]
    text = re.split(r" between | at |\. ", text)[0]
    return text if len(text) <= 120 else text[:117] + "..."


def _same(a, b) -> bool:
    if isinstance(a, np.ndarray) and isinstance(b, (list, tuple, np.ndarray)):
        return len(a) == len(b) and all(x is y for x, y in zip(a, b))
    return a is b


def safe_op(fn: Callable, *args, what: str, **kwargs):
    """``fn(*args, **kwargs)``, retried on cleaned geometry arguments (module
    docstring) when GEOS raises; :class:`GeometryError` naming ``what`` when every
    cleaning step fails too. Arguments that are not geometries (distances,
    options) are passed on unchanged."""
    try:
        return fn(*args, **kwargs)
    except GEOSException as exc:
        first = exc
    previous = list(args)
    for step in range(len(CLEANING)):
        try:
            cleaned = [clean(a, step) if _geometric(a) else a for a in args]
        except GEOSException:        # this cleaning step fails on these polygons: try the next
            continue
        if all(_same(c, p) for c, p in zip(cleaned, previous)):
            continue                 # this step changed nothing: the same call would fail again
        previous = cleaned
        try:
            return fn(*cleaned, **kwargs)
        except GEOSException:
            continue
    reason = short_reason(first)
    raise GeometryError(f"{what}: the geometry library (GEOS) failed ({reason}) even after the polygons were "
                        f"made valid and snapped to a {SNAP_GRIDS[-1] * 1e6:g} um grid") from None


# the operations the fabrication code uses, each through safe_op


def difference(a, b, *, what: str):
    """a - b (shapely.difference) through :func:`safe_op`."""
    return safe_op(shapely.difference, a, b, what=what)


def intersection(a, b, *, what: str):
    """a & b (shapely.intersection) through :func:`safe_op`."""
    return safe_op(shapely.intersection, a, b, what=what)


def union(a, b, *, what: str):
    """a | b (shapely.union) through :func:`safe_op`."""
    return safe_op(shapely.union, a, b, what=what)


def union_all(geoms, *, what: str):
    """The union of a sequence of geometries (shapely.union_all) through :func:`safe_op`."""
    geoms = [g for g in geoms if g is not None]
    if not geoms:
        return MultiPolygon()
    return safe_op(shapely.union_all, np.array(geoms, dtype=object), what=what)


def buffer(geom, distance: float, *, what: str, quad_segs: int = 16, **kwargs):
    """geom offset by ``distance`` (m; negative: inward) through :func:`safe_op`;
    ``quad_segs`` (segments per quarter circle, 16 as ``geom.buffer``) and ``kwargs``
    as for shapely.buffer. The result is made valid when it is not: GEOS's offset of
    a valid polygon with nearly coincident edges can cross itself (seen on the bundled
    scans' sections), and the next overlay then fails or goes wrong."""
    out = safe_op(shapely.buffer, geom, distance, what=what, quad_segs=quad_segs, **kwargs)
    return safe_op(_valid, out, what=what) if isinstance(out, BaseGeometry) else out


def simplify(geom, tolerance: float, *, what: str, preserve_topology: bool = True):
    """shapely.simplify through :func:`safe_op`."""
    return safe_op(shapely.simplify, geom, tolerance, what=what, preserve_topology=preserve_topology)
