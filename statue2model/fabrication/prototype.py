"""The prototype as built: stacked boards, glue films and alignment rods.

Board k is the prism of its (as-cut) outline minus the rod holes, from z = k p to
k p + board, in OSB. The glue film above it covers where boards k and k + 1 meet
(their intersection, minus the holes), ``glue`` thick. Each rod is a cylinder of
the rod's diameter and its own length. The mass properties are integrated in
closed form from the polygons (Green's theorem), so they are exact for the outlines
written to the DXF files; the rocking parameters then follow as for a scan, with
the footprint of board 1 as the base.

Example
-------
>>> from shapely.geometry import MultiPolygon, box
>>> layer = MultiPolygon([box(-0.1, -0.05, 0.1, 0.05)])
>>> mp = stack_mass_properties([layer] * 10, pitch=0.01, board=0.01, glue=0.0,
...                            holes=[np.zeros((0, 2))] * 10, hole=0.0, rods=(), densities=(500.0, 0.0, 0.0))
>>> round(mp.mass, 6), round(float(mp.com[2]), 6)          # 0.2 x 0.1 x 0.1 m of 500 kg/m^3
(1.0, 0.05)
>>> round(float(mp.inertia[0, 0]), 8)                     # m (0.1^2 + 0.1^2) / 12
0.00166667
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import Point, Polygon

from ..geometry.massprops import MassProperties


def _ring_moments(xy: np.ndarray) -> np.ndarray:
    """[A, Sx, Sy, Ixx, Iyy, Ixy] = integrals of 1, x, y, x^2, y^2, xy over a closed
    ring's signed area (positive counter-clockwise)."""
    x0, y0 = xy[:-1, 0], xy[:-1, 1]
    x1, y1 = xy[1:, 0], xy[1:, 1]
    c = x0 * y1 - x1 * y0
    return np.array([
        c.sum() / 2,
        ((x0 + x1) * c).sum() / 6,
        ((y0 + y1) * c).sum() / 6,
        ((x0 * x0 + x0 * x1 + x1 * x1) * c).sum() / 12,
        ((y0 * y0 + y0 * y1 + y1 * y1) * c).sum() / 12,
        ((x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) * c).sum() / 24,
    ])


def area_moments(geom) -> np.ndarray:
    """[A, Sx, Sy, Ixx, Iyy, Ixy] of a (Multi)Polygon (holes subtracted)."""
    total = np.zeros(6)
    for poly in shapely.get_parts(shapely.orient_polygons(geom)):
        if not isinstance(poly, Polygon) or poly.is_empty:
            continue
        total += _ring_moments(np.asarray(poly.exterior.coords))
        for ring in poly.interiors:
            total += _ring_moments(np.asarray(ring.coords))   # clockwise: negative
    return total


class _Accumulator:
    """Zeroth, first and second moments of mass about the origin."""

    def __init__(self):
        self.m = 0.0
        self.first = np.zeros(3)
        self.second = np.zeros((3, 3))   # integral of r r^T dm
        self.volume = 0.0

    def prism(self, mom: np.ndarray, z0: float, z1: float, rho: float) -> None:
        A, Sx, Sy, Ixx, Iyy, Ixy = mom
        t = z1 - z0
        if A <= 0 or t <= 0:
            return
        z1m = (z1**2 - z0**2) / 2
        z2m = (z1**3 - z0**3) / 3
        self.volume += A * t
        self.m += rho * A * t
        self.first += rho * np.array([Sx * t, Sy * t, A * z1m])
        self.second += rho * np.array([
            [Ixx * t, Ixy * t, Sx * z1m],
            [Ixy * t, Iyy * t, Sy * z1m],
            [Sx * z1m, Sy * z1m, A * z2m],
        ])

    def cylinder(self, x: float, y: float, radius: float, z0: float, z1: float, rho: float) -> None:
        A = np.pi * radius**2
        k = A * radius**2 / 4                       # integral of x'^2 over the disc
        mom = np.array([A, A * x, A * y, A * x * x + k, A * y * y + k, A * x * y])
        self.prism(mom, z0, z1, rho)

    def result(self) -> MassProperties:
        com = self.first / self.m
        J = self.second - self.m * np.outer(com, com)
        inertia = np.trace(J) * np.eye(3) - J
        return MassProperties(volume=float(self.volume), mass=float(self.m), density=float(self.m / self.volume),
                              com=com, inertia=inertia)


