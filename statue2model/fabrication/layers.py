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

How a section is built (and why it cannot silently lose area). The faces are
wound outward, so each triangle-plane crossing is a *directed* segment (solid on
its left), and the solid at the plane is where the winding number w of those
segments is non-zero: the robust definition when the surface folds through
itself or two closed shells overlap (a scan's double walls, a Thingiverse OBJ of
several shells), where even-odd filling would cut holes and polygonising
segments that cross without a node returns nothing at all.

1. Segments are chained into closed loops by the mesh edges they cross (each
   crossed edge is where one segment ends and the next begins; on a mesh that
   is not closed, by their end points merged within MERGE), and the loops are
   filled with the non-zero rule (manifold3d's CrossSection, i.e. Clipper2).
2. Independent check, with no polygon built: the signed shoelace sum of the
   directed segments equals the integral of w over the plane; it equals the
   filled area wherever w is 0 or 1. It must agree within
   AREA_RTOL * area + AREA_ATOL.
3. When it does not (overlapping shells, w = 2; inside-out folds, w < 0; or a
   fault of step 1), the segments are noded and polygonised (shapely) and the
   winding number of every face of that arrangement is counted: the faces with
   w != 0 must give the same area as step 1 (then step 1 stands, and the area
   where w >= 2 or w < 0 is recorded); if they do not, the arrangement is used
   when its sum of w * area matches the shoelace sum, and otherwise the layer
   is refused (InputError) rather than written wrong.

A surface that is open at a plane (section ends that do not meet within MERGE)
has no inside there: it is refused too (a Body is always closed).

:class:`SectionCheck` records per plane what was done; ``slicing`` turns it into
warnings.

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

Two boxes crossing each other, not united (overlapping shells): the section is
their union, and the check records where the winding number is 2.

>>> a, b = trimesh.creation.box((0.2, 0.1, 0.2)), trimesh.creation.box((0.1, 0.2, 0.2))
>>> v, f = np.vstack([a.vertices, b.vertices]), np.vstack([a.faces, b.faces + len(a.vertices)])
>>> (sec,), (check,) = plane_sections(v, f, [0.05])
>>> round(sec.area, 6), round(check.winding_area, 6), round(check.overlap, 6), check.method
(0.03, 0.04, 0.01, 'loops')
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from ..errors import InputError
from . import robust

POLICIES = ("mid", "envelope", "core")
SLAB_PLANES = 5
"""Planes through a board for the envelope and core policies (faces included)."""
AREA_RTOL = 1e-6
AREA_ATOL = 1e-8
"""A section's filled area and its shoelace (winding-integral) area agree when they
differ by at most AREA_RTOL * area + AREA_ATOL (m^2; 0.01 mm^2). Both are sums over
the same points (Clipper2 rounds to 1e-8 mm), so anything larger is geometry: w = 2
(overlapping shells) or w < 0 (inside-out folds), or a fault of the loops."""
MERGE = 1e-6
"""Crossing points closer than this (m) are one point when segments must be chained
by their ends (a mesh that is not closed: duplicated seams, cracks)."""
CLIPPER_SCALE = 1000.0
"""Clipper2 in manifold3d rounds to 1e-8 of a unit: it works in mm (1e-11 m)."""


@dataclass(frozen=True)
class SectionCheck:
    """How one plane's section was built and checked (lengths m, areas m^2).

    z            : height of the plane
    segments     : triangle-plane crossings
    area         : area of the outline returned
    winding_area : signed shoelace sum of the directed segments = integral of the
                   winding number w over the plane (no polygon built)
    method       : 'loops' (chained and filled, w != 0), 'arrangement' (noded, w
                   counted per face: the fallback) or 'none' (nothing crosses the plane)
    overlap      : area where w >= 2 (overlapping shells), known when the arrangement ran
    inverted     : area where w < 0 (inside-out folds), idem
    merged       : crossing points merged across gaps up to MERGE (0 on a closed mesh)
    note         : why the arrangement ran, or ''
    """

    z: float
    segments: int
    area: float
    winding_area: float
    method: str
    overlap: float = 0.0
    inverted: float = 0.0
    merged: int = 0
    note: str = ""

    @property
    def repaired(self) -> bool:
        """The loops were wrong or could not be built; the arrangement gave the outline."""
        return self.method == "arrangement"

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


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
    return layer_sections_checked(vertices, faces, bottoms, board, policy, tolerance)[0]


def layer_sections_checked(vertices, faces, bottoms, board: float, policy: str = "mid",
                           tolerance: float = 0.0) -> tuple[list[MultiPolygon], list[tuple[SectionCheck, ...]]]:
    """:func:`layer_sections` and, per board, the :class:`SectionCheck` of each plane
    it was built from (one for 'mid', SLAB_PLANES for 'envelope' and 'core')."""
    bottoms = np.asarray(bottoms, dtype=float)
    if policy == "mid":
        out, checks = plane_sections(vertices, faces, bottoms + 0.5 * board)
        per_layer = [(c,) for c in checks]
    elif policy in ("envelope", "core"):
        # planes just inside the board faces: a face exactly on the base plane has no section
        t = np.linspace(1e-4, 1 - 1e-4, SLAB_PLANES)
        top = float(np.asarray(vertices)[:, 2].max())
        z = np.minimum(bottoms[:, None] + board * t[None, :], top - 1e-6 * board)
        flat, flat_checks = plane_sections(vertices, faces, z.ravel())
        out, per_layer = [], []
        for k in range(len(bottoms)):
            slab = [s for s in flat[k * SLAB_PLANES:(k + 1) * SLAB_PLANES]]
            per_layer.append(tuple(flat_checks[k * SLAB_PLANES:(k + 1) * SLAB_PLANES]))
            where = _where(k, bottoms[k] + 0.5 * board)
            if policy == "envelope":
                geom = robust.union_all(slab, what=f"the union of the sections through {where}")
            else:
                geom = slab[0]
                for s in slab[1:]:
                    geom = robust.intersection(geom, s, what=f"the common part of the sections through {where}")
            out.append(_as_multipolygon(geom))
    else:
        raise InputError(f"section policy {policy!r} is not one of {', '.join(POLICIES)}")
    if tolerance > 0:
        out = [_as_multipolygon(robust.simplify(s, tolerance, what=f"simplifying the outline of "
                                                f"{_where(k, bottoms[k] + 0.5 * board)}"))
               for k, s in enumerate(out)]
    return out, per_layer


def _where(k: int, z: float) -> str:
    """'layer 12 (z = 109.3 mm)': 0-based index k, mid-board height z in m."""
    return f"layer {k + 1} (z = {z * 1000:.1f} mm)"


def _as_multipolygon(geom) -> MultiPolygon:
    """A valid MultiPolygon of the areal parts of ``geom`` (robust.as_multipolygon:
    a collection that make_valid returns with a MultiPolygon inside keeps it)."""
    return robust.as_multipolygon(geom)


def _segments(vertices: np.ndarray, faces: np.ndarray, z: float,
              cand: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Directed segments where faces ``cand`` cross the plane at height z.

    Returns (m, 2, 2) segments, solid on their left (from the face's edge that
    goes down through the plane to the one that goes up: outward winding), and
    (m,) keys of the mesh edges they start and end on. A vertex on the plane
    counts as above it; every crossing point is interpolated from the
    lower-numbered end of its edge, so neighbouring faces share it exactly."""
    f = faces[cand]
    d = vertices[f, 2] - z                      # (m, 3)
    above = d >= 0
    n_v = np.int64(len(vertices))
    pts = np.zeros((len(f), 2, 2))
    keys = np.zeros((len(f), 2), dtype=np.int64)
    hits = np.zeros(len(f), dtype=int)
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
        end = above[idx, e1].astype(int)        # going up through the plane: the segment's end
        pts[idx, end] = p
        keys[idx, end] = lo * n_v + hi
        hits[idx] += 1
    ok = hits == 2
    return pts[ok], keys[ok, 0], keys[ok, 1]


def _shoelace(segs: np.ndarray) -> float:
    """Signed area enclosed by directed segments (closed chains): the integral of w."""
    x0, y0 = segs[:, 0, 0], segs[:, 0, 1]
    x1, y1 = segs[:, 1, 0], segs[:, 1, 1]
    return float(0.5 * np.sum(x0 * y1 - x1 * y0))


def _agree(a: float, b: float) -> bool:
    return abs(a - b) <= AREA_RTOL * max(abs(a), abs(b)) + AREA_ATOL


def _successors(start: np.ndarray, end: np.ndarray) -> np.ndarray | None:
    """next[i]: a segment starting where segment i ends, each used once (an Euler
    decomposition into closed loops); None if some point has more segments in than out."""
    os_ = np.argsort(start, kind="stable")
    oe = np.argsort(end, kind="stable")
    if not np.array_equal(start[os_], end[oe]):
        return None
    nxt = np.empty(len(start), dtype=np.int64)
    nxt[oe] = os_
    return nxt


def _cycles(nxt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The cycles of the permutation ``nxt``: (order, starts) such that
    order[starts[i]:starts[i + 1]] is cycle i in sequence. Pointer jumping:
    O(n log n) array operations, no Python loop over the segments."""
    n = len(nxt)
    rounds = max(1, int(n).bit_length())
    idx = np.arange(n)
    rep, p = idx.copy(), nxt
    for _ in range(rounds):                     # smallest index of each cycle
        rep = np.minimum(rep, rep[p])
        p = p[p]
    prv = np.empty(n, dtype=np.int64)
    prv[nxt] = idx
    root = rep == idx
    dist = (~root).astype(np.int64)
    q = np.where(root, idx, prv)
    for _ in range(rounds):                     # steps from the cycle's first segment
        dist = dist + dist[q]
        q = q[q]
    order = np.lexsort((dist, rep))
    cut = np.flatnonzero(np.diff(rep[order])) + 1
    return order, np.concatenate([[0], cut, [n]])


def _from_cross_section(cs, scale: float) -> MultiPolygon:
    polys = []
    for comp in cs.decompose():
        rings = [np.asarray(r, dtype=float) * scale for r in comp.to_polygons()]
        rings = [r for r in rings if len(r) >= 3]
        if not rings:
            continue
        areas = [_ring_area(r) for r in rings]
        i = int(np.argmax(areas))
        polys.append(Polygon(rings[i], [r for j, r in enumerate(rings) if j != i]))
    out = MultiPolygon(polys)
    return out if out.is_valid else _as_multipolygon(out)


def _ring_area(r: np.ndarray) -> float:
    x, y = r[:, 0], r[:, 1]
    return float(0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)))


