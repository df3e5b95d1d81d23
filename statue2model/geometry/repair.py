"""Turn a raw scan into a closed, consistently oriented volume, and say what was done.

Steps, in order (each one runs only when the mesh needs it), what a careful
MeshLab user would do by hand:

1. weld        : merge vertices that coincide (within 1e-9 of the bounding-box diagonal)
2. degenerate  : drop faces that use a vertex twice
3. repeated    : a triangle present twice with opposite winding is a zero-thickness
                 fin or double wall: both copies go; copies with the same winding
                 are kept once (found as edges on more than two faces)
4. pinches     : delete the faces on edges shared by more than two faces (the holes
                 this opens are closed in step 7); after step 7, split every vertex
                 where separate fans of faces still meet (two sheets touching at a
                 point) into one vertex per fan
5. fragments   : drop loose open or closed scraps that are tiny next to the largest
                 part (volume below ``min_fragment`` of it and area below 1 %)
6. winding     : make neighbouring faces agree
7. holes       : close boundary loops that are small (perimeter up to ``max_hole`` of
                 the diagonal, fan to the centroid) or flat (a planar cut such as an
                 open base, capped by constrained Delaunay triangulation). Holes that
                 share vertices (a bow tie, or the two holes left where two sheets met
                 along a deleted non-manifold edge) are walked apart into simple loops
                 (:func:`~statue2model.geometry.topology.hole_loops`), and a flat cap never
                 reuses an edge of the mesh or of another cap (it is cut at the edge's
                 midpoint instead): a fill adds no non-manifold edge
8. shells      : cavities kept (wound inward), overlapping or touching shells united,
                 loose pieces dropped or refused (:mod:`statue2model.geometry.shells`)
9. proof       : every edge on exactly two faces, neighbours wound alike, no
                 non-manifold vertex, positive volume; a repaired mesh is also
                 accepted by manifold3d as a 2-manifold. Otherwise InputError.

A repair that would change the body materially is refused, naming the defect, its
size and where it is: the fill of the holes may add or remove at most
``MAX_FILL_CHANGE`` of the volume (bounded by half the patch area times the
hole's depth out of its plane).

Example
-------
>>> import trimesh
>>> from statue2model.geometry.repair import repair_mesh
>>> box = trimesh.creation.box()
>>> r = repair_mesh(box.vertices, box.faces[:-1])   # one triangle missing
>>> r.closed, r.log
(True, ('closed 1 hole (0 small, 1 flat; largest perimeter 3.414)', 'checked: a closed 2-manifold, 12 faces (+1)'))
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .orient import face_area_vectors
from .shells import resolve_shells
from .topology import (EdgeTopology, edge_topology, hole_loops, nonmanifold_vertices, orient_faces,
                       split_nonmanifold_vertices)

MAX_FILL_CHANGE = 0.005
"""Largest share of the volume that closing holes may change (bound, see module doc)."""


@dataclass(frozen=True)
class RepairResult:
    """A repaired mesh and the record of what was changed.

    vertices : (n, 3) float, same units as the input
    faces    : (f, 3) int, outward winding
    log      : one human-readable line per change made
    closed   : always True (an open result raises instead)
    warnings : what the user should check (e.g. a large share of the surface rebuilt)
    """

    vertices: np.ndarray
    faces: np.ndarray
    log: tuple[str, ...]
    closed: bool = True
    warnings: tuple[str, ...] = ()


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
    else:  # fine tolerance on a large scan: sort the rows (lexsort is ~3x np.unique(axis=0))
        order = np.lexsort((q[:, 2], q[:, 1], q[:, 0]))
        sq = q[order]
        new = np.r_[True, np.any(sq[1:] != sq[:-1], axis=1)]
        first = order[new]
        inverse = np.empty(len(q), dtype=np.int64)
        inverse[order] = np.cumsum(new) - 1
    merged = len(vertices) - len(first)
    if merged == 0:
        return vertices, faces, 0
    return vertices[first], inverse[faces], merged


def drop_degenerate(faces: np.ndarray) -> tuple[np.ndarray, int]:
    """Remove faces that use a vertex twice."""
    ok = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])
    return faces[ok], int((~ok).sum())


def drop_duplicates(faces: np.ndarray, n_vertices: int) -> tuple[np.ndarray, int, int]:
    """Remove repeated faces (the same three vertices in any order).

    Copies wound the same way are kept once; a copy wound the other way cancels one
    (a zero-thickness fin or wall has no volume: both go). Returns the faces, the
    number of same-winding repeats dropped and the number of twin pairs removed.
    """
    s = np.sort(faces, axis=1)
    n = np.int64(n_vertices)
    if float(n_vertices) ** 3 < 2**62:
        _, group = _group_keys((s[:, 0] * n + s[:, 1]) * n + s[:, 2])
    else:  # pragma: no cover
        _, group = np.unique(s, axis=0, return_inverse=True)
        group = group.reshape(-1)
    # winding class: rotate the smallest index first; (min, p, q) is 'even' when p < q
    k = np.argmin(faces, axis=1)
    rows = np.arange(len(faces))
    even = faces[rows, (k + 1) % 3] < faces[rows, (k + 2) % 3]
    n_groups = int(group.max()) + 1
    n_even = np.bincount(group, weights=even, minlength=n_groups).astype(np.int64)
    n_odd = np.bincount(group, minlength=n_groups) - n_even
    twins = np.minimum(n_even, n_odd)
    left_even = n_even - twins
    left_odd = n_odd - twins
    # keep the first face of each group in the surviving winding class, if any survives
    want = np.where(left_even > 0, 1, np.where(left_odd > 0, 0, -1))[group]
    cand = want == even
    first = np.full(n_groups, -1)
    idx = np.flatnonzero(cand)
    first[group[idx[::-1]]] = idx[::-1]
    keep = np.zeros(len(faces), dtype=bool)
    keep[first[first >= 0]] = True
    n_twin = int(twins.sum())
    n_repeat = len(faces) - int(keep.sum()) - 2 * n_twin
    return faces[keep], n_repeat, n_twin


def delete_nonmanifold_edges(faces: np.ndarray, n_vertices: int, topo: EdgeTopology) -> tuple[np.ndarray, int]:
    """Delete the faces on edges shared by more than two faces. Returns the faces left
    and the number deleted (the holes they leave are closed later)."""
    if not topo.n_nonmanifold:
        return faces, 0
    def key(e):
        return np.minimum(e[:, 0], e[:, 1]) * np.int64(n_vertices) + np.maximum(e[:, 0], e[:, 1])
    bad = key(topo.nonmanifold_edges)
    on_bad = np.zeros(len(faces), dtype=bool)
    for a, b in ((0, 1), (1, 2), (2, 0)):
        on_bad |= np.isin(key(faces[:, [a, b]]), bad)
    return faces[~on_bad], int(on_bad.sum())


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
    """Faces flipped so that neighbours agree (:func:`~statue2model.geometry.topology.orient_faces`);
    InputError for a surface that cannot be oriented."""
    out, _ = orient_faces(faces, len(vertices))
    left = edge_topology(out, len(vertices)).inconsistent_face
    if len(left):
        raise InputError(f"the surface cannot be oriented (it is one-sided, like a Moebius strip, around "
                         f"{len(left)} edges): repair the scan in a mesh editor")
    return out


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


@dataclass(frozen=True)
class Hole:
    """One boundary loop: perimeter, patch area, depth out of its best plane (file
    units), centre (3,), and how it was closed ('flat', 'fan' or 'open')."""

    perimeter: float
    area: float
    depth: float
    centre: np.ndarray
    how: str

    @property
    def change_bound(self) -> float:
        """Bound on the volume the patch may add or remove, file units cubed."""
        return 0.5 * self.area * self.depth

    def where(self) -> str:
        return "(" + ", ".join(f"{x:.4g}" for x in self.centre) + ")"


def _edge_keys(tris: np.ndarray, n: int) -> np.ndarray:
    """(3 t,) undirected key lo * n + hi of every edge of the triangles (t, 3)."""
    e = tris[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    return np.minimum(e[:, 0], e[:, 1]) * np.int64(n) + np.maximum(e[:, 0], e[:, 1])


def _split_edges(patch: np.ndarray, keys: list[int], n: int, first_new: int) -> np.ndarray:
    """``patch`` (t, 3) with every edge in ``keys`` (undirected, lo * n + hi) cut at a new
    vertex (indices first_new, first_new + 1, ... in the order of ``keys``): each triangle
    p -> q -> r on such an edge p-q becomes (p, m, r) and (m, q, r). Same surface, same
    winding; the edge p-q is no longer used."""
    tris = [list(t) for t in patch.tolist()]
    for i, key in enumerate(keys):
        a, b = divmod(int(key), n)
        m = first_new + i
        out = []
        for t in tris:
            if a in t and b in t:
                k = t.index(a)
                p, q, r = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]) if t[(k + 1) % 3] == b else \
                    (t[(k + 2) % 3], t[k], t[(k + 1) % 3])
                out += [[p, m, r], [m, q, r]]
            else:
                out.append(t)
        tris = out
    return np.array(tris, dtype=np.int64)


def fill_holes(
    vertices: np.ndarray, faces: np.ndarray, topo: EdgeTopology, max_perimeter: float, flat_tol: float
) -> tuple[np.ndarray, np.ndarray, list[Hole]]:
    """Close the boundary loops that are small or planar. Returns new arrays and one
    :class:`Hole` per loop (``how == 'open'`` for those left open).

    Every loop is simple (:func:`~statue2model.geometry.topology.hole_loops`), so a fan to
    a new centre point only adds the loop's own boundary edges (each then on two faces)
    and spokes to the new point. A flat cap also adds diagonals between loop vertices: a
    diagonal that is already an edge of the mesh or of another cap (two holes sharing
    two vertices, e.g. where the faces around a non-manifold edge were deleted) would be
    a non-manifold edge, so the cap is cut there instead, at the diagonal's midpoint (the
    same flat surface, another triangulation)."""
    n = len(vertices)
    new_vertices = [vertices]
    new_faces = [faces]
    holes = []
    next_index = n
    caps: list[tuple[int, np.ndarray]] = []         # (position in new_faces, loop) of caps with diagonals
    for loop in hole_loops(vertices, faces, topo):
        pts = vertices[loop]
        perimeter = float(np.linalg.norm(pts - np.roll(pts, -1, axis=0), axis=1).sum())
        centre = pts.mean(axis=0)
        depth = 0.0
        if len(loop) >= 3:
            _, sv, vt = np.linalg.svd(pts - centre, full_matrices=False)
            depth = float(np.abs((pts - centre) @ vt[2]).max())
        cap = _cap_planar(pts, loop, flat_tol) if len(loop) >= 3 else None
        if cap is not None:
            patch = loop[cap]
            if len(loop) > 3:
                caps.append((len(new_faces), loop))
            new_faces.append(patch)
            how = "flat"
            depth = 0.0
            area = float(np.linalg.norm(face_area_vectors(vertices, patch).sum(axis=0)))
        elif len(loop) >= 3 and perimeter <= max_perimeter:
            new_vertices.append(centre[None, :])
            nxt = np.roll(loop, -1)
            fan = np.column_stack([nxt, loop, np.full(len(loop), next_index)])
            next_index += 1
            new_faces.append(fan)
            a, b = pts[np.r_[1:len(pts), 0]] - centre, pts - centre
            area = float(0.5 * np.linalg.norm(np.cross(a, b), axis=1).sum())
            how = "fan"
        else:
            area, how = float("nan"), "open"
        holes.append(Hole(perimeter, area, depth, centre, how))
    if caps:
        mark = np.zeros(n, dtype=bool)
        mark[np.concatenate([loop for _, loop in caps])] = True
        existing = np.unique(_edge_keys(faces[mark[faces].any(axis=1)], n))
        taken: set[int] = set()
        for pos, loop in caps:
            patch = new_faces[pos]
            nxt = np.roll(loop, -1)
            rim = set((np.minimum(loop, nxt) * np.int64(n) + np.maximum(loop, nxt)).tolist())
            inner = [k for k in np.unique(_edge_keys(patch, n)).tolist() if k not in rim]
            hit = np.isin(inner, existing)
            clash = [k for k, h in zip(inner, hit) if h or k in taken]
            taken.update(k for k in inner if k not in clash)
            if clash:
                lo, hi = np.divmod(np.array(clash), n)
                new_vertices.append(0.5 * (vertices[lo] + vertices[hi]))
                new_faces[pos] = _split_edges(patch, clash, n, next_index)
                next_index += len(clash)
    return np.vstack(new_vertices), np.vstack(new_faces), holes


def _compact(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop the vertices no face uses."""
    used = np.zeros(len(v), dtype=bool)
    used[f.ravel()] = True
    if used.all():
        return v, f
    remap = np.cumsum(used) - 1
    return v[used], remap[f]


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
    warnings: list[str] = []
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
    n_in = len(f)

    topo = edge_topology(f, len(v))
    repaired = False
    n_deleted = 0
    if topo.n_nonmanifold:  # repeated faces show up as edges on more than two faces
        f, n_dup, n_twin = drop_duplicates(f, len(v))
        if n_dup:
            log.append(f"dropped {n_dup} duplicate faces")
        if n_twin:
            log.append(f"removed {n_twin} twin face pair(s) (one triangle twice, wound opposite ways: "
                       "a zero-thickness fin or wall)")
        if n_dup or n_twin:
            topo = edge_topology(f, len(v))
    if topo.n_nonmanifold:
        n_nme = topo.n_nonmanifold
        f, n_deleted = delete_nonmanifold_edges(f, len(v), topo)
        log.append(f"deleted {n_deleted} faces on {n_nme} non-manifold edge(s)")
        repaired = True
        if len(f) == 0:
            raise InputError("the mesh has no faces left after deleting those around its non-manifold "
                             "edges and vertices: it is not a surface")
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

    if not topo.winding_consistent:
        f = _fix_winding(v, f)
        topo = edge_topology(f, len(v))
        log.append("made the face winding consistent")

    holes: list[Hole] = []
    if len(topo.boundary_edges):
        v, f, holes = fill_holes(v, f, topo, max_hole * diag, 1e-6 * diag)
        left = [h for h in holes if h.how == "open"]
        if left:
            big = max(left, key=lambda h: h.perimeter)
            raise InputError(
                f"the mesh is not a closed volume: {len(left)} hole(s) could not be closed (the largest has a "
                f"perimeter of {big.perimeter:.4g} file units and is centred at {big.where()}; the limit for "
                f"a curved hole is {max_hole * diag:.4g})"
                + (f", after deleting {n_deleted} faces around non-manifold edges and vertices" if n_deleted else "")
                + "; close them in a mesh editor"
            )
        n_flat = sum(h.how == "flat" for h in holes)
        n_small = len(holes) - n_flat
        log.append(f"closed {len(holes)} hole{'s' if len(holes) > 1 else ''} ({n_small} small, {n_flat} flat; "
                   f"largest perimeter {max(h.perimeter for h in holes):.4g})")
        topo = edge_topology(f, len(v))
        repaired = True
    if not topo.is_closed:
        raise InputError(
            f"the mesh is not a closed volume: {len(topo.boundary_edges)} open and "
            f"{topo.n_nonmanifold} non-manifold edges remain after repair"
        )
    if not topo.winding_consistent:
        f = _fix_winding(v, f)
        topo = edge_topology(f, len(v))
        log.append("made the face winding consistent")
    labels = topo.face_component
    if repaired:
        v, f, n_split = split_nonmanifold_vertices(v, f)
        if n_split:
            log.append(f"split {n_split} non-manifold vertex(es) where separate sheets meet")
            labels = None                      # splitting may part components

    shells = resolve_shells(v, f, labels=labels)
    v, f = shells.vertices, shells.faces
    log.extend(shells.log)
    v, f = _compact(v, f)
    total = shells.volume
    if not total > 1e-12 * diag**3:
        raise InputError(f"the mesh encloses no volume (volume {total:.3g} in file units cubed)")
    fans = [h for h in holes if h.how == "fan"]
    if fans:
        change = sum(h.change_bound for h in fans)
        if change > MAX_FILL_CHANGE * total:
            big = max(fans, key=lambda h: h.change_bound)
            raise InputError(
                f"closing the scan's {len(fans)} curved hole(s) could change its volume by up to "
                f"{change / total:.2%} (limit {MAX_FILL_CHANGE:.1%}): the largest has a perimeter of "
                f"{big.perimeter:.4g} and an area of {big.area:.4g} file units, is {big.depth:.3g} deep and "
                f"centred at {big.where()}; close it in a mesh editor"
            )
        surface = float(_face_measures(v, f)[1].sum())
        patched = sum(h.area for h in fans)
        if patched > 0.01 * surface:
            warnings.append(f"repair rebuilt {patched / surface:.1%} of the surface (curved holes closed by "
                            "fans): check the scan")
    if repaired or shells.several:
        _prove_closed(v, f)
        log.append(f"checked: a closed 2-manifold, {len(f)} faces"
                   + (f" ({len(f) - n_in:+d})" if len(f) != n_in else ""))
    return RepairResult(vertices=v, faces=f, log=tuple(log), warnings=tuple(warnings))


def _prove_closed(v: np.ndarray, f: np.ndarray) -> None:
    """Raise unless the mesh is closed, consistently wound, vertex-manifold and accepted
    by manifold3d (an independent check of the same facts)."""
    topo = edge_topology(f, len(v))
    nmv = nonmanifold_vertices(f, len(v))
    problems = []
    if len(topo.boundary_edges):
        problems.append(f"{len(topo.boundary_edges)} open edges")
    if topo.n_nonmanifold:
        problems.append(f"{topo.n_nonmanifold} non-manifold edges")
    if len(nmv):
        problems.append(f"{len(nmv)} non-manifold vertices")
    if not topo.winding_consistent:
        problems.append(f"{len(topo.inconsistent_face)} edges wound inconsistently")
    if not problems:
        import manifold3d as m3d

        status = m3d.Manifold(m3d.Mesh64(vert_properties=np.ascontiguousarray(v, dtype=np.float64),
                                         tri_verts=f.astype(np.uint32))).status()
        if status != m3d.Error.NoError:
            problems.append(f"manifold3d rejects it ({status})")
    if problems:
        raise InputError(f"the repaired mesh is not a closed volume ({', '.join(problems)}): "
                         "repair the scan in a mesh editor")
