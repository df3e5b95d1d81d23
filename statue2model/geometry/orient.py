"""Up axis and base: turn a scan so that it stands on its flat base on z = 0.

Scans come Y-up (most scanners, glTF, OBJ, PLY) or Z-up (CAD, STL). For each of
the six axis directions the lowest region of the body (vertices within 0.5 % of
the height of the lowest point, on faces facing down) is a candidate base. A
candidate is *stable* when the centre of mass projects inside the convex hull
of that region, and *flat* when the region covers a fair share of the body's
plan. Among the flat stable candidates the tallest pose wins (statues are
upright), ties going to +z, then +y. The base is then levelled: its
area-weighted normal is turned to point exactly down (tilts of up to 10 degrees,
e.g. a scan taken on a sloping turntable).

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


@dataclass(frozen=True)
class Orientation:
    """Where the scan stands: x_body = rotation @ x_file + translation (after scaling)."""

    up: str
    rotation: np.ndarray
    tilt: float  # levelling correction applied, rad
    note: str


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
    extent: np.ndarray,
) -> BaseCandidate:
    """Score the pose in which file direction ``up`` points up (``extent``: the (3,)
    bounding-box sizes of ``vertices``)."""
    R = UP_ROTATIONS[up]
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
            raise InputError(
                f"with {key} up the body would not stand: its centre of mass lies "
                f"{-cand.margin:.4g} file units outside its base"
            )
        return cand, f"up axis {key} as given"
    cands = [evaluate_base(vertices, faces, area_vectors, com, k, extent) for k in UP_ROTATIONS]
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


def base_faces(vertices: np.ndarray, faces: np.ndarray, area_vectors: np.ndarray, height: float) -> np.ndarray:
    """Indices of the down-facing faces within BASE_BAND of the lowest point (z-up body)."""
    z = vertices[:, 2]
    low = z - z.min() <= BASE_BAND * height
    idx, _ = _down_facing(area_vectors, np.array([0.0, 0.0, 1.0]))
    return idx[low[faces[idx]].all(axis=1)]


def base_roughness(vertices: np.ndarray, faces: np.ndarray, area_vectors: np.ndarray, height: float) -> float:
    """Standard deviation of the heights of the base's vertices (z-up, levelled body), length unit."""
    sel = base_faces(vertices, faces, area_vectors, height)
    if not len(sel):
        return 0.0
    return float(np.std(vertices[np.unique(faces[sel]), 2]))


def level_base(
    vertices: np.ndarray, faces: np.ndarray, area_vectors: np.ndarray, height: float
) -> tuple[np.ndarray, float]:
    """Rotation that makes the base (z-up body) exactly horizontal, and its tilt (rad).

    The base normal is the area-weighted mean normal of the down-facing faces within
    BASE_BAND of the lowest point. Tilts above 10 degrees are left alone (returns identity).
    """
    sel = base_faces(vertices, faces, area_vectors, height)
    if not len(sel):
        return np.eye(3), 0.0
    n = area_vectors[sel].sum(axis=0)
    n /= np.linalg.norm(n)
    tilt = float(np.arccos(np.clip(-n[2], -1.0, 1.0)))
    if tilt == 0.0 or tilt > MAX_LEVEL_TILT:
        return np.eye(3), 0.0
    return _rotation_between(n, np.array([0.0, 0.0, -1.0])), tilt
