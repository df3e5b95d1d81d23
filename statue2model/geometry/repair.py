"""Turn a raw scan into a closed, consistently oriented volume, and say what was done.

Steps, in order (each one runs only when the mesh needs it):

1. weld    : merge vertices that coincide (within 1e-9 of the bounding-box diagonal)
2. degenerate : drop faces that use a vertex twice, and repeated faces (found as
                edges on more than two faces)
3. fragments  : drop loose components that are tiny next to the largest one
                (volume below ``min_fragment`` of it and area below 1 %)
4. winding    : make neighbouring faces agree, then every component face outward
5. holes      : close boundary loops that are small (perimeter up to
                ``max_hole`` of the diagonal, fan to the centroid) or flat (a planar
                cut such as an open base, capped by constrained Delaunay triangulation)
6. check      : the result must be closed (every edge on exactly two faces) with a
                positive volume; otherwise :class:`InputError` says what is left open.

Example
-------
>>> import trimesh
>>> from statue2model.geometry.repair import repair_mesh
>>> box = trimesh.creation.box()
>>> r = repair_mesh(box.vertices, box.faces[:-1])   # one triangle missing
>>> r.closed, r.log
(True, ('closed 1 hole (0 small, 1 flat)',))
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .topology import EdgeTopology, boundary_loops, edge_topology


@dataclass(frozen=True)
class RepairResult:
    """A repaired mesh and the record of what was changed.

    vertices : (n, 3) float, same units as the input
    faces    : (f, 3) int, outward winding
    log      : one human-readable line per change made
    closed   : always True (an open result raises instead)
    """

    vertices: np.ndarray
    faces: np.ndarray
    log: tuple[str, ...]
    closed: bool = True


def check_arrays(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Validate raw arrays: finite coordinates, valid indices, something to work with."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
        raise InputError("the mesh has no vertices")
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise InputError("the mesh has no triangle faces")
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        raise InputError(f"the mesh has {int(bad.sum())} vertices with NaN or infinite coordinates")
    f = f.astype(np.int64)
    if f.min() < 0 or f.max() >= len(v):
        raise InputError("the mesh has faces that point to vertices that do not exist")
    return v, f


def _group_keys(key: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first index of each distinct key, group id of every element), one stable radix sort."""
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    new_group = np.empty(len(key), dtype=bool)
    new_group[0] = True
    np.not_equal(sorted_key[1:], sorted_key[:-1], out=new_group[1:])
    group = np.empty(len(key), dtype=np.int64)
    group[order] = np.cumsum(new_group) - 1
    return order[new_group], group


