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

What cannot be cut is taken out of the layer before anything else is planned
(:func:`trim_layer`): a part (island) narrower than the cutter everywhere (its
opening by r is empty) is dropped, and a thin feature is opened away (the part
minus that sliver: the opening is what is left of it). Both are counted per
layer, with their area, and :func:`summarise` turns a slice's reports into a
few lines (one per kind, with the layers), not one line per part.

Compensation (off by default; CAM software normally does it) gives the path of the
cutter's centre instead of the outline: every part offset outward by r.

Every offset and overlay goes through :mod:`.robust` (an invalid layer is made valid
first; a GEOS TopologyException is retried on cleaned polygons); what still fails is
a :class:`~.robust.GeometryError`, which ``slicing`` names with the layer.

Example
-------
>>> from shapely.geometry import MultiPolygon, Polygon, box
>>> part = box(0, 0, 0.1, 0.1).difference(box(0.04, 0.02, 0.042, 0.08))   # a 2 mm slot
>>> report = check_layer(MultiPolygon([part]), tool=0.003)
>>> report.narrow_openings, round(report.max_deviation * 1000, 2)
(1, 1.0)
>>> chip = box(0.2, 0, 0.202, 0.05)                                         # 2 mm wide: narrower than 3 mm
>>> kept, rep, removed = trim_layer(MultiPolygon([part, chip]), tool=0.003)
>>> len(kept.geoms), rep.dropped_parts, round(rep.dropped_area * 1e6, 1)
(1, 1, 100.0)
>>> summarise([rep], tool=0.003, board_area=kept.area + removed.area)[0]
'dropped 1 part narrower than the 3 mm cutter (total area 100 mm^2, 1.0 % of the board area), on layer 1'
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from . import robust

RESOLUTION = 16
"""Segments per quarter circle of the offsets."""


@dataclass(frozen=True)
class ToolReport:
    """Per-layer findings (lengths in m, areas in m^2).

    corners          : inside corners and slot ends the cutter rounds off by more than tol
    narrow_openings  : holes and gaps between parts narrower than the cutter
    thin_features    : bits of the parts narrower than the cutter (``trim_layer``:
                       opened away, no longer in the layer)
    uncut_area       : wood left by the cutter (closing - layer)
    thin_area        : area of the thin features
    max_deviation    : farthest the cut outline strays from the true one
    dropped_parts    : parts narrower than the cutter everywhere, left out (``trim_layer``)
    dropped_area     : their area
    trimmed          : True when thin features and narrow parts were taken out of the layer
    """

    corners: int
    narrow_openings: int
    thin_features: int
    uncut_area: float
    thin_area: float
    max_deviation: float
    dropped_parts: int = 0
    dropped_area: float = 0.0
    trimmed: bool = False

    @property
    def clean(self) -> bool:
        return (self.corners == 0 and self.narrow_openings == 0 and self.thin_features == 0
                and self.dropped_parts == 0)

    def to_dict(self) -> dict:
        return {
            "inside_corners": self.corners, "narrow_openings": self.narrow_openings,
            "thin_features": self.thin_features, "uncut_area": self.uncut_area,
            "thin_area": self.thin_area, "max_deviation": self.max_deviation,
            "dropped_parts": self.dropped_parts, "dropped_area": self.dropped_area,
            "trimmed": self.trimmed,
        }

    def describe(self, tool: float) -> str:
        bits = []
        if self.dropped_parts:
            bits.append(f"{self.dropped_parts} part(s) narrower than the {tool * 1000:g} mm cutter dropped "
                        f"({self.dropped_area * 1e6:.0f} mm^2)")
        if self.narrow_openings:
            bits.append(f"{self.narrow_openings} hole(s)/gap(s) narrower than the {tool * 1000:g} mm cutter")
        if self.corners:
            bits.append(f"{self.corners} inside corner(s) it rounds off (up to {self.max_deviation * 1000:.1f} mm)")
        if self.thin_features:
            bits.append(f"{self.thin_features} feature(s) thinner than the cutter "
                        f"({self.thin_area * 1e6:.0f} mm^2){' opened away' if self.trimmed else ''}")
        return "; ".join(bits)


def _regions(geom, min_area: float) -> list[Polygon]:
    return [g for g in robust.polygons(geom) if g.area > min_area]


