"""Up axis and base: turn a scan so that it stands on its flat base on z = 0.

Scans come Y-up (most scanners, glTF, OBJ, PLY) or Z-up (CAD, STL). For each of
the six axis directions the lowest region of the body (vertices within 0.5 % of
the height of the lowest point, on faces facing down) is a candidate base. A
candidate is *stable* when the centre of mass projects inside the convex hull
of that region, and *flat* when the region covers a fair share of the body's
plan. Among the flat stable candidates the tallest pose wins (statues are
upright), ties going to +z, then +y. A pose whose base is scanned off level
(up to 10 degrees, e.g. on a sloping turntable) is judged, and then levelled,
on the facet of the convex hull it rests on (:func:`rest_plane`).

Frames: a Y-up file is turned by +90 degrees about x, (x, y, z) -> (x, -z, y);
every rotation used is proper (det = +1), so nothing is mirrored.

Example
-------
>>> import numpy as np, trimesh
>>> from statue2model.geometry.orient import UP_ROTATIONS
>>> UP_ROTATIONS["+y"] @ np.array([0.0, 1.0, 0.0])
array([0., 0., 1.])
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ..errors import InputError
from .footprint import convex_hull_2d, hull_edge_distances, polygon_area

UP_ROTATIONS = {
    "+z": np.eye(3),
    "+y": np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]]),
    "+x": np.array([[0.0, 0, -1], [0, 1, 0], [1, 0, 0]]),
    "-z": np.array([[1.0, 0, 0], [0, -1, 0], [0, 0, -1]]),
    "-y": np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]]),
    "-x": np.array([[0.0, 0, 1], [0, 1, 0], [-1, 0, 0]]),
}
"""Rotation turning each candidate up direction of the file into +z."""

BASE_BAND = 0.005
"""Vertices within this fraction of the height above the lowest point form a candidate base."""

MAX_LEVEL_TILT = np.radians(10.0)


@dataclass(frozen=True)
class BaseCandidate:
    up: str
    height: float  # extent along up, file units
    flat_area: float  # area of the down-facing faces in the base band, projected
    plan_area: float  # bounding-box area of the body seen from above
    stable: bool
    margin: float  # distance of the centre of mass projection inside the base hull

    @property
    def flatness(self) -> float:
        return self.flat_area / self.plan_area if self.plan_area > 0 else 0.0


def _rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Proper rotation turning unit vector a into unit vector b (Rodrigues)."""
    v = np.cross(a, b)
    c = float(np.dot(a, b))
    s = np.linalg.norm(v)
    if s < 1e-15:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = v / s
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def face_area_vectors(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(f, 3) face normals scaled by face area (turn with the body: av' = av @ R.T)."""
    a, b, c = (vertices[faces[:, j]] for j in range(3))
    return 0.5 * np.cross(b - a, c - a)


def _down_facing(area_vectors: np.ndarray, up: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Indices of faces facing down (within 20 deg) w.r.t. ``up``, and their projected areas."""
    down = -(area_vectors @ up)
    idx = np.flatnonzero(down > 0.94 * np.sqrt(np.einsum("ij,ij->i", area_vectors, area_vectors)))
    return idx, down[idx]


def evaluate_base(
    vertices: np.ndarray, faces: np.ndarray, area_vectors: np.ndarray, com: np.ndarray, up: str,
    extent: np.ndarray, level: bool = False,
) -> BaseCandidate:
    """Score the pose in which file direction ``up`` points up (``extent``: the (3,)
    bounding-box sizes of ``vertices``); ``level``: first turn it onto its rest facet."""
    R = UP_ROTATIONS[up]
    if level:
        R = rest_plane(vertices @ R.T, faces, R @ com)[0] @ R
    z = vertices @ R[2]
    zmin = z.min()
    height = float(z.max() - zmin)
    low = z - zmin <= BASE_BAND * height
    idx, down = _down_facing(area_vectors, R[2])
    in_band = low[faces[idx]].all(axis=1)
    flat_area = float(down[in_band].sum())
    plan_area = float(np.prod(np.abs(R[:2]) @ extent))
    hull = convex_hull_2d(vertices[low] @ R[:2].T)
    stable, margin = False, -np.inf
    if len(hull) >= 3 and polygon_area(hull) > 0:
        margin = float(hull_edge_distances(hull, R[:2] @ com)[1].min())
        stable = margin > 0
    return BaseCandidate(up, height, flat_area, plan_area, stable, margin)


def choose_up(
    vertices: np.ndarray, faces: np.ndarray, area_vectors: np.ndarray, com: np.ndarray, up: str = "auto"
) -> tuple[BaseCandidate, str]:
    """Pick the up direction (see the module docstring); ``up`` forces one ('+z', 'y', ...)."""
    extent = np.ptp(vertices, axis=0)
    if up != "auto":
        key = up if up[0] in "+-" else "+" + up
        if key not in UP_ROTATIONS:
            raise InputError(f"unknown up axis '{up}': use auto, x, y, z, -x, -y or -z")
        cand = evaluate_base(vertices, faces, area_vectors, com, key, extent)
        if not cand.stable:
            cand = evaluate_base(vertices, faces, area_vectors, com, key, extent, level=True)
        if not cand.stable:
            raise InputError(
                f"with {key} up the body would not stand: its centre of mass lies "
                f"{-cand.margin:.4g} file units outside its base"
            )
        return cand, f"up axis {key} as given"
    cands = [evaluate_base(vertices, faces, area_vectors, com, k, extent) for k in UP_ROTATIONS]
    if not any(c.stable and c.flat_area > 0 for c in cands):   # a base scanned off level: judge it levelled
        cands = [c if c.stable or c.flat_area <= 0 else
                 evaluate_base(vertices, faces, area_vectors, com, c.up, extent, level=True) for c in cands]
    stable = [c for c in cands if c.stable and c.flat_area > 0]
    if not stable:
        raise InputError(
            "no flat base on which the body stands was found along x, y or z "
            "(the centre of mass falls outside every candidate base): pass --up, or check the scan"
        )
    best_flat = max(c.flatness for c in stable)
    flat = [c for c in stable if c.flatness >= 0.5 * best_flat]
    tallest = max(c.height for c in flat)
    chosen = next(c for c in flat if c.height >= tallest * (1 - 1e-9))
    note = f"up axis detected as {chosen.up} (flat base, {chosen.flatness:.0%} of the plan)"
    others = [c.up for c in flat if c is not chosen]
    if others:
        note += f"; {', '.join(others)} would also stand: the tallest pose was taken, pass --up to choose"
    return chosen, note


MAX_REST_TURN = np.radians(5.0)
"""Rest facets are looked for within this angle of the base's own mean normal: a scan
tilted on its turntable is levelled, a body that would tip over onto another part of
itself is not (it does not stand)."""


def base_faces(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The base of a z-up body: indices of the faces facing down (within 20 deg) with every
    vertex within BASE_BAND of the height above the lowest point, and their area vectors."""
    z = vertices[:, 2]
    low = z <= z.min() + BASE_BAND * float(np.ptp(z))
    cand = np.flatnonzero(low[faces].all(axis=1))
    av = face_area_vectors(vertices, faces[cand])
    idx, _ = _down_facing(av, np.array([0.0, 0.0, 1.0]))
    return cand[idx], av[idx]


def base_normal(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray | None:
    """Area-weighted mean outward normal (3,) of the base (:func:`base_faces`) of a z-up
    body, or None when it has no down-facing face."""
    idx, av = base_faces(vertices, faces)
    if not len(idx):
        return None
    n = av.sum(axis=0)
    return n / np.linalg.norm(n)


def rest_plane(vertices: np.ndarray, faces: np.ndarray, com: np.ndarray) -> tuple[np.ndarray, float]:
    """Rotation (3, 3) that puts the body (z up, roughly on its base) on the hull facet
    it rests on, and that facet's tilt from horizontal (rad; 0 and identity when no
    facet qualifies).

    Candidates are the hull facets within MAX_REST_TURN of the base's mean normal
    (:func:`base_normal`), itself within MAX_LEVEL_TILT of straight down. Of those, the
    facet that contains the projection of G along its own normal is the stable one; if
    several do, the one closest to horizontal; if none does (G above an edge of the
    hull), the facet the vertical through G leaves the hull by.
    """
    around = base_normal(vertices, faces)
    if around is None or around[2] > -np.cos(MAX_LEVEL_TILT):
        return np.eye(3), 0.0
    z = vertices[:, 2]
    # the bottom of the hull only: the points low enough to matter for a 10 deg tilt
    span = float(np.ptp(vertices[:, :2], axis=0).max())
    low = z <= z.min() + np.tan(MAX_LEVEL_TILT + MAX_REST_TURN) * span + 1e-12
    # G joins the points: a base whose low points all lie in one plane still has a hull,
    # and the facets through G face up, so they never compete with the base's
    pts = np.vstack([vertices[low], com[None, :]])
    try:
        hull = ConvexHull(pts)
    except (QhullError, ValueError):
        return np.eye(3), 0.0
    n, d = hull.equations[:, :3], hull.equations[:, 3]
    down = (n @ around > np.cos(MAX_REST_TURN)) & (n[:, 2] < -np.cos(MAX_LEVEL_TILT + MAX_REST_TURN))
    if not down.any():
        return np.eye(3), 0.0
    idx = np.flatnonzero(down)
    tri = pts[hull.simplices[idx]]                     # (k, 3, 3)
    nn = n[idx]
    proj = com - (nn @ com + d[idx])[:, None] * nn      # G projected on each facet's plane
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    # qhull does not orient its simplices: inside means the three sides agree in sign
    sides = np.column_stack([np.einsum("ij,ij->i", np.cross(p1 - p0, proj - p0), nn)
                             for p0, p1 in ((a, b), (b, c), (c, a))])
    eps = 1e-12 * span**2
    inside = (sides >= -eps).all(axis=1) | (sides <= eps).all(axis=1)
    if inside.any():
        best = idx[inside][np.argmin(n[idx[inside], 2])]   # most nearly horizontal
    else:
        t = (n[idx] @ com + d[idx]) / n[idx, 2]           # exit of the downward vertical through G
        best = idx[np.argmin(t)]
    normal = n[best]
    tilt = float(np.arccos(np.clip(-normal[2], -1.0, 1.0)))
    if tilt <= 1e-12:
        return np.eye(3), 0.0
    return _rotation_between(normal, np.array([0.0, 0.0, -1.0])), tilt
