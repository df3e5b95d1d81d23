"""The footprint: where a body standing on z = 0 touches its base.

The contact region F is made of the faces whose three vertices lie within
``tol`` of the base plane; its outline is traced from the region's boundary
edges (no polygon unions, so it is fast on million-face scans). Rocking pivots
are the extreme points of conv(F) along the excitation direction, so the convex
hull is computed from every contact vertex (also where the body touches the base
only at points, e.g. on feet).

Example
-------
>>> import trimesh
>>> from statue2model.geometry.footprint import footprint
>>> box = trimesh.creation.box(extents=(0.4, 0.2, 1.0))
>>> _ = box.apply_translation((0, 0, 0.5))
>>> fp = footprint(box.vertices, box.faces, tol=1e-9)
>>> round(fp.area, 12), round(fp.hull_area, 12)
(0.08, 0.08)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ..errors import InputError
from .topology import boundary_loops, edge_topology


@dataclass(frozen=True)
class Footprint:
    """Contact region on the base plane (coordinates in m, in the body frame).

    polygons  : list of (exterior (k, 2), [holes (j, 2), ...]) rings, exterior counter-clockwise
    hull      : (k, 2) convex hull of the contact vertices, counter-clockwise, not closed
    area      : area of the contact faces, m^2
    hull_area : area of the hull, m^2
    tol       : height below which a vertex counts as touching, m
    """

    polygons: tuple
    hull: np.ndarray
    area: float
    hull_area: float
    tol: float

    def to_dict(self) -> dict:
        return {
            "area": self.area,
            "hull_area": self.hull_area,
            "tol": self.tol,
            "hull": self.hull.tolist(),
            "polygons": [
                {"exterior": ext.tolist(), "holes": [h.tolist() for h in holes]} for ext, holes in self.polygons
            ],
        }

    def shifted(self, dxy: np.ndarray) -> "Footprint":
        """The same footprint moved by ``dxy`` (2,) in plan."""
        return Footprint(
            polygons=tuple((e + dxy, tuple(h + dxy for h in holes)) for e, holes in self.polygons),
            hull=self.hull + dxy, area=self.area, hull_area=self.hull_area, tol=self.tol,
        )

    def contains(self, point: np.ndarray) -> float:
        """Signed distance from ``point`` (2,) to the hull boundary, positive inside (m)."""
        return float(hull_edge_distances(self.hull, point)[1].min())


def hull_edge_distances(hull: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outward unit normals (k, 2) of the edges of a CCW hull (k, 2) and the signed
    distances (k,) from ``point`` to each edge's line, positive inside."""
    edges = np.roll(hull, -1, axis=0) - hull
    normals = np.column_stack([edges[:, 1], -edges[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return normals, np.einsum("ij,ij->i", hull - point, normals)


def convex_hull_2d(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise convex hull of (n, 2) points; empty (0, 2) when degenerate."""
    pts = np.unique(np.asarray(points, dtype=float), axis=0)
    if len(pts) < 3:
        return np.zeros((0, 2))
    try:
        hull = ConvexHull(pts)
    except QhullError:
        return np.zeros((0, 2))
    return pts[hull.vertices]  # qhull returns 2-D hulls counter-clockwise


def polygon_area(ring: np.ndarray) -> float:
    """Signed area (m^2) of a ring, positive when counter-clockwise."""
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _rings(vertices: np.ndarray, faces: np.ndarray) -> tuple:
    """Outline of a set of downward faces, as (exterior, holes) with CCW exteriors."""
    import shapely

    topo = edge_topology(faces, len(vertices))
    rings = [vertices[loop, :2] for loop in boundary_loops(topo.boundary_edges) if len(loop) >= 3]
    # Seen from above, a downward face runs clockwise: an outer boundary runs
    # clockwise and a hole's boundary counter-clockwise.
    outer = [r[::-1] for r in rings if polygon_area(r) < 0]
    holes = [r[::-1] for r in rings if polygon_area(r) > 0]
    shells = [shapely.Polygon(r) for r in outer]
    assigned: list[list[np.ndarray]] = [[] for _ in outer]
    for h in holes:
        p = shapely.Point(h[0])
        inside = [i for i, s in enumerate(shells) if s.covers(p)]
        if inside:
            best = min(inside, key=lambda i: shells[i].area)
            assigned[best].append(h)
    return tuple((o, tuple(a)) for o, a in zip(outer, assigned))


def footprint(vertices: np.ndarray, faces: np.ndarray, tol: float) -> Footprint:
    """Footprint of a body resting on z = 0 (vertices (n, 3) in m, faces (f, 3))."""
    low = vertices[:, 2] <= tol
    if not low.any():
        raise InputError("no part of the body touches the base plane z = 0")
    hull = convex_hull_2d(vertices[low, :2])
    if len(hull) < 3 or polygon_area(hull) <= 1e-12 * np.ptp(vertices[:, :2], axis=0).prod():
        raise InputError("the body touches its base only at a point or along a line: it cannot stand")
    base_faces = faces[low[faces].all(axis=1)]
    polygons = _rings(vertices, base_faces) if len(base_faces) else ()
    area = float(sum(polygon_area(ext) + sum(polygon_area(h) for h in holes) for ext, holes in polygons))
    return Footprint(polygons=polygons, hull=hull, area=area, hull_area=polygon_area(hull), tol=tol)
