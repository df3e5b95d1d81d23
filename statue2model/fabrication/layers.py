"""Cross-sections of a closed mesh at the layers of a stacked-board prototype.

A prototype at scale 1:lambda is built from boards of thickness ``board`` glued
with a film of thickness ``glue``: layer k (k = 0 at the base) fills
z in [k p, k p + board] with pitch p = board + glue, all lengths in m. Each layer's
outline is a shapely MultiPolygon that may hold several islands and holes; the
section policy says which:

    mid       the section at the board's mid-plane (default; second-order accurate)
    envelope  the union of the sections through the board (both faces and three
              planes between): the board is never smaller than the statue
    core      their intersection: the board never sticks out of the statue

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

POLICIES = ("mid", "envelope", "core")
SLAB_PLANES = 5
"""Planes through a board for the envelope and core policies (faces included)."""


def section_heights(height: float, board: float, glue: float, policy: str = "mid") -> np.ndarray:
    """z (m) of the mid-plane of each layer, bottom first: n = ceil(height / pitch)
    layers (the top one trimmed by the body)."""
    return layer_bottoms(height, board, glue, policy) + 0.5 * board


def layer_bottoms(height: float, board: float, glue: float, policy: str = "mid") -> np.ndarray:
    """z (m) of the underside of each board, bottom first (k * pitch): the boards
    whose mid-plane lies below the top of the body (policy 'envelope': every board
    the body reaches into)."""
    if not (math.isfinite(height) and height > 0):
        raise InputError(f"body height must be positive, got {height}")
    if not (math.isfinite(board) and board > 0):
        raise InputError(f"board thickness must be positive, got {board}")
    if not (math.isfinite(glue) and glue >= 0):
        raise InputError(f"glue thickness must be >= 0, got {glue}")
    if policy not in POLICIES:
        raise InputError(f"section policy {policy!r} is not one of {', '.join(POLICIES)}")
    pitch = board + glue
    n = int(math.ceil(height / pitch - 1e-9))
    z0 = np.arange(n) * pitch
    if policy == "envelope":          # any board the body reaches into
        return z0[z0 < height - 1e-9 * height]
    return z0[z0 + 0.5 * board < height]


def layer_sections(vertices, faces, bottoms, board: float, policy: str = "mid",
                   tolerance: float = 0.0) -> list[MultiPolygon]:
    """The outline of each board (bottom z in ``bottoms``, m) under ``policy``,
    simplified to ``tolerance`` (m, topology kept)."""
    bottoms = np.asarray(bottoms, dtype=float)
    if policy == "mid":
        out = sections(vertices, faces, bottoms + 0.5 * board)
    elif policy in ("envelope", "core"):
        # planes just inside the board faces: a face exactly on the base plane has no section
        t = np.linspace(1e-4, 1 - 1e-4, SLAB_PLANES)
        top = float(np.asarray(vertices)[:, 2].max())
        z = np.minimum(bottoms[:, None] + board * t[None, :], top - 1e-6 * board)
        flat = sections(vertices, faces, z.ravel())
        out = []
        for k in range(len(bottoms)):
            slab = [s for s in flat[k * SLAB_PLANES:(k + 1) * SLAB_PLANES]]
            if policy == "envelope":
                geom = shapely.union_all(slab)
            else:
                geom = slab[0]
                for s in slab[1:]:
                    geom = geom.intersection(s)
            out.append(_as_multipolygon(geom))
    else:
        raise InputError(f"section policy {policy!r} is not one of {', '.join(POLICIES)}")
    if tolerance > 0:
        out = [_as_multipolygon(shapely.simplify(s, tolerance, preserve_topology=True)) for s in out]
    return out


def _as_multipolygon(geom) -> MultiPolygon:
    polys = [g for g in shapely.get_parts(shapely.make_valid(geom)) if isinstance(g, Polygon) and g.area > 0]
    return MultiPolygon(polys)


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
    return _as_multipolygon(out)


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
