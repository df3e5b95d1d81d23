"""The base a body rests on: rest plane, contact tolerance, and how much the answer depends on it.

A rigid body on a rigid floor rests on the facet of its 3D convex hull that holds
the projection of its centre of mass G (along the facet's normal): that facet's
plane is the floor (:func:`statue2model.geometry.orient.rest_plane`). Which points of the scan touch the floor is a matter of
tolerance: a scanned base is never exactly flat (triangulation, noise, a warped
or dished stone). The contact tolerance follows from the scan itself:

    tol = max(BASE_TOL h_body, 6 sigma, edge / 4), at most BASE_BAND h_body

with sigma the roughness of the base (rms of its heights about a smooth quadratic
surface fitted to them: the floor touches the lowest reading, about 3 sigma below
the true surface, and the true surface reads up to 3 sigma above it, hence 6 sigma) and edge the median edge length of its faces (the scan's
resolution there). The smooth surface also gives the base's *warp*: how far it
rises above the rest plane within the base (a dished, domed or saddle-shaped
underside). The edge term lets a scan triangle that rises from the floor at up to
14 deg (atan 1/4) count as touching at its far end. The pivots, and so b_L, b_R and the uplift acceleration, are then
recomputed at half and at double the tolerance: when the weakest uplift
acceleration a_min moves more than SENSITIVITY_LIMIT, the contact is uncertain
and the user is told so, with the numbers.

Example
-------
>>> import numpy as np, trimesh
>>> from statue2model.geometry.body import body_from_mesh
>>> disc = trimesh.creation.cylinder(radius=0.4, height=1.0, sections=64)
>>> body = body_from_mesh(disc.vertices, disc.faces, units="m", up="z")
>>> c = body.base
>>> round(c.tol * 1000, 3), round(c.surface.warp * 1000, 3), c.uncertain   # 0.5 % of the height: coarse fan
(5.0, 0.0, False)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..quantities import G

from .footprint import convex_hull_2d, hull_edge_distances, polygon_area
from .orient import BASE_BAND, base_faces

BASE_TOL = 1e-3
"""Least contact tolerance as a fraction of the body's height (1.8 mm on 1.8 m)."""
SENSITIVITY_LIMIT = 0.10
"""Relative change of a_min between half and double the tolerance above which the
base contact is reported as uncertain."""


@dataclass(frozen=True)
class BaseSurface:
    """What the scan says about its base (m, body frame, rest plane z = 0).

    edge      : median edge length of the base's faces (the scan's resolution there)
    roughness : rms of the base's heights about a fitted quadratic surface
    warp      : largest rise of that smooth surface above z = 0 within the base
    n_points  : base vertices used
    """

    edge: float
    roughness: float
    warp: float
    n_points: int


def base_surface(vertices: np.ndarray, faces: np.ndarray) -> BaseSurface:
    """Resolution, roughness and warp of the base of a body resting on z = 0."""
    sel, _ = base_faces(vertices, faces)
    if not len(sel):
        return BaseSurface(0.0, 0.0, 0.0, 0)
    f = faces[sel]
    e = np.linalg.norm(vertices[f] - vertices[np.roll(f, -1, axis=1)], axis=2).ravel()
    ids = np.unique(f)
    p = vertices[ids]
    if len(p) < 12:
        return BaseSurface(float(np.median(e)), 0.0, float(p[:, 2].max()), len(p))
    centre = p[:, :2].mean(axis=0)
    scale = float(np.ptp(p[:, :2], axis=0).max()) or 1.0
    x, y = ((p[:, :2] - centre) / scale).T
    A = np.column_stack([np.ones_like(x), x, y, x * x, x * y, y * y])
    coef, *_ = np.linalg.lstsq(A, p[:, 2], rcond=None)
    smooth = A @ coef
    rough = float(np.sqrt(np.mean((p[:, 2] - smooth) ** 2)))
    return BaseSurface(float(np.median(e)), rough, float(max(smooth.max(), 0.0)), len(p))


def contact_tolerance(surface: BaseSurface, height: float) -> tuple[float, str]:
    """The tolerance of the module docstring (m) and which term set it."""
    terms = {"0.1 % of the height": BASE_TOL * height, "6 x the base roughness": 6.0 * surface.roughness,
             "a quarter of the scan's edge length at the base": 0.25 * surface.edge}
    why = max(terms, key=terms.get)
    tol = terms[why]
    cap = BASE_BAND * height
    if tol > cap:
        return cap, f"{why}, capped at {BASE_BAND:.1%} of the height"
    return tol, why