def _deviation(region: Polygon, outline) -> float:
    pts = shapely.points(shapely.get_coordinates(region.exterior))
    return float(np.max(shapely.distance(pts, outline))) if len(pts) else 0.0


def _offset(geom, d: float, what: str):
    return robust.buffer(geom, d, quad_segs=RESOLUTION, what=what)


def _closing(layer, r: float):
    """The layer closed by a disc of radius r (what the cutter leaves)."""
    return _offset(_offset(layer, r, "the cutter check (outward offset)"), -r, "the cutter check (closing)")


def _opening(layer, r: float):
    """The layer opened by a disc of radius r (what the cutter can reach round)."""
    return _offset(_offset(layer, -r, "the cutter check (inward offset)"), r, "the cutter check (opening)")


def as_cut(layer: MultiPolygon, tool: float) -> MultiPolygon:
    """The parts as a cutter of diameter ``tool`` makes them (the closing)."""
    layer = robust.as_multipolygon(layer)
    if layer.is_empty:
        return layer
    closed = _closing(layer, 0.5 * tool)
    return MultiPolygon(_regions(robust.union(closed, layer, what="the boards as cut"), 0.0))


def check_layer(layer: MultiPolygon, tool: float, tol: float = 5e-4) -> ToolReport:
    """Inside corners, narrow openings and thin features of one layer (see module)."""
    layer = robust.as_multipolygon(layer)
    if layer.is_empty:
        return ToolReport(0, 0, 0, 0.0, 0.0, 0.0)
    r = 0.5 * tool
    corners, narrow, uncut_area, max_dev = _closing_findings(layer, r, tol)
    thin = _thin_features(layer, r, tol)
    return ToolReport(
        corners=corners, narrow_openings=narrow, thin_features=len(thin),
        uncut_area=uncut_area, thin_area=float(sum(g.area for g in thin)), max_deviation=max_dev,
    )


def _closing_findings(layer, r: float, tol: float) -> tuple[int, int, float, float]:
    """(inside corners, narrow openings, uncut area, largest deviation) of the closing."""
    min_area = (0.1 * tol) ** 2
    outline = layer.boundary
    closed = _closing(layer, r)
    uncut = robust.difference(closed, layer, what="the cutter check (uncut wood)")
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
    return corners, narrow, float(uncut.area), max_dev


def _thin_features(layer, r: float, tol: float, opened=None) -> list[Polygon]:
    """Bits of the layer outside its opening by r that reach more than a cutter
    diameter (or tol) beyond it: slivers, not just sharp tips."""
    min_area = (0.1 * tol) ** 2
    if opened is None:
        opened = _opening(layer, r)
    return [g for g in _regions(robust.difference(layer, opened, what="the cutter check (thin features)"), min_area)
            if _deviation(g, opened.boundary) > max(tol, 2 * r)]


def trim_layer(layer: MultiPolygon, tool: float, tol: float = 5e-4) -> tuple[MultiPolygon, ToolReport, MultiPolygon]:
    """What the cutter can make of a layer: (the layer without its parts narrower
    than the cutter and without its thin features, the report, what was taken out).

    A part is dropped when its opening by r = tool/2 is empty (no disc of the
    cutter's diameter fits in it anywhere); a thin feature (see module) is removed
    from its part, which may split it. Corners and narrow openings are then
    checked on what is kept (they only add wood: see :func:`as_cut`)."""
    layer = robust.as_multipolygon(layer)
    if layer.is_empty:
        return layer, ToolReport(0, 0, 0, 0.0, 0.0, 0.0, trimmed=True), MultiPolygon()
    r = 0.5 * tool
    parts = np.array(list(layer.geoms), dtype=object)
    eroded = _offset(layer, -r, "the cutter check (inward offset)")
    wide = shapely.intersects(parts, eroded) if not eroded.is_empty else np.zeros(len(parts), dtype=bool)
    dropped = list(parts[~wide])
    kept = MultiPolygon(list(parts[wide]))
    removed = list(dropped)
    thin: list[Polygon] = []
    if not kept.is_empty:
        opened = _offset(eroded, r, "the cutter check (opening)")
        thin = _thin_features(kept, r, tol, opened)
        if thin:
            slivers = robust.union_all(thin, what="the cutter check (slivers)")
            kept = _as_multipolygon(robust.difference(kept, slivers, what="the cutter check (opening slivers away)"))
            removed.extend(thin)
    corners, narrow, uncut_area, max_dev = _closing_findings(kept, r, tol) if not kept.is_empty else (0, 0, 0.0, 0.0)
    rep = ToolReport(
        corners=corners, narrow_openings=narrow, thin_features=len(thin), uncut_area=uncut_area,
        thin_area=float(sum(g.area for g in thin)), max_deviation=max_dev,
        dropped_parts=len(dropped), dropped_area=float(sum(g.area for g in dropped)), trimmed=True,
    )
    taken = _as_multipolygon(robust.union_all(removed, what="the cutter check (what it takes out)")) if removed \
        else MultiPolygon()
    return kept, rep, taken