def _fill_loops(segs: np.ndarray, nxt: np.ndarray) -> MultiPolygon:
    """Chain the segments into loops and fill them by the non-zero winding rule."""
    import manifold3d as m3d

    order, starts = _cycles(nxt)
    pts = segs[order, 0] * CLIPPER_SCALE
    loops = [pts[a:b] for a, b in zip(starts[:-1], starts[1:]) if b - a >= 3]
    if not loops:
        return MultiPolygon()
    return _from_cross_section(m3d.CrossSection(loops, m3d.FillRule.NonZero), 1.0 / CLIPPER_SCALE)


def _merge_ends(segs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """End points closer than MERGE made one: (segments moved onto the merged
    points, start and end labels, number of points moved)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pts = segs.reshape(-1, 2)
    pairs = cKDTree(pts).query_pairs(MERGE, output_type="ndarray")
    n = len(pts)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    _, first = np.unique(label, return_index=True)
    snapped = pts[first[label]]
    moved = int(np.count_nonzero(np.any(snapped != pts, axis=1)))
    label = label.reshape(-1, 2)
    return snapped.reshape(-1, 2, 2), label[:, 0].astype(np.int64), label[:, 1].astype(np.int64), moved


def winding_numbers(points: np.ndarray, segs: np.ndarray) -> np.ndarray:
    """Winding number of directed segments (m, 2, 2) about each point (q, 2)
    (+1 inside a counter-clockwise loop)."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    x0, y0 = segs[:, 0, 0], segs[:, 0, 1]
    x1, y1 = segs[:, 1, 0], segs[:, 1, 1]
    out = np.zeros(len(points), dtype=np.int64)
    chunk = max(1, 2_000_000 // max(1, len(segs)))
    for i in range(0, len(points), chunk):
        qx = points[i:i + chunk, 0:1]
        qy = points[i:i + chunk, 1:2]
        left = (x1 - x0) * (qy - y0) - (qx - x0) * (y1 - y0)
        up = (y0 <= qy) & (qy < y1) & (left > 0)
        down = (y1 <= qy) & (qy < y0) & (left < 0)
        out[i:i + chunk] = up.sum(axis=1) - down.sum(axis=1)
    return out


def _arrangement(segs: np.ndarray, what: str = "the noded section") -> tuple[MultiPolygon, float, float, float]:
    """Node the segments, polygonise, and count each face's winding number:
    (faces with w != 0, sum of w * area, area with w >= 2, area with w < 0).
    ``what`` names the section in a robust.GeometryError."""
    segs = segs[np.any(segs[:, 0] != segs[:, 1], axis=1)]
    if len(segs) == 0:
        return MultiPolygon(), 0.0, 0.0, 0.0
    noded = robust.safe_op(shapely.node, shapely.multilinestrings(shapely.linestrings(segs)),
                           what=f"noding the segments of {what}")
    faces = shapely.get_parts(robust.safe_op(shapely.polygonize, shapely.get_parts(noded),
                                             what=f"polygonising {what}"))
    faces = faces[shapely.area(faces) > 0]
    if len(faces) == 0:
        return MultiPolygon(), 0.0, 0.0, 0.0
    area = shapely.area(faces)
    w = winding_numbers(shapely.get_coordinates(shapely.point_on_surface(faces)), segs)
    geom = (_as_multipolygon(robust.union_all(faces[w != 0], what=f"joining the faces of {what}"))
            if np.any(w != 0) else MultiPolygon())
    return geom, float(np.sum(w * area)), float(area[w >= 2].sum()), float(area[w < 0].sum())


def section_at(vertices: np.ndarray, faces: np.ndarray, z: float,
               cand: np.ndarray | None = None) -> tuple[MultiPolygon, SectionCheck]:
    """The section of a closed mesh (m) at height z and how it was checked (see
    the module docstring). ``cand``: indices of the faces that may cross z."""
    if cand is None:
        cand = np.arange(len(faces))
    segs, start, end = _segments(vertices, faces, z, cand)
    if len(segs) == 0:
        return MultiPolygon(), SectionCheck(float(z), 0, 0.0, 0.0, "none")
    origin = segs.reshape(-1, 2).mean(axis=0)   # shoelace and Clipper near the origin
    segs = segs - origin
    merged = 0
    nxt = _successors(start, end)
    if nxt is None:                             # not a closed manifold here: chain by the points
        segs, start, end, merged = _merge_ends(segs)
        nxt = _successors(start, end)
    if nxt is None:
        ends = np.unique(np.concatenate([start, end]), return_counts=True)[0]
        unmatched = int(np.count_nonzero(np.bincount(np.searchsorted(ends, start), minlength=len(ends))
                                         != np.bincount(np.searchsorted(ends, end), minlength=len(ends))))
        raise InputError(f"the surface is open at z = {z * 1000:.2f} mm: {unmatched} end(s) of its section do not "
                         f"meet within {MERGE * 1e6:g} um, so what is inside is undefined; close the mesh")
    a_w = _shoelace(segs)
    loops = _fill_loops(segs, nxt)
    if _agree(loops.area, a_w):
        check = SectionCheck(float(z), len(segs), float(loops.area), a_w, "loops", merged=merged)
        return _moved(loops, origin), check
    note = f"filled loops {loops.area * 1e6:.2f} mm^2 against a winding integral of {a_w * 1e6:.2f} mm^2"
    arr, w_sum, overlap, inverted = _arrangement(segs, f"the section at z = {z * 1000:.2f} mm")
    if _agree(loops.area, arr.area):
        geom, method = loops, "loops"           # the arrangement confirms the loops
    elif _agree(w_sum, a_w):
        geom, method = arr, "arrangement"       # the loops were wrong: repaired
    else:
        raise InputError(
            f"the section at z = {z * 1000:.2f} mm cannot be built reliably: filled loops {loops.area * 1e6:.1f} "
            f"mm^2, noded arrangement {arr.area * 1e6:.1f} mm^2 (sum of w * area {w_sum * 1e6:.1f} mm^2), "
            f"winding integral {a_w * 1e6:.1f} mm^2; repair the scan's surface near that height")
    check = SectionCheck(float(z), len(segs), float(geom.area), a_w, method, overlap=overlap, inverted=inverted,
                         merged=merged, note=note)
    return _moved(geom, origin), check


def _moved(geom: MultiPolygon, origin: np.ndarray) -> MultiPolygon:
    if geom.is_empty:
        return geom
    return shapely.transform(geom, lambda c: c + origin)


def plane_sections(vertices, faces, heights) -> tuple[list[MultiPolygon], list[SectionCheck]]:
    """:func:`sections` and the :class:`SectionCheck` of each plane."""
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    fz = vertices[faces, 2]
    zmin, zmax = fz.min(axis=1), fz.max(axis=1)
    order = np.argsort(zmin)
    zmin_sorted = zmin[order]
    out, checks = [], []
    for z in np.asarray(heights, dtype=float):
        reach = order[: np.searchsorted(zmin_sorted, z, side="right")]
        cand = reach[zmax[reach] >= z]
        geom, check = section_at(vertices, faces, float(z), cand)
        out.append(geom)
        checks.append(check)
    return out, checks


def sections(vertices, faces, heights) -> list[MultiPolygon]:
    """The cross-section of a closed mesh (m) at each height (m), in plan (x, y):
    where the winding number of the outward-wound surface is non-zero."""
    return plane_sections(vertices, faces, heights)[0]
