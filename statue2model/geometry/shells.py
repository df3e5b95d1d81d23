"""The closed shells of a repaired scan: the body, its cavities, pieces joined to it, loose pieces.

A scan often holds more than one closed shell: a cavity (a shell inside the body,
e.g. a hollow cast), parts modelled separately that overlap or touch the body (a
sword through a hand, a plinth stood under a figure), and pieces that do not
touch the body at all (a floating scrap, a second object in the same file). A
statue is analysed as one rigid body, so:

* nesting depth (how many other shells contain a shell, from the generalised
  winding number) decides orientation: even depth is solid (wound outward), odd
  depth is a cavity (wound inward);
* the outermost solid with the largest volume is the body; every other solid whose
  bounding box meets the body's is united with it (manifold3d), so overlapping
  volume is counted once;
* what still does not touch the body is a loose piece: dropped with a count when
  all of them together hold at most ``max_loose`` of the body's volume, refused
  otherwise (a statue cannot be two bodies).

Example
-------
>>> import numpy as np, trimesh
>>> a = trimesh.creation.box((1, 1, 1))
>>> b = trimesh.creation.box((1, 1, 1)); _ = b.apply_translation((0.5, 0, 0))  # overlaps a
>>> m = trimesh.util.concatenate([a, b])
>>> res = resolve_shells(m.vertices, m.faces)
>>> float(round(trimesh.Trimesh(res.vertices, res.faces).volume, 9)), res.log
(1.5, ('united 2 overlapping or touching shells into one body (overlap 0.5 in file units cubed)',))
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .topology import edge_topology

MAX_LOOSE = 0.005
"""Loose pieces (not touching the body) holding up to this fraction of the body's
volume together are dropped; more is refused."""


def winding_number(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Generalised winding number of the closed, outward-wound surface (vertices (n, 3),
    faces (f, 3)) at ``points`` (k, 3): 1 inside, 0 outside, 1/2 on the surface.
    Sum of the solid angles of the triangles (Van Oosterom and Strackee, 1983).

    >>> import trimesh
    >>> box = trimesh.creation.box()
    >>> winding_number(box.vertices, box.faces, np.array([[0, 0, 0.1], [2, 0, 0]])).round(12).tolist()
    [1.0, 0.0]
    """
    out = np.empty(len(points))
    tri = np.asarray(vertices, dtype=float)[np.asarray(faces)]
    for i, p in enumerate(np.asarray(points, dtype=float)):
        a, b, c = tri[:, 0] - p, tri[:, 1] - p, tri[:, 2] - p
        la, lb, lc = (np.sqrt(np.einsum("ij,ij->i", x, x)) for x in (a, b, c))
        num = np.einsum("ij,ij->i", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la
               + np.einsum("ij,ij->i", c, a) * lb)
        out[i] = np.arctan2(num, den).sum() / (2 * np.pi)
    return out


@dataclass(frozen=True)
class ShellResult:
    """vertices (n, 3), faces (f, 3) outward (cavities inward); log: one line per change;
    several: the mesh held more than one shell; volume: the body's, in file units cubed."""

    vertices: np.ndarray
    faces: np.ndarray
    log: tuple[str, ...]
    several: bool = False
    volume: float = float("nan")


def _signed_volumes(v, f, labels, n):
    ref = 0.5 * (v.min(axis=0) + v.max(axis=0))
    a, b, c = (v[f[:, j]] - ref for j in range(3))
    vol = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0
    return np.bincount(labels, weights=vol, minlength=n)


def _where(lo, hi) -> str:
    centre = 0.5 * (lo + hi)
    return "(" + ", ".join(f"{x:.4g}" for x in centre) + ")"