@dataclass(frozen=True)
class ContactCase:
    """The contact hull at one tolerance: tol (m), hull (k, 2) CCW (empty when the body
    touches at a point or along a line), a_min (m/s^2, 0 when it cannot stand)."""

    tol: float
    hull: np.ndarray
    a_min: float

    def b(self, com: np.ndarray, direction_deg: float) -> tuple[float, float]:
        """(b_L, b_R) along ``direction_deg`` (m): where the rays from G's projection along -x and +x leave this
        contact hull (geometry/rocking_params.ray_exit); 0, 0 when G is not inside."""
        from .rocking_params import ray_exit

        if len(self.hull) < 3 or hull_edge_distances(self.hull, com[:2])[1].min() <= 0:
            return 0.0, 0.0
        psi = np.radians(direction_deg)
        x = np.array([np.cos(psi), np.sin(psi)])
        return ray_exit(self.hull, com[:2], -x)[0], ray_exit(self.hull, com[:2], x)[0]


def contact_case(vertices: np.ndarray, com: np.ndarray, tol: float, g: float = G) -> ContactCase:
    """Contact hull and weakest uplift acceleration with vertices within ``tol`` of z = 0."""
    hull = convex_hull_2d(vertices[vertices[:, 2] <= tol, :2])
    a_min = 0.0
    if len(hull) >= 3 and polygon_area(hull) > 0:
        dist = hull_edge_distances(hull, com[:2])[1].min()
        a_min = g * max(float(dist), 0.0) / float(com[2])
    return ContactCase(tol, hull, a_min)


@dataclass(frozen=True)
class BaseContact:
    """How the body meets the floor, and how sure that is.

    tol, why  : contact tolerance used (m) and the term that set it
    surface   : resolution, roughness and warp of the base (:class:`BaseSurface`)
    tilt      : rotation applied to rest on the hull facet, rad
    cases     : ContactCase at tol / 2, tol and 2 tol (the nominal one in the middle)
    """

    tol: float
    why: str
    surface: BaseSurface
    tilt: float
    cases: tuple[ContactCase, ContactCase, ContactCase]

    @property
    def spread(self) -> float:
        """Largest relative change of a_min at half or double the tolerance."""
        nominal = self.cases[1].a_min
        if nominal <= 0:
            return float("inf")
        return max(abs(c.a_min - nominal) for c in (self.cases[0], self.cases[2])) / nominal

    @property
    def uncertain(self) -> bool:
        return self.spread > SENSITIVITY_LIMIT

    def rows(self, com: np.ndarray, direction_deg: float, g: float = G) -> list[dict]:
        """One row per tolerance: tol, b_L, b_R along ``direction_deg``, a_min (m, m/s^2)."""
        out = []
        for c in self.cases:
            b_L, b_R = c.b(com, direction_deg)
            out.append({"tol": c.tol, "b_L": b_L, "b_R": b_R, "a_min": c.a_min, "a_min_g": c.a_min / g})
        return out

    def warning(self, g: float = G) -> str | None:
        """The line the user must read when the contact is uncertain, else None."""
        if not self.uncertain:
            return None
        lo, mid, hi = self.cases
        cause = (f"the base is not flat: its smooth surface rises {self.surface.warp * 1000:.1f} mm above the "
                 "rest plane" if self.surface.warp > 0.5 * self.tol else
                 f"the base is rough ({self.surface.roughness * 1000:.2f} mm rms)")
        return (f"uncertain base contact: the weakest uplift acceleration is {lo.a_min / g:.3f} g at half the "
                f"contact tolerance ({lo.tol * 1000:.2f} mm), {mid.a_min / g:.3f} g at {mid.tol * 1000:.2f} mm and "
                f"{hi.a_min / g:.3f} g at double ({hi.tol * 1000:.2f} mm), a change of {self.spread:.0%}; {cause}. "
                "Check the base (or measure it) and pass --base-tol to choose")

    def to_dict(self, com: np.ndarray, direction_deg: float, g: float = G) -> dict:
        return {"tol": self.tol, "why": self.why, "tilt_deg": float(np.degrees(self.tilt)),
                "edge": self.surface.edge, "roughness": self.surface.roughness, "warp": self.surface.warp,
                "sensitivity": self.rows(com, direction_deg, g), "spread": self.spread,
                "uncertain": self.uncertain, "limit": SENSITIVITY_LIMIT}


def base_contact(vertices: np.ndarray, com: np.ndarray, surface: BaseSurface, tol: float, why: str,
                 tilt: float, g: float = G) -> BaseContact:
    """The contact at tol / 2, tol and 2 tol of a body resting on z = 0 (G at ``com``)."""
    cases = tuple(contact_case(vertices, com, t, g) for t in (0.5 * tol, tol, 2.0 * tol))
    return BaseContact(tol=tol, why=why, surface=surface, tilt=tilt, cases=cases)
