"""What a round cutter of diameter ``tool`` can and cannot make of a layer's outline.

The cutter's centre runs outside the parts, so the material it leaves is the
morphological *closing* of the layer by a disc of radius r = tool/2:

    closing = layer.buffer(r).buffer(-r)

closing - layer is wood the cutter cannot remove: rounded inside corners, and
holes or gaps between parts narrower than the cutter (which it cannot enter at
all). Features of the part narrower than the cutter (``layer`` minus its opening
``layer.buffer(-r).buffer(r)``) are cut, but are thinner than the cutter and break
easily. Uncut wood is reported per layer when it strays from the true outline by
more than ``tol``; a thin feature when it reaches more than one cutter diameter
beyond what the cutter could round (a sliver, not just a sharp tip).

Compensation (off by default; CAM software normally does it) gives the path of the
cutter's centre instead of the outline: every part offset outward by r.

Example
-------
>>> from shapely.geometry import MultiPolygon, Polygon, box
>>> part = box(0, 0, 0.1, 0.1).difference(box(0.04, 0.02, 0.042, 0.08))   # a 2 mm slot
>>> report = check_layer(MultiPolygon([part]), tool=0.003)
>>> report.narrow_openings, round(report.max_deviation * 1000, 2)
(1, 1.0)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

RESOLUTION = 16
"""Segments per quarter circle of the offsets."""


@dataclass(frozen=True)
class ToolReport:
    """Per-layer findings (lengths in m, areas in m^2).

    corners          : inside corners and slot ends the cutter rounds off by more than tol
    narrow_openings  : holes and gaps between parts narrower than the cutter
    thin_features    : bits of the parts narrower than the cutter
    uncut_area       : wood left by the cutter (closing - layer)
    thin_area        : area of the thin features
    max_deviation    : farthest the cut outline strays from the true one
    """

    corners: int
    narrow_openings: int
    thin_features: int
    uncut_area: float
    thin_area: float
    max_deviation: float

    @property
    def clean(self) -> bool:
        return self.corners == 0 and self.narrow_openings == 0 and self.thin_features == 0

    def to_dict(self) -> dict:
        return {
            "inside_corners": self.corners, "narrow_openings": self.narrow_openings,
            "thin_features": self.thin_features, "uncut_area": self.uncut_area,
            "thin_area": self.thin_area, "max_deviation": self.max_deviation,
        }

    def describe(self, tool: float) -> str:
        bits = []
        if self.narrow_openings:
            bits.append(f"{self.narrow_openings} hole(s)/gap(s) narrower than the {tool * 1000:g} mm cutter")
        if self.corners:
            bits.append(f"{self.corners} inside corner(s) it rounds off (up to {self.max_deviation * 1000:.1f} mm)")
        if self.thin_features:
            bits.append(f"{self.thin_features} feature(s) thinner than the cutter "
                        f"({self.thin_area * 1e6:.0f} mm^2)")
        return "; ".join(bits)


def _regions(geom, min_area: float) -> list[Polygon]:
    return [g for g in shapely.get_parts(geom) if isinstance(g, Polygon) and g.area > min_area]


def _deviation(region: Polygon, outline) -> float:
    pts = shapely.points(shapely.get_coordinates(region.exterior))
    return float(np.max(shapely.distance(pts, outline))) if len(pts) else 0.0


def as_cut(layer: MultiPolygon, tool: float) -> MultiPolygon:
    """The parts as a cutter of diameter ``tool`` makes them (the closing)."""
    r = 0.5 * tool
    closed = layer.buffer(r, quad_segs=RESOLUTION).buffer(-r, quad_segs=RESOLUTION)
    return MultiPolygon(_regions(closed.union(layer), 0.0))


def check_layer(layer: MultiPolygon, tool: float, tol: float = 5e-4) -> ToolReport:
    """Inside corners, narrow openings and thin features of one layer (see module)."""
    if layer.is_empty:
        return ToolReport(0, 0, 0, 0.0, 0.0, 0.0)
    r = 0.5 * tool
    min_area = (0.1 * tol) ** 2
    outline = layer.boundary
    closed = layer.buffer(r, quad_segs=RESOLUTION).buffer(-r, quad_segs=RESOLUTION)
    uncut = closed.difference(layer)
    corners = narrow = 0
    max_dev = 0.0
    for region in _regions(uncut, min_area):
        dev = _deviation(region, outline)
        if dev <= 1e-9:
            # bounded by the true outline all round: a hole or gap the cutter cannot enter
            from shapely.ops import polylabel

            dev = float(region.exterior.distance(polylabel(region, tolerance=0.01 * tol)))
            if dev > 0.5 * tol:
                narrow += 1
                max_dev = max(max_dev, dev)
        else:
            # how far the true corner lies from the cut (rounded) outline
            dev = _deviation(region, closed.boundary)
            if dev > tol:
                corners += 1
                max_dev = max(max_dev, dev)
    opened = layer.buffer(-r, quad_segs=RESOLUTION).buffer(r, quad_segs=RESOLUTION)
    thin = [g for g in _regions(layer.difference(opened), min_area) if _deviation(g, opened.boundary) > max(tol, tool)]
    return ToolReport(
        corners=corners, narrow_openings=narrow, thin_features=len(thin),
        uncut_area=float(uncut.area), thin_area=float(sum(g.area for g in thin)), max_deviation=max_dev,
    )


def compensate(layer: MultiPolygon, tool: float) -> MultiPolygon:
    """Cutter-centre paths: each part offset outward by tool/2 (holes shrink, and
    vanish when narrower than the cutter)."""
    r = 0.5 * tool
    parts = []
    for poly in layer.geoms:
        parts.extend(_regions(poly.buffer(r, quad_segs=RESOLUTION), 0.0))
    return MultiPolygon(parts)