def _as_multipolygon(geom) -> MultiPolygon:
    return robust.as_multipolygon(geom)


def layer_list(layers: list[int], most: int = 12) -> str:
    """'layer 4' / 'layers 3-9, 41' (1-based numbers), at most ``most`` runs shown."""
    runs = []
    for n in sorted(set(layers)):
        if runs and n == runs[-1][1] + 1:
            runs[-1][1] = n
        else:
            runs.append([n, n])
    text = ", ".join(f"{a}-{b}" if b > a else str(a) for a, b in runs[:most])
    if len(runs) > most:
        text += f" and {sum(b - a + 1 for a, b in runs[most:])} more"
    return ("layer " if len(layers) == 1 else "layers ") + text


def summarise(reports, tool: float, board_area: float) -> list[str]:
    """One line per kind of finding over a whole slice (``reports``: one ToolReport
    per layer, bottom first; ``board_area``: the layers' total area before trimming, m^2)."""
    mm = tool * 1000
    def share(a: float) -> str:
        pct = a / board_area * 100 if board_area > 0 else float("nan")
        return f"{pct:.1f} % of the board area" if pct >= 0.1 else f"{pct:.2g} % of the board area"

    out = []

    def where(pred):
        return [k + 1 for k, rep in enumerate(reports) if pred(rep)]

    n = sum(r.dropped_parts for r in reports)
    if n:
        a = sum(r.dropped_area for r in reports)
        out.append(f"dropped {n} part{'s' if n > 1 else ''} narrower than the {mm:g} mm cutter (total area "
                   f"{a * 1e6:.0f} mm^2, {share(a)}), on {layer_list(where(lambda r: r.dropped_parts))}")
    n = sum(r.thin_features for r in reports)
    if n:
        a = sum(r.thin_area for r in reports)
        verb = "opened away" if all(r.trimmed for r in reports) else "found"
        out.append(f"{verb} {n} sliver{'s' if n > 1 else ''} thinner than the {mm:g} mm cutter (total area "
                   f"{a * 1e6:.0f} mm^2, {share(a)}), on {layer_list(where(lambda r: r.thin_features))}")
    corners = sum(r.corners for r in reports)
    narrow = sum(r.narrow_openings for r in reports)
    if corners or narrow:
        bits = []
        if corners:
            bits.append(f"rounds {corners} inside corner{'s' if corners > 1 else ''} (by up to "
                        f"{max(r.max_deviation for r in reports if r.corners) * 1000:.1f} mm, on "
                        f"{layer_list(where(lambda r: r.corners))})")
        if narrow:
            bits.append(f"cannot enter {narrow} hole{'s' if narrow > 1 else ''} or gap{'s' if narrow > 1 else ''} "
                        f"(on {layer_list(where(lambda r: r.narrow_openings))})")
        a = sum(r.uncut_area for r in reports)
        out.append(f"the {mm:g} mm cutter " + " and ".join(bits)
                   + f": the wood it leaves ({a * 1e6:.0f} mm^2) is in the prototype as built")
    return out


def compensate(layer: MultiPolygon, tool: float) -> MultiPolygon:
    """Cutter-centre paths: each part offset outward by tool/2 (holes shrink, and
    vanish when narrower than the cutter)."""
    r = 0.5 * tool
    parts = []
    for poly in robust.as_multipolygon(layer).geoms:
        parts.extend(_regions(_offset(poly, r, "the tool compensation (cutter-centre path)"), 0.0))
    return MultiPolygon(parts)