def weld(vertices: np.ndarray, faces: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Merge vertices whose coordinates agree after rounding to ``tol``; keep first coordinates."""
    q = np.round((vertices - vertices.min(axis=0)) / tol).astype(np.int64)
    span = q.max(axis=0) + 1
    if np.prod(span.astype(float)) < 2**62:
        first, inverse = _group_keys((q[:, 0] * span[1] + q[:, 1]) * span[2] + q[:, 2])
    else:  # pragma: no cover - only for absurd coordinate ranges
        _, first, inverse = np.unique(q, axis=0, return_index=True, return_inverse=True)
        inverse = inverse.reshape(-1)
    merged = len(vertices) - len(first)
    if merged == 0:
        return vertices, faces, 0
    return vertices[first], inverse[faces], merged


def drop_degenerate(faces: np.ndarray) -> tuple[np.ndarray, int]:
    """Remove faces that use a vertex twice."""
    ok = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])
    return faces[ok], int((~ok).sum())


def drop_duplicates(faces: np.ndarray, n_vertices: int) -> tuple[np.ndarray, int]:
    """Remove repeated faces (the same three vertices in any order)."""
    s = np.sort(faces, axis=1)
    n = np.int64(n_vertices)
    if float(n_vertices) ** 3 < 2**62:
        keep, _ = _group_keys((s[:, 0] * n + s[:, 1]) * n + s[:, 2])
    else:  # pragma: no cover
        _, keep = np.unique(s, axis=0, return_index=True)
    return faces[np.sort(keep)], len(faces) - len(keep)


def _face_measures(vertices: np.ndarray, faces: np.ndarray, area: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
    """Signed tetrahedron volumes (against the bounding-box middle) and areas per face."""
    ref = 0.5 * (vertices.min(axis=0) + vertices.max(axis=0))
    cols = [np.ascontiguousarray(vertices[:, k] - ref[k]) for k in range(3)]
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = ([c[faces[:, j]] for c in cols] for j in range(3))
    vol = (ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)) / 6.0
    if not area:
        return vol, None
    ux, uy, uz, wx, wy, wz = bx - ax, by - ay, bz - az, cx - ax, cy - ay, cz - az
    nx, ny, nz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
    return vol, 0.5 * np.sqrt(nx * nx + ny * ny + nz * nz)


def _fix_winding(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    import trimesh  # only for inconsistent scans

    mesh = trimesh.Trimesh(vertices, faces, process=False)
    trimesh.repair.fix_winding(mesh)
    return np.asarray(mesh.faces, dtype=np.int64)


def _cap_planar(points: np.ndarray, loop: np.ndarray, flat_tol: float) -> np.ndarray | None:
    """Triangles (indices into ``loop``) capping a planar loop, or None if not planar/simple."""
    import shapely

    centre = points.mean(axis=0)
    _, s, vt = np.linalg.svd(points - centre, full_matrices=False)
    if s[-1] / np.sqrt(len(points)) > flat_tol:
        return None
    normal = vt[2]
    if np.abs(((points - centre) @ normal)).max() > flat_tol:
        return None
    uv = (points - centre) @ vt[:2].T
    poly = shapely.Polygon(uv)
    if not poly.is_valid or poly.area <= 0:
        return None
    tris = shapely.get_parts(shapely.constrained_delaunay_triangles(poly))
    lookup = {tuple(p): i for i, p in enumerate(uv.tolist())}
    loop_ccw = shapely.Polygon(uv).exterior.is_ccw
    out = []
    for t in tris:
        xy = shapely.get_coordinates(t)[:3]
        try:
            idx = [lookup[tuple(p)] for p in xy.tolist()]
        except KeyError:
            return None
        e1, e2 = xy[1] - xy[0], xy[2] - xy[0]
        area2 = e1[0] * e2[1] - e1[1] * e2[0]
        # the cap runs against the loop: opposite turning sense in the plane
        if (area2 > 0) == loop_ccw:
            idx = idx[::-1]
        out.append(idx)
    if abs(sum(shapely.area(tris)) - poly.area) > 1e-9 * max(poly.area, 1e-300):
        return None
    return np.array(out, dtype=np.int64)


def fill_holes(
    vertices: np.ndarray, faces: np.ndarray, topo: EdgeTopology, max_perimeter: float, flat_tol: float
) -> tuple[np.ndarray, np.ndarray, int, int, list[float]]:
    """Close the boundary loops that are small or planar. Returns new arrays, counts and
    the perimeters of the loops left open."""
    new_vertices = [vertices]
    new_faces = [faces]
    n_small = n_flat = 0
    left = []
    next_index = len(vertices)
    for loop in boundary_loops(topo.boundary_edges):
        pts = vertices[loop]
        perimeter = float(np.linalg.norm(pts - np.roll(pts, -1, axis=0), axis=1).sum())
        cap = _cap_planar(pts, loop, flat_tol) if len(loop) >= 3 else None
        if cap is not None:
            new_faces.append(loop[cap])
            n_flat += 1
        elif len(loop) >= 3 and perimeter <= max_perimeter:
            centre = next_index
            next_index += 1
            new_vertices.append(pts.mean(axis=0, keepdims=True))
            nxt = np.roll(loop, -1)
            new_faces.append(np.column_stack([nxt, loop, np.full(len(loop), centre)]))
            n_small += 1
        else:
            left.append(perimeter)
    return np.vstack(new_vertices), np.vstack(new_faces), n_small, n_flat, left


def repair_mesh(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    min_fragment: float = 1e-3,
    max_hole: float = 0.1,
) -> RepairResult:
    """Clean a raw scan into a closed volume (see the module docstring for the steps).

    vertices     : (n, 3) float, any length unit
    faces        : (f, 3) int
    min_fragment : loose parts with |volume| below this fraction of the largest part
                   (and area below 1 % of the total) are dropped
    max_hole     : non-planar holes with a perimeter up to this fraction of the
                   bounding-box diagonal are closed
    """
    v, f = check_arrays(vertices, faces)
    log: list[str] = []
    diag = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    if diag <= 0:
        raise InputError("all vertices of the mesh coincide: it has zero size")

    v, f, merged = weld(v, f, 1e-9 * diag)
    if merged:
        log.append(f"welded {merged} duplicate vertices")
    f, n_deg = drop_degenerate(f)
    if n_deg:
        log.append(f"dropped {n_deg} degenerate faces")
    if len(f) == 0:
        raise InputError("the mesh has no faces with three distinct vertices")

    topo = edge_topology(f, len(v))
    if topo.n_nonmanifold:  # repeated faces show up as edges on more than two faces
        f, n_dup = drop_duplicates(f, len(v))
        if n_dup:
            log.append(f"dropped {n_dup} duplicate faces")
            topo = edge_topology(f, len(v))
    if topo.n_components > 1:
        vol, area = _face_measures(v, f)
        comp_vol = np.abs(np.bincount(topo.face_component, weights=vol, minlength=topo.n_components))
        comp_area = np.bincount(topo.face_component, weights=area, minlength=topo.n_components)
        tiny = (comp_vol < min_fragment * comp_vol.max()) & (comp_area < 0.01 * comp_area.sum())
        if tiny.any() and not tiny.all():
            keep = ~tiny[topo.face_component]
            dropped_faces = int((~keep).sum())
            log.append(
                f"dropped {int(tiny.sum())} loose fragment(s) ({dropped_faces} faces, "
                f"{comp_vol[tiny].sum() / comp_vol.sum():.2%} of the volume)"
            )
            f = f[keep]
            used = np.zeros(len(v), dtype=bool)
            used[f.ravel()] = True
            remap = np.cumsum(used) - 1
            v, f = v[used], remap[f]
            topo = topo.keep_components(~tiny, remap)

    if topo.n_nonmanifold:
        raise InputError(
            f"the mesh has {topo.n_nonmanifold} non-manifold edges (shared by more than two faces): "
            "repair it in a mesh editor first"
        )
    if not topo.winding_consistent:
        f = _fix_winding(v, f)
        topo = edge_topology(f, len(v))
        log.append("made the face winding consistent")

    if len(topo.boundary_edges):
        v, f, n_small, n_flat, left = fill_holes(v, f, topo, max_hole * diag, 1e-6 * diag)
        if n_small or n_flat:
            log.append(f"closed {n_small + n_flat} hole{'s' if n_small + n_flat > 1 else ''} ({n_small} small, {n_flat} flat)")
        if left:
            raise InputError(
                f"the mesh is not a closed volume: {len(left)} hole(s) could not be closed "
                f"(largest perimeter {max(left):.4g} in file units, limit {max_hole * diag:.4g}); "
                "close them in a mesh editor"
            )
        topo = edge_topology(f, len(v))
    if not topo.is_closed:
        raise InputError(
            f"the mesh is not a closed volume: {len(topo.boundary_edges)} open and "
            f"{topo.n_nonmanifold} non-manifold edges remain after repair"
        )

    vol, _ = _face_measures(v, f, area=False)
    comp_vol = np.bincount(topo.face_component, weights=vol, minlength=topo.n_components)
    inverted = comp_vol < 0
    if inverted.any():
        flip = inverted[topo.face_component]
        f = f.copy()
        f[flip] = f[flip][:, ::-1]
        log.append(f"turned {int(inverted.sum())} inside-out component(s) outward")
        comp_vol = np.abs(comp_vol)
    total = float(comp_vol.sum())
    if not total > 1e-12 * diag**3:
        raise InputError(f"the mesh encloses no volume (volume {total:.3g} in file units cubed)")
    return RepairResult(vertices=v, faces=f, log=tuple(log))
