"""The isolator plates' contact surfaces for the 3D scene: the grooves as a lattice or as tiles.

* lattice (the default groove model, isolator_scene.GRID): :func:`grid_cap` triangulates each
  spherical groove on a regular triangular lattice lifted onto the sphere, :func:`grid_plate_mesh`
  adds the carved face (and the top plate's upper face) - one concave triangle mesh per plate;
* tiles (groove 'tiles'): :func:`tile_cap` covers each groove with flat square tiles tangent to the
  sphere, :func:`tile_plate` gives every plate's boxes, :func:`tile_boxes` their centres, axes and
  sizes - a compound of convex pieces (loaded by isolator_scene).

Frames as statue2model.isolator.plates.plate_solid's; lengths in m.

Example
-------
>>> v, f = grid_cap(0.9, 0.008, 0.004)
>>> bool(abs(float(v[:, 2].min()) + 0.008) < 1e-3), v.shape[1], f.shape[1]
(True, 3, 3)
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError


def grid_cap(R: float, depth: float, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """A spherical cap (radius R, depth ``depth``, opening a) triangulated on a regular triangular
    lattice of side ``spacing`` (m) in plan, lifted onto the sphere: every vertex exactly on the
    sphere, near-equilateral faces of the same size everywhere (at most 6 per vertex; no fan of
    ``segments`` slivers at the deepest point), the rim a ring of vertices exactly at radius a.
    The lattice is shifted by spacing / 4 across x so that a ball rolling along x crosses edges
    instead of running along one. Returns (vertices (n, 3) with the face at z = 0 and the cap
    below it, faces (k, 3) oriented with their normals towards the sphere's centre)."""
    from scipy.spatial import Delaunay

    a = math.sqrt(depth * (2 * R - depth))
    dy = spacing * math.sqrt(3) / 2
    nr = math.ceil(a / dy) + 1
    pts = []
    for j in range(-nr, nr + 1):
        y = j * dy + spacing / 4
        off = 0.5 * spacing * (j % 2)
        nx = math.ceil(a / spacing) + 1
        for i in range(-nx, nx + 1):
            x = i * spacing + off
            if math.hypot(x, y) < a - 0.5 * spacing:
                pts.append((x, y))
    m = max(12, math.ceil(2 * math.pi * a / spacing))
    ph = 2 * math.pi * np.arange(m) / m
    xy = np.vstack([np.asarray(pts, dtype=float).reshape(-1, 2), np.column_stack([a * np.cos(ph), a * np.sin(ph)])])
    tri = Delaunay(xy).simplices
    rho2 = np.minimum((xy**2).sum(axis=1), a * a)
    z = (R - depth) - np.sqrt(R * R - rho2)          # face z = 0; deepest point -depth
    z[-m:] = 0.0                                      # the rim exactly on the face
    v = np.column_stack([xy, z])
    e1, e2 = v[tri[:, 1]] - v[tri[:, 0]], v[tri[:, 2]] - v[tri[:, 0]]
    flip = np.cross(e1, e2)[:, 2] < 0                 # normals up (towards the centre, above the cap)
    tri[flip] = tri[flip][:, ::-1]
    return v, tri


def grid_plate_mesh(geom, which: str, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """The contact surfaces of a plate (its own frame, as plate_solid's): the grooves (:func:`grid_cap`),
    the carved face around them as a coarse triangulation of the face with a ring of vertices on
    each groove rim, and for the top plate its upper face (two triangles; the statue stands on it).
    Not a closed solid: Bullet collides a concave mesh triangle by triangle, and these are all the
    triangles the balls and the statue can touch."""
    from scipy.spatial import Delaunay

    t, half = geom.thickness, 0.5 * geom.side
    cv, cf = grid_cap(geom.R, geom.depth, spacing)
    verts, faces = [], []
    n = 0
    rims = []
    for (cx, cy) in geom.groove_centres:
        verts.append(cv + [cx, cy, t])
        faces.append(cf + n)
        n += len(cv)
        rims.append(cv[cv[:, 2] == 0.0, :2] + [cx, cy])
    # carved face: corners + rim rings, Delaunay, drop the triangles inside a groove
    corners = np.array([[-half, -half], [half, -half], [half, half], [-half, half]])
    fxy = np.vstack([corners] + rims)
    ft = Delaunay(fxy).simplices
    cen = fxy[ft].mean(axis=1)
    a = geom.opening_radius
    inside = np.zeros(len(ft), bool)
    for (cx, cy) in geom.groove_centres:
        inside |= np.hypot(cen[:, 0] - cx, cen[:, 1] - cy) < a
    ft = ft[~inside]
    fv = np.column_stack([fxy, np.full(len(fxy), t)])
    e1, e2 = fv[ft[:, 1]] - fv[ft[:, 0]], fv[ft[:, 2]] - fv[ft[:, 0]]
    flip = np.cross(e1, e2)[:, 2] < 0
    ft[flip] = ft[flip][:, ::-1]
    verts.append(fv)
    faces.append(ft + n)
    n += len(fv)
    v, f = np.vstack(verts), np.vstack(faces)
    if which == "top":              # mirror z -> t - z (carved face at z = 0), reorient, add the upper face
        v = v * [1.0, 1.0, -1.0] + [0.0, 0.0, t]
        f = f[:, ::-1]
        up = np.array([[-half, -half, t], [half, -half, t], [half, half, t], [-half, half, t]])
        v = np.vstack([v, up])
        f = np.vstack([f, np.array([[0, 1, 2], [0, 2, 3]]) + n])
    elif which != "bottom":
        raise InputError(f"plate must be 'bottom' or 'top', got {which!r}")
    return v, f.astype(np.int64)


TILE_THICKNESS = 0.004
"""Thickness of a groove tile, m (outward, behind its contact face)."""

_BOX_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                       [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])


def tile_cap(R: float, depth: float, size: float, overlap: float = 1.3) -> np.ndarray:
    """A spherical groove (radius R, depth ``depth``, opening a) as flat square tiles tangent to the
    sphere: tangent points on a square lattice of ``size`` (m) in plan over the whole opening, each tile
    a thin box (side ``overlap`` x size, TILE_THICKNESS behind the face, away from the centre) whose face
    is the tangent plane. The tiles meet at creases inside the region they bound (a polyhedron around
    the sphere, touching it at the tangent points); a tile's part beyond a crease lies behind its
    neighbour's plane, out of reach. A ball of radius r touches one tile (two or four at a crease):
    every contact is convex-convex with one plane, the normal within size / (sqrt(2) R) of the radial
    one. Frame as :func:`grid_cap` (face at z = 0, cap below, sphere centre at z = R - depth).
    Returns the tiles' vertices (k, 8, 3): box corners, the first four of each (bit 0 of the index)
    ... see _BOX_FACES for the faces."""
    a = math.sqrt(depth * (2 * R - depth))
    n = math.ceil(a / size) + 1
    c = np.array([0.0, 0.0, R - depth])
    half = 0.5 * overlap * size
    out = []
    for i in range(-n, n + 1):
        for j in range(-n, n + 1):
            x, y = (i + 0.25) * size, j * size          # shifted: a ball rolling along x crosses creases
            if math.hypot(x, y) > a + 0.5 * size:
                continue
            rho = min(math.hypot(x, y), 0.999 * R)
            pt = np.array([x, y, (R - depth) - math.sqrt(R * R - rho * rho)])
            nrm = (c - pt) / np.linalg.norm(c - pt)        # towards the centre
            e1 = np.array([1.0, 0.0, 0.0]) - nrm[0] * nrm
            e1 /= np.linalg.norm(e1)
            e2 = np.cross(nrm, e1)
            corners = [pt + s1 * half * e1 + s2 * half * e2 - dz * TILE_THICKNESS * nrm
                       for s1 in (-1, 1) for s2 in (-1, 1) for dz in (0, 1)]
            out.append(corners)
    return np.asarray(out)


def tile_plate(geom, which: str, size: float) -> tuple[np.ndarray, np.ndarray]:
    """The convex pieces of a plate (its own frame, as plate_solid's): the tiles of every groove
    (:func:`tile_cap`) and, for the top plate, a slab under its upper face (the statue stands on it).
    Returns (vertices (8 k, 3), faces (12 k, 3)): every 8 vertices and 12 faces one convex box."""
    t, half = geom.thickness, 0.5 * geom.side
    cap = tile_cap(geom.R, geom.depth, size)
    tiles = [cap + [cx, cy, t] for (cx, cy) in geom.groove_centres]
    v = np.concatenate(tiles).reshape(-1, 3)
    if which == "top":
        v = v * [1.0, 1.0, -1.0] + [0.0, 0.0, t]
        h = min(0.5 * t, max(t - geom.depth - 0.002, 0.001))
        slab = np.array([[sx * half, sy * half, z] for sx in (-1, 1) for sy in (-1, 1) for z in (t - h, t)])
        v = np.vstack([v, slab])
    elif which != "bottom":
        raise InputError(f"plate must be 'bottom' or 'top', got {which!r}")
    k = len(v) // 8
    f = (_BOX_FACES[None, :, :] + 8 * np.arange(k)[:, None, None]).reshape(-1, 3)
    return v, f.astype(np.int64)


def tile_boxes(v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The boxes of :func:`tile_plate`'s vertices ``v`` (8 k, 3): centres (k, 3), rotation matrices
    (k, 3, 3) whose columns are the box axes (right-handed), full side lengths (k, 3), all m."""
    c = np.asarray(v, dtype=float).reshape(-1, 8, 3)
    e = np.stack([c[:, 4] - c[:, 0], c[:, 2] - c[:, 0], c[:, 1] - c[:, 0]], axis=2)   # (k, 3 coords, 3 axes)
    dims = np.linalg.norm(e, axis=1)
    rot = e / dims[:, None, :]
    flip = np.linalg.det(rot) < 0                          # the top plate is a mirror image
    rot[flip, :, 2] *= -1
    return c.mean(axis=1), rot, dims