def resolve_shells(vertices: np.ndarray, faces: np.ndarray, *, max_loose: float = MAX_LOOSE,
                   labels: np.ndarray | None = None) -> ShellResult:
    """One rigid body from a closed, consistently wound mesh with one or more shells
    (see the module docstring). Raises InputError when loose pieces are too large.
    ``labels``: the (f,) connected-component label of each face, when known."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    if labels is None:
        labels = edge_topology(f, len(v)).face_component
    n = int(labels.max()) + 1
    vol = _signed_volumes(v, f, labels, n)
    if n == 1:
        if vol[0] < 0:
            return ShellResult(v, f[:, ::-1].copy(), ("turned 1 inside-out component(s) outward",), volume=-vol[0])
        return ShellResult(v, f, (), volume=vol[0])
    log: list[str] = []
    # every shell outward first
    flip = vol < 0
    if flip.any():
        f = f.copy()
        f[flip[labels]] = f[flip[labels]][:, ::-1]
    size = np.abs(vol)
    lo = np.full((n, 3), np.inf)
    hi = np.full((n, 3), -np.inf)
    fv = v[f]
    np.minimum.at(lo, labels, fv.min(axis=1))
    np.maximum.at(hi, labels, fv.max(axis=1))
    first_face = np.full(n, -1)
    first_face[labels[::-1]] = np.arange(len(f))[::-1]
    depth = np.zeros(n, dtype=int)
    parent = np.full(n, -1)
    order = np.argsort(-size)
    for c in range(n):
        probe = v[f[first_face[c]]].mean(axis=0, keepdims=True)   # a point on shell c
        for d in order:
            if d == c or size[d] <= size[c]:
                continue
            if np.all(lo[d] <= lo[c]) and np.all(hi[d] >= hi[c]):
                if winding_number(v, f[labels == d], probe)[0] > 0.5:
                    depth[c] += 1
                    if parent[c] < 0 or size[d] < size[parent[c]]:
                        parent[c] = d
    cavity = depth % 2 == 1
    if cavity.any():
        f[cavity[labels]] = f[cavity[labels]][:, ::-1]
        log.append(f"kept {int(cavity.sum())} closed shell(s) inside the body as cavities")
    solid = ~cavity
    outer = np.flatnonzero(solid & (depth == 0))
    main = outer[np.argmax(size[outer])]
    owner = np.where(cavity, parent, np.arange(n))   # the solid each shell belongs to
    others = [c for c in np.flatnonzero(solid) if c != main]
    # the outer solids linked to the body by overlapping bounding boxes, directly or through others
    pad = 1e-9 * float(np.linalg.norm(hi.max(axis=0) - lo.min(axis=0)))
    touching, frontier = [], [main]
    pool = [c for c in others if depth[c] == 0]
    while frontier:
        c = frontier.pop()
        near = [d for d in pool if np.all(lo[d] <= hi[c] + pad) and np.all(hi[d] >= lo[c] - pad)]
        pool = [d for d in pool if d not in near]
        touching.extend(near)
        frontier.extend(near)
    loose = [c for c in others if c not in touching]
    if touching:
        import manifold3d as m3d

        def manifold(shell):
            sel = owner[labels] == shell
            used = np.unique(f[sel])
            remap = np.full(len(v), -1)
            remap[used] = np.arange(len(used))
            man = m3d.Manifold(m3d.Mesh64(vert_properties=v[used], tri_verts=remap[f[sel]].astype(np.uint32)))
            if man.status() != m3d.Error.NoError:
                raise InputError(f"the scan's shells overlap and cannot be united ({man.status()}); "
                                 "join them in a mesh editor")
            return man

        parts = [manifold(main)] + [manifold(c) for c in touching]
        before = sum(p.volume() for p in parts)
        pieces = sorted(m3d.Manifold.batch_boolean(parts, m3d.OpType.Add).decompose(), key=lambda p: -p.volume())
        body = pieces[0]
        joined = len(parts) - len(pieces) + 1
        apart = [p for p in pieces[1:]]
        if joined > 1:
            log.append(f"united {joined} overlapping or touching shells into one body "
                       f"(overlap {before - sum(p.volume() for p in pieces):.3g} in file units cubed)")
        mesh = body.to_mesh64()
        bv = np.asarray(mesh.vert_properties)[:, :3].astype(float)
        bf = np.asarray(mesh.tri_verts).astype(np.int64)
        body_volume = body.volume()
        loose_vol = [p.volume() for p in apart] + [size[c] - _cavities(c, owner, cavity, size) for c in loose]
        loose_where = [_where(*(np.asarray(x) for x in _bbox(p))) for p in apart] + [_where(lo[c], hi[c]) for c in loose]
        rest_sel = np.isin(owner[labels], loose)
        apart_faces = sum(p.num_tri() for p in apart)
    else:
        body_volume = size[main] - _cavities(main, owner, cavity, size)
        sel = owner[labels] == main
        bv, bf = v, f[sel]
        loose_vol = [size[c] - _cavities(c, owner, cavity, size) for c in loose]
        loose_where = [_where(lo[c], hi[c]) for c in loose]
        rest_sel = np.isin(owner[labels], loose)
        apart_faces = 0
    if loose_vol:
        total = float(sum(loose_vol))
        n_faces = int(rest_sel.sum()) + apart_faces
        if total > max_loose * body_volume:
            big = int(np.argmax(loose_vol))
            raise InputError(
                f"the scan holds {len(loose_vol)} piece(s) not joined to the main body (apart from it, or touching "
                f"it only at points or along lines), with "
                f"{total / body_volume:.3g} times its volume (the largest, {loose_vol[big] / body_volume:.3g} times, "
                f"centred at {loose_where[big]} in file units; limit {max_loose:.1%} together): a statue is analysed "
                "as one rigid body: remove the pieces or join them to it in a mesh editor")
        log.append(f"dropped {len(loose_vol)} loose piece(s) not joined to the body "
                   f"({n_faces} faces, {total / body_volume:.3%} of its volume)")
    used = np.zeros(len(bv), dtype=bool)
    used[bf.ravel()] = True
    remap = np.cumsum(used) - 1
    return ShellResult(bv[used], remap[bf], tuple(log), True, float(body_volume))


def _bbox(man):
    box = np.asarray(man.bounding_box(), dtype=float)
    return box[:3], box[3:]


def _cavities(shell, owner, cavity, size) -> float:
    """Volume of the cavities that belong to solid ``shell``."""
    return float(size[(owner == shell) & cavity].sum())
