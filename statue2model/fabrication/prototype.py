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
from . import robust


def area_moments(geom) -> np.ndarray:
    """[A, Sx, Sy, Ixx, Iyy, Ixy] of a (Multi)Polygon (holes subtracted): every ring
    at once (exteriors counter-clockwise, holes clockwise, so holes count negative)."""
    parts = shapely.get_parts(shapely.orient_polygons(geom))
    parts = parts[(shapely.get_type_id(parts) == 3) & ~shapely.is_empty(parts)]
    if len(parts) == 0:
        return np.zeros(6)
    xy, ring = shapely.get_coordinates(shapely.get_rings(parts), return_index=True)
    same = ring[1:] == ring[:-1]                    # consecutive points of one ring: an edge
    x0, y0 = xy[:-1][same].T
    x1, y1 = xy[1:][same].T
    c = x0 * y1 - x1 * y0
    return np.array([
        c.sum() / 2,
        ((x0 + x1) * c).sum() / 6,
        ((y0 + y1) * c).sum() / 6,
        ((x0 * x0 + x0 * x1 + x1 * x1) * c).sum() / 12,
        ((y0 * y0 + y0 * y1 + y1 * y1) * c).sum() / 12,
        ((x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) * c).sum() / 24,
    ])


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


def _holes_geom(centres: np.ndarray, hole: float, what: str = "the rod holes"):
    if hole <= 0 or len(centres) == 0:
        return None
    return robust.union_all([Point(c).buffer(0.5 * hole, quad_segs=32) for c in centres], what=what)


def stack_mass_properties(layers, pitch: float, board: float, glue: float, holes, hole: float,
                          rods, densities: tuple[float, float, float], rod: float = 0.0) -> MassProperties:
    """Mass properties of the built stack.

    layers    : per board, the as-cut outline (MultiPolygon, m)
    holes     : per board, (n, 2) hole centres, m; ``hole`` their diameter
    rods      : iterable of objects with x, y, z_bottom, z_top (m); ``rod`` their diameter
    densities : (board, glue, rod), kg/m^3
    """
    return combine(stack_moments(layers, pitch, board, glue, holes, hole, rods, rod), densities)


def stack_moments(layers, pitch: float, board: float, glue: float, holes, hole: float, rods,
                  rod: float = 0.0) -> tuple:
    """Volume moments (density 1) of the boards, the glue films and the rods of the
    stack (arguments as :func:`stack_mass_properties`), to be weighted by :func:`combine`."""
    acc = (_Accumulator(), _Accumulator(), _Accumulator())
    drilled = []
    for k, layer in enumerate(layers):
        cut = _holes_geom(holes[k], hole, f"the rod holes of layer {k + 1}")
        drilled.append(robust.difference(layer, cut, what=f"drilling the rod holes of layer {k + 1}")
                       if cut is not None else layer)
    for k, layer in enumerate(drilled):
        z0 = k * pitch
        acc[0].prism(area_moments(layer), z0, z0 + board, 1.0)
        if glue > 0 and k + 1 < len(drilled):
            film = robust.intersection(layer, drilled[k + 1], what=f"the glue film on layer {k + 1}")
            acc[1].prism(area_moments(film), z0 + board, z0 + pitch, 1.0)
    if rod > 0:
        for r in rods:
            acc[2].cylinder(r.x, r.y, 0.5 * rod, r.z_bottom, r.z_top, 1.0)
    return acc


def combine(moments: tuple, densities: tuple[float, float, float]) -> MassProperties:
    """Mass properties of volume moments (:func:`stack_moments`) at their densities
    (a density of 0 leaves that material out)."""
    total = _Accumulator()
    for a, rho in zip(moments, densities):
        if rho > 0:
            total.m += rho * a.m
            total.first += rho * a.first
            total.second += rho * a.second
            total.volume += a.volume
    return total.result()


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
            extrude(robust.intersection(layer, layers[k + 1], what=f"the glue film on layer {k + 1}"),
                    z0 + board, glue)
    if not solids:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    offsets = np.cumsum([0] + [len(v) for v, _ in solids[:-1]])
    return (np.vstack([v for v, _ in solids]),
            np.vstack([f + off for (_, f), off in zip(solids, offsets)]))


