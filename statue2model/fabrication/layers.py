"""Cross-sections of a closed mesh at the layers of a stacked-board prototype.

A prototype at scale 1:lambda is built from boards of thickness ``board`` glued
with a film of thickness ``glue``: layer k (k = 0 at the base) fills
z in [k p, k p + board] with pitch p = board + glue, all lengths in m. Each layer's
outline is one section of the scaled body (policy ``mid``: the board's mid-plane),
a shapely MultiPolygon that may hold several islands and holes.

Volume check (midpoint rule): sum_k A_k p differs from the volume under the
sections by at most (H p^2 / 24) max |A''(z)| plus the part of the top layer
above the body; the tests check it on a sphere and a cone.

Example
-------
>>> import trimesh
>>> sphere = trimesh.creation.icosphere(subdivisions=4, radius=0.1)
>>> v = sphere.vertices + [0, 0, 0.1]
>>> z = section_heights(0.2, board=0.009, glue=0.0005)
>>> len(z), round(float(z[0]), 5)
(21, 0.0045)
>>> secs = sections(v, sphere.faces, z)
>>> round(max(s.area for s in secs) / (3.14159 * 0.01), 2)   # the widest section ~ pi R^2
1.0
"""
from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from ..errors import InputError


def section_heights(height: float, board: float, glue: float, policy: str = "mid") -> np.ndarray:
    """z (m) of the section of each layer, bottom first: n = ceil(height / pitch)
    layers (the top one trimmed by the body); ``policy`` 'mid' cuts at the board's
    mid-plane."""
    if not (math.isfinite(height) and height > 0):
        raise InputError(f"body height must be positive, got {height}")
    if not (math.isfinite(board) and board > 0):
        raise InputError(f"board thickness must be positive, got {board}")
    if not (math.isfinite(glue) and glue >= 0):
        raise InputError(f"glue thickness must be >= 0, got {glue}")
    if policy != "mid":
        raise InputError(f"section policy {policy!r} is not available (use 'mid')")
    pitch = board + glue
    n = int(math.ceil(height / pitch - 1e-9))
    z = np.arange(n) * pitch + 0.5 * board
    return z[z < height]


def _segments(vertices: np.ndarray, faces: np.ndarray, z: float, cand: np.ndarray) -> np.ndarray:
    """(m, 2, 2) segments where faces ``cand`` cross the plane at height z.
    A vertex on the plane counts as above it; every crossing point is interpolated
    from the lower-numbered end of its edge, so neighbouring faces share it exactly."""
    f = faces[cand]
    d = vertices[f, 2] - z                      # (m, 3)
    above = d >= 0
    pts = np.zeros((len(f), 2, 2))
    k = np.zeros(len(f), dtype=int)
    for e0, e1 in ((0, 1), (1, 2), (2, 0)):
        cross = above[:, e0] != above[:, e1]
        if not np.any(cross):
            continue
        a = f[cross, e0]
        b = f[cross, e1]
        lo = np.minimum(a, b)
        hi = np.maximum(a, b)
        pa = vertices[lo]
        pb = vertices[hi]
        t = (z - pa[:, 2]) / (pb[:, 2] - pa[:, 2])
        p = pa[:, :2] + t[:, None] * (pb[:, :2] - pa[:, :2])
        idx = np.flatnonzero(cross)
        pts[idx, k[idx]] = p
        k[idx] += 1
    return pts[k == 2]


def _assemble(segs: np.ndarray) -> MultiPolygon:
    """Closed loops from segments, combined even-odd (islands, holes, islands in holes)."""
    if len(segs) == 0:
        return MultiPolygon()
    lines = shapely.linestrings(segs)
    rings = shapely.get_parts(shapely.polygonize(lines))
    rings = [r for r in rings if r.area > 0]
    rings.sort(key=lambda r: -r.area)
    out = Polygon()
    for r in rings:
        out = out.symmetric_difference(Polygon(r.exterior))
    out = shapely.make_valid(out)
    polys = [g for g in shapely.get_parts(out) if isinstance(g, Polygon) and g.area > 0]
    return MultiPolygon(polys)


def sections(vertices, faces, heights) -> list[MultiPolygon]:
    """The cross-section of a closed mesh (m) at each height (m), in plan (x, y)."""
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    fz = vertices[faces, 2]
    zmin, zmax = fz.min(axis=1), fz.max(axis=1)
    order = np.argsort(zmin)
    zmin_sorted = zmin[order]
    out = []
    for z in np.asarray(heights, dtype=float):
        reach = order[: np.searchsorted(zmin_sorted, z, side="right")]
        cand = reach[zmax[reach] >= z]
        out.append(_assemble(_segments(vertices, faces, z, cand)))
    return out