def _holes_geom(centres: np.ndarray, hole: float):
    if hole <= 0 or len(centres) == 0:
        return None
    return shapely.union_all([Point(c).buffer(0.5 * hole, quad_segs=32) for c in centres])


def stack_mass_properties(layers, pitch: float, board: float, glue: float, holes, hole: float,
                          rods, densities: tuple[float, float, float], rod: float = 0.0) -> MassProperties:
    """Mass properties of the built stack.

    layers    : per board, the as-cut outline (MultiPolygon, m)
    holes     : per board, (n, 2) hole centres, m; ``hole`` their diameter
    rods      : iterable of objects with x, y, z_bottom, z_top (m); ``rod`` their diameter
    densities : (board, glue, rod), kg/m^3
    """
    rho_board, rho_glue, rho_rod = densities
    acc = _Accumulator()
    drilled = []
    for k, layer in enumerate(layers):
        cut = _holes_geom(holes[k], hole)
        drilled.append(layer.difference(cut) if cut is not None else layer)
    for k, layer in enumerate(drilled):
        z0 = k * pitch
        acc.prism(area_moments(layer), z0, z0 + board, rho_board)
        if glue > 0 and rho_glue > 0 and k + 1 < len(drilled):
            acc.prism(area_moments(layer.intersection(drilled[k + 1])), z0 + board, z0 + pitch, rho_glue)
    if rho_rod > 0 and rod > 0:
        for r in rods:
            acc.cylinder(r.x, r.y, 0.5 * rod, r.z_bottom, r.z_top, rho_rod)
    return acc.result()


def stack_mesh(layers, pitch: float, board: float, glue: float):
    """The stack as a triangle mesh (vertices (n, 3) m, faces (f, 3)): one closed
    shell per board and per glue film, each extruded with manifold3d, then
    concatenated (they only touch, face to face; a boolean union, or manifold's
    compose, of ~200 slabs touching on shared planes takes 2-15 s for the same
    volume). Rod holes are not cut: the rods fill them."""
    import manifold3d as m3d

    solids = []

    def extrude(geom, z0, t):
        polys = []
        for poly in shapely.get_parts(shapely.orient_polygons(geom)):
            if not isinstance(poly, Polygon) or poly.is_empty:
                continue
            polys.append(np.asarray(poly.exterior.coords)[:-1])
            polys.extend(np.asarray(r.coords)[:-1] for r in poly.interiors)
        if not polys or t <= 0:
            return
        mesh = m3d.Manifold.extrude(m3d.CrossSection(polys, m3d.FillRule.EvenOdd), t).to_mesh64()
        verts = np.asarray(mesh.vert_properties)[:, :3].astype(float) + (0.0, 0.0, z0)
        solids.append((verts, np.asarray(mesh.tri_verts).astype(np.int64)))

    for k, layer in enumerate(layers):
        z0 = k * pitch
        extrude(layer, z0, board)
        if glue > 0 and k + 1 < len(layers):
            extrude(layer.intersection(layers[k + 1]), z0 + board, glue)
    if not solids:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    offsets = np.cumsum([0] + [len(v) for v, _ in solids[:-1]])
    return (np.vstack([v for v, _ in solids]),
            np.vstack([f + off for (_, f), off in zip(solids, offsets)]))


@dataclass(frozen=True)
class Comparison:
    """Prototype against the scaled scan: relative errors (signed, prototype / scan - 1),
    and the centre-of-mass offset as a fraction of the scan's height."""

    volume: float
    mass_ratio: float
    com_offset: float
    I_G_per_mass: float
    b_L: float
    b_R: float
    h: float
    a_L: float
    a_R: float

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


def compare(proto_mass: MassProperties, proto_params, scan_mass: MassProperties, scan_params,
            height: float) -> Comparison:
    """Relative errors of the prototype (as built) against the scaled scan."""
    rel = lambda a, b: a / b - 1.0
    return Comparison(
        volume=rel(proto_mass.volume, scan_mass.volume),
        mass_ratio=proto_mass.mass / scan_mass.mass,
        com_offset=float(np.linalg.norm(proto_mass.com - scan_mass.com) / height),
        I_G_per_mass=rel(proto_params.I_G / proto_params.m, scan_params.I_G / scan_params.m),
        b_L=rel(proto_params.b_L, scan_params.b_L),
        b_R=rel(proto_params.b_R, scan_params.b_R),
        h=rel(proto_params.h, scan_params.h),
        a_L=rel(proto_params.a_L, scan_params.a_L),
        a_R=rel(proto_params.a_R, scan_params.a_R),
    )