ERROR_LIMIT = 0.05
"""Relative error of the prototype against the scaled scan above which a quantity
fails (warning, red row in the report)."""
CHECKED = ("volume", "h", "b_L", "b_R", "I_G_per_mass", "a_R", "a_min")
"""The errors held to ERROR_LIMIT (a_R: along the analysed direction; a_L is not:
the weakest side is a_R or a_min)."""
LABELS = {"volume": "volume", "h": "h", "b_L": "b_L", "b_R": "b_R", "I_G_per_mass": "I_G / m",
          "a_L": "a_L", "a_R": "a_R", "a_min": "a_min (weakest direction)"}


@dataclass(frozen=True)
class PrototypeComparison:
    """Prototype against the scaled scan: relative errors (signed, prototype / scan - 1),
    and the centre-of-mass offset as a fraction of the scan's height. ``a_min`` is the
    uplift acceleration in each body's own weakest direction."""

    volume: float
    mass_ratio: float
    com_offset: float
    I_G_per_mass: float
    b_L: float
    b_R: float
    h: float
    a_L: float
    a_R: float
    a_min: float = 0.0

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    def largest(self) -> tuple[str, float]:
        """(key, error) of the largest |error| among the parameters and the volume."""
        keys = ("volume", "h", "b_L", "b_R", "I_G_per_mass", "a_R", "a_min")
        key = max(keys, key=lambda k: abs(getattr(self, k)))
        return key, getattr(self, key)

    def failing(self, limit: float = ERROR_LIMIT) -> list[str]:
        """Keys of CHECKED whose |error| exceeds ``limit``."""
        return [k for k in CHECKED if not abs(getattr(self, k)) <= limit]


def compare(proto_mass: MassProperties, proto_params, scan_mass: MassProperties, scan_params,
            height: float, proto_a_min: float | None = None, scan_a_min: float | None = None) -> PrototypeComparison:
    """Relative errors of the prototype (as built) against the scaled scan."""
    def rel(a, b):
        return a / b - 1.0
    return PrototypeComparison(
        volume=rel(proto_mass.volume, scan_mass.volume),
        mass_ratio=proto_mass.mass / scan_mass.mass,
        com_offset=float(np.linalg.norm(proto_mass.com - scan_mass.com) / height),
        I_G_per_mass=rel(proto_params.I_G / proto_params.m, scan_params.I_G / scan_params.m),
        b_L=rel(proto_params.b_L, scan_params.b_L),
        b_R=rel(proto_params.b_R, scan_params.b_R),
        h=rel(proto_params.h, scan_params.h),
        a_L=rel(proto_params.a_L, scan_params.a_L),
        a_R=rel(proto_params.a_R, scan_params.a_R),
        a_min=rel(proto_a_min, scan_a_min) if proto_a_min is not None and scan_a_min else 0.0,
    )


def stack_volume_moments(layers, pitch: float, board: float) -> MassProperties | None:
    """Volume-weighted moments (density 1) of ``layers`` (MultiPolygons, one per board,
    e.g. what was taken out of each) as boards of thickness ``board``; None when empty."""
    acc = _Accumulator()
    for k, layer in enumerate(layers):
        if layer is not None and not layer.is_empty:
            acc.prism(area_moments(layer), k * pitch, k * pitch + board, 1.0)
    return acc.result() if acc.m > 0 else None


def effect(scan_mass: MassProperties, delta: MassProperties | None, sign: float, axis: np.ndarray) -> dict:
    """First-order effect on the scan's volume, h and I_G / m (relative) of adding
    (sign +1) or removing (-1) the material ``delta`` (volume-weighted moments).
    ``axis``: the rocking axis (3,), horizontal, through G."""
    if delta is None:
        return {"volume": 0.0, "h": 0.0, "I_G_per_mass": 0.0}
    V = scan_mass.volume
    c = scan_mass.com
    J = scan_mass.inertia / scan_mass.density            # volume-weighted, about G
    I = float(axis @ J @ axis)
    r = delta.com - c
    dist2 = float(r @ r - (r @ axis) ** 2)
    dI = float(axis @ delta.inertia @ axis) + delta.volume * dist2
    dV = sign * delta.volume
    return {"volume": dV / V, "h": dV * (delta.com[2] - c[2]) / (V + dV) / c[2],
            "I_G_per_mass": sign * dI / I - dV / V}


def base_difference(scan_hull: np.ndarray, proto_hull: np.ndarray, scan_com: np.ndarray,
                    proto_com: np.ndarray, direction_deg: float) -> dict:
    """How the first board's hull differs from the scan's base footprint hull along
    the rocking direction (m): 'right' and 'left' how much further the board reaches
    toward each pivot, 'com' how far G's projection moved toward +x, 'width' the
    relative width difference across the base along x, 'area' the relative hull-area
    difference, 'nearest' the change of the distance from G to the nearest hull edge."""
    from ..geometry.footprint import hull_edge_distances, polygon_area

    psi = np.radians(direction_deg)
    u = np.array([np.cos(psi), np.sin(psi)])
    ps, pp = np.asarray(scan_hull) @ u, np.asarray(proto_hull) @ u
    near_s = float(hull_edge_distances(np.asarray(scan_hull), scan_com[:2])[1].min())
    near_p = float(hull_edge_distances(np.asarray(proto_hull), proto_com[:2])[1].min())
    return {"right": float(pp.max() - ps.max()), "left": float(ps.min() - pp.min()),
            "com": float((proto_com[:2] - scan_com[:2]) @ u),
            "width": float((pp.max() - pp.min()) / (ps.max() - ps.min()) - 1.0),
            "area": float(polygon_area(np.asarray(proto_hull)) / polygon_area(np.asarray(scan_hull)) - 1.0),
            "nearest": near_p - near_s}


def likely_causes(cmp: PrototypeComparison, base: dict, effects: dict[str, dict], notes: dict[str, str],
                  first_board: str, pitch: float) -> dict[str, str]:
    """A sentence per quantity of the comparison on what most likely makes its error,
    from numbers computed on this slice.

    base      : :func:`base_difference`
    effects   : label -> :func:`effect` of one known source of difference (parts
                dropped, slivers opened away, wood the cutter leaves, overlapping
                shells the scan counts twice, ...)
    notes     : extra facts per key (e.g. 'volume': 'layers 12-13 are empty: a gap in the scan')
    first_board : what the first board's outline is (e.g. 'its section 4.5 mm up')
    pitch     : the layer pitch (m)
    """
    out = {}
    side = {"b_R": ("right", 1.0), "b_L": ("left", -1.0)}
    for key, (name, s) in side.items():
        reach, moved = base[name], s * base["com"]
        if abs(reach) >= abs(moved):
            how = "narrower" if base["width"] < 0 else "wider"
            out[key] = (f"the first board's outline ({first_board}) reaches "
                        f"{abs(reach) * 1000:.1f} mm {'further' if reach > 0 else 'less far'} toward the "
                        f"{name} pivot than the scan's base footprint; it is {abs(base['width']) * 100:.1f} % "
                        f"{how} than the base along the rocking direction")
        else:
            out[key] = (f"the centre of mass moved {abs(base['com']) * 1000:.1f} mm toward the "
                        f"{'right' if base['com'] > 0 else 'left'} pivot (the board's edge moved "
                        f"{reach * 1000:+.1f} mm)")
    out["a_L"] = f"{out['b_L']}; h {cmp.h * 100:+.2f} %"
    out["a_R"] = f"{out['b_R']}; h {cmp.h * 100:+.2f} %"
    how = "closer to" if base["nearest"] < 0 else "farther from"
    out["a_min"] = (f"the nearest edge of the first board's hull is {abs(base['nearest']) * 1000:.1f} mm {how} "
                    f"G than that of the scan's base footprint (hull area {base['area'] * 100:+.1f} %); "
                    f"h {cmp.h * 100:+.2f} %")
    for key in ("volume", "I_G_per_mass", "h"):
        err = getattr(cmp, key)
        items = sorted(((label, e[key]) for label, e in effects.items() if abs(e[key]) >= 5e-5),
                       key=lambda t: -abs(t[1]))
        explained = sum(v for _, v in items)
        rest = err - explained
        bits = [f"{label} {v * 100:+.2f} %" for label, v in items]
        stepping = f"the stepping of the {pitch * 1000:g} mm layers and the sampling at mid-board"
        if items and abs(items[0][1]) >= abs(rest):
            text = f"mostly {items[0][0]} ({items[0][1] * 100:+.2f} %)"
            if len(items) > 1 or abs(rest) >= 5e-5:
                text += "; " + ", ".join(bits[1:] + [f"the rest {rest * 100:+.2f} %: {stepping}"])
        else:
            text = f"{stepping} ({rest * 100:+.2f} %)" + (f"; {', '.join(bits)}" if bits else
                                                           "; no part was dropped and no layer is missing")
        if key in notes:
            text += "; " + notes[key]
        out[key] = text
    return out
