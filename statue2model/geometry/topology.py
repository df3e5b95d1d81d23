"""Edge topology of a triangle mesh in one sorting pass.

Everything the repair step needs to know about connectivity comes from sorting
the 3 f directed edges once: which edges are on a boundary (used by one face),
which are non-manifold (more than two faces), whether neighbouring faces agree
on their winding, and which faces form connected components.

Example
-------
>>> import trimesh
>>> from statue2model.geometry.topology import edge_topology
>>> box = trimesh.creation.box()
>>> t = edge_topology(box.faces, len(box.vertices))
>>> t.is_closed, t.winding_consistent, t.n_components
(True, True, 1)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components


@dataclass(frozen=True)
class EdgeTopology:
    """Connectivity facts of a mesh.

    boundary_edges     : (k, 2) directed edges (as they run in their face) used by one face only
    boundary_face      : (k,) the face of each boundary edge
    nonmanifold_face   : (j,) one face of each edge used by more than two faces
    nonmanifold_edges  : (j, 2) the vertex pairs of those edges
    inconsistent_face  : (i,) one face of each shared edge that runs the same way in both faces
    face_component     : (f,) component label of each face (faces sharing an edge are joined)
    n_components       : number of connected components
    """

    boundary_edges: np.ndarray
    boundary_face: np.ndarray
    nonmanifold_face: np.ndarray
    nonmanifold_edges: np.ndarray
    inconsistent_face: np.ndarray
    face_component: np.ndarray
    n_components: int

    @property
    def n_nonmanifold(self) -> int:
        return len(self.nonmanifold_face)

    @property
    def winding_consistent(self) -> bool:
        return len(self.inconsistent_face) == 0

    @property
    def is_closed(self) -> bool:
        """Every edge is shared by exactly two faces."""
        return len(self.boundary_edges) == 0 and self.n_nonmanifold == 0

    def keep_components(self, keep: np.ndarray, vertex_map: np.ndarray) -> "EdgeTopology":
        """The topology of the faces of the components flagged in ``keep`` ((n_components,) bool),
        with vertices renumbered by ``vertex_map`` (old index -> new index). Whole components
        share no edge with the rest, so nothing needs to be sorted again."""
        face_keep = keep[self.face_component]
        face_map = np.cumsum(face_keep) - 1
        labels = np.cumsum(keep) - 1
        b = face_keep[self.boundary_face]
        nm = face_keep[self.nonmanifold_face]
        return EdgeTopology(
            boundary_edges=vertex_map[self.boundary_edges[b]],
            boundary_face=face_map[self.boundary_face[b]],
            nonmanifold_face=face_map[self.nonmanifold_face[nm]],
            nonmanifold_edges=vertex_map[self.nonmanifold_edges[nm]],
            inconsistent_face=face_map[self.inconsistent_face[face_keep[self.inconsistent_face]]],
            face_component=labels[self.face_component[face_keep]],
            n_components=int(keep.sum()),
        )


def _edge_groups(faces: np.ndarray, n_vertices: int):
    """The 3 f directed edges (f, k) -> row 3 f + k, sorted by their undirected key:
    (directed (3f, 2), order, sorted keys, start of each group, group sizes)."""
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    lo = np.minimum(directed[:, 0], directed[:, 1])
    hi = np.maximum(directed[:, 0], directed[:, 1])
    key = lo * np.int64(n_vertices) + hi
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    starts = np.flatnonzero(np.r_[True, sorted_key[1:] != sorted_key[:-1]])
    counts = np.diff(np.r_[starts, len(sorted_key)])
    return directed, order, sorted_key, starts, counts


def edge_topology(faces: np.ndarray, n_vertices: int) -> EdgeTopology:
    """Analyse the edges of ``faces`` ((f, 3) int indices into n_vertices vertices)."""
    faces = np.asarray(faces, dtype=np.int64)
    n_faces = len(faces)
    directed, order, sorted_key, starts, counts = _edge_groups(faces, n_vertices)

    boundary_index = order[starts[counts == 1]]
    nonmanifold_index = order[starts[counts > 2]]
    nonmanifold_face = nonmanifold_index // 3

    # consecutive edges of one group join their faces (pairs for manifold edges)
    same_as_next = np.r_[sorted_key[1:] == sorted_key[:-1], False]
    a = order[same_as_next]
    b = order[np.r_[False, same_as_next[:-1]]]
    pair = np.repeat(counts, counts)[same_as_next] == 2
    a_pair, b_pair = a[pair], b[pair]
    inconsistent_face = a_pair[directed[a_pair, 0] != directed[b_pair, 1]] // 3

    fa, fb = a // 3, b // 3
    graph = csr_matrix((np.ones(len(fa), dtype=np.int8), (fa, fb)), shape=(n_faces, n_faces))
    n_comp, labels = connected_components(graph, directed=False)
    return EdgeTopology(
        boundary_edges=directed[boundary_index],
        boundary_face=boundary_index // 3,
        nonmanifold_face=nonmanifold_face,
        nonmanifold_edges=directed[nonmanifold_index],
        inconsistent_face=inconsistent_face,
        face_component=labels,
        n_components=int(n_comp),
    )


def boundary_loops(boundary_edges: np.ndarray) -> list[np.ndarray]:
    """Chain directed boundary edges into closed vertex loops.

    Returns a list of (k,) vertex index arrays, each loop in the direction of its
    edges. Edges that do not close a loop (a defect beyond repair) are left out.
    """
    outgoing: dict[int, list[int]] = {}
    for u, v in boundary_edges.tolist():
        outgoing.setdefault(u, []).append(v)
    loops = []
    while outgoing:
        start = next(iter(outgoing))
        loop = [start]
        current = start
        while True:
            nxt = outgoing[current].pop()
            if not outgoing[current]:
                del outgoing[current]
            if nxt == start:
                loops.append(np.array(loop, dtype=np.int64))
                break
            if nxt not in outgoing:
                break  # open chain: cannot be closed by a cap
            loop.append(nxt)
            current = nxt
    return loops


def corner_fans(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """(f, 3) fan label of every face corner: the corners of one vertex that are joined
    across edges shared by exactly two faces get the same label."""
    faces = np.asarray(faces, dtype=np.int64)
    n_faces = len(faces)
    directed, order, _, starts, counts = _edge_groups(faces, n_vertices)   # edge k of face f: corners k, k + 1
    two = starts[counts == 2]
    e1, e2 = order[two], order[two + 1]            # directed-edge indices of the two faces
    f1, k1 = e1 // 3, e1 % 3
    f2, k2 = e2 // 3, e2 % 3
    # corner index = 3 * face + position; the edge's start and end corners in each face
    s1, t1 = 3 * f1 + k1, 3 * f1 + (k1 + 1) % 3
    s2, t2 = 3 * f2 + k2, 3 * f2 + (k2 + 1) % 3
    same = directed[e1, 0] == directed[e2, 0]      # both run u -> w (inconsistent winding)
    a = np.r_[s1, t1]
    b = np.r_[np.where(same, s2, t2), np.where(same, t2, s2)]
    n_corners = 3 * n_faces
    graph = csr_matrix((np.ones(len(a), dtype=np.int8), (a, b)), shape=(n_corners, n_corners))
    _, labels = connected_components(graph, directed=False)
    return labels.reshape(-1, 3)


def nonmanifold_vertices(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """Indices of the vertices where the faces around a vertex do not form one fan.

    Two sheets that meet at a single vertex (a pinch, an hourglass), or two holes
    whose rims touch at a vertex, leave that vertex with two or more separate fans
    of faces even when every edge is shared by at most two faces (see
    :func:`corner_fans`).

    >>> import numpy as np
    >>> tets = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> hourglass = np.vstack([tets, np.where(tets == 0, 0, tets + 3)])  # two tetrahedra sharing vertex 0
    >>> nonmanifold_vertices(hourglass, 7).tolist()
    [0]
    """
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return np.zeros(0, dtype=np.int64)
    labels = corner_fans(faces, n_vertices).ravel()
    n_corners = np.int64(labels.size)
    pairs = np.unique(faces.ravel() * n_corners + labels)
    fans = np.bincount(pairs // n_corners, minlength=n_vertices)
    return np.flatnonzero(fans > 1)


def split_nonmanifold_vertices(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """Give every fan of a non-manifold vertex its own copy of the vertex (MeshLab's
    'split vertices on non-manifold vertex'): the sheets that met there part, at the
    same place. Returns vertices, faces and the number of vertices split.

    >>> import numpy as np
    >>> tets = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> hourglass = np.vstack([tets, np.where(tets == 0, 0, tets + 3)])
    >>> v, f, n = split_nonmanifold_vertices(np.zeros((7, 3)), hourglass)
    >>> n, len(v), nonmanifold_vertices(f, len(v)).tolist()
    (1, 8, [])
    """
    faces = np.asarray(faces, dtype=np.int64)
    labels = corner_fans(faces, len(vertices)).ravel()
    corner_vertex = faces.ravel()
    n_corners = np.int64(labels.size)
    pair_key = corner_vertex * n_corners + labels
    uniq, inverse = np.unique(pair_key, return_inverse=True)
    owner = uniq // n_corners
    first = np.r_[True, owner[1:] != owner[:-1]]      # the first fan keeps the vertex's index
    new_index = np.where(first, owner, len(vertices) + np.cumsum(~first) - 1)
    n_split = int(np.unique(owner[~first]).size)
    if n_split == 0:
        return vertices, faces, 0
    v = np.vstack([vertices, vertices[owner[~first]]])
    return v, new_index[inverse.reshape(-1)].reshape(-1, 3), n_split


def simple_loops(loop: np.ndarray) -> list[np.ndarray]:
    """Split a closed vertex loop that visits a vertex more than once into simple loops.

    The loop's edges run loop[i] -> loop[i + 1] (and back to loop[0]); every edge ends up
    in exactly one of the returned loops, each of which visits a vertex once. A loop
    through a vertex twice (a figure of eight) filled as one, from a centre point, would
    put that vertex's spoke on four faces: a non-manifold edge. Pieces of fewer than
    three vertices (an edge and its reverse) are dropped.

    >>> [s.tolist() for s in simple_loops(np.array([0, 1, 2, 0, 3, 4]))]
    [[0, 1, 2], [0, 3, 4]]
    >>> [s.tolist() for s in simple_loops(np.array([5, 1, 6, 2, 5, 3, 6, 4]))]
    [[5, 1, 6, 2], [5, 3, 6, 4]]
    """
    stack: list[int] = []
    where: dict[int, int] = {}
    out = []
    for v in np.asarray(loop).tolist():
        i = where.get(v)
        if i is None:
            where[v] = len(stack)
            stack.append(v)
            continue
        piece = stack[i:]                      # v ... back to v
        for u in piece[1:]:
            del where[u]
        del stack[i + 1:]
        if len(piece) >= 3:
            out.append(np.array(piece, dtype=np.int64))
    if len(stack) >= 3:
        out.append(np.array(stack, dtype=np.int64))
    return out


def _corner_angles(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(f, 3) angle of every face corner, radians."""
    p = vertices[faces]
    out = np.empty(faces.shape)
    for k in range(3):
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        out[:, k] = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))
    return out


def _fan_measures(vertices: np.ndarray, faces: np.ndarray, labels: np.ndarray, at: np.ndarray):
    """For every vertex flagged in ``at`` ((n,) bool) and every fan of faces around it
    (``labels``, :func:`corner_fans`): the sum of the fan's corner angles there (radians)
    and its unit mean normal (area-weighted). Two dicts {vertex: {fan label: value}}."""
    rows, cols = np.nonzero(at[faces])
    angles = _corner_angles(vertices, faces[rows])[np.arange(len(rows)), cols]
    p = vertices[faces[rows]]
    area_vec = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    theta: dict[int, dict[int, float]] = {}
    normal: dict[int, dict[int, np.ndarray]] = {}
    for i, (r, c) in enumerate(zip(rows.tolist(), cols.tolist())):
        vert, lab = int(faces[r, c]), int(labels[r, c])
        fan_theta = theta.setdefault(vert, {})
        fan_theta[lab] = fan_theta.get(lab, 0.0) + float(angles[i])
        fan_normal = normal.setdefault(vert, {})
        fan_normal[lab] = fan_normal.get(lab, 0.0) + area_vec[i]
    for fan_normal in normal.values():
        for lab, n in fan_normal.items():
            fan_normal[lab] = n / (np.linalg.norm(n) + 1e-300)
    return theta, normal


def _ccw(a: np.ndarray, b: np.ndarray, axis: np.ndarray) -> float:
    """Angle in [0, 2 pi) turning counter-clockwise about ``axis`` (unit) from ray ``a`` to ray ``b``."""
    a = a - np.dot(a, axis) * axis
    b = b - np.dot(b, axis) * axis
    return float(np.arctan2(np.dot(axis, np.cross(a, b)), np.dot(a, b)) % (2 * np.pi))


def _pair_fans(v: int, ins: list[int], outs: list[int], fan_of_in: list[int], fan_of_out: list[int],
               theta: dict[int, float], normal: dict[int, np.ndarray], vertices: np.ndarray,
               edges: np.ndarray) -> dict[int, int]:
    """Which boundary edge leaving vertex ``v`` follows each one arriving (one to one).

    Each open fan of faces around v turns counter-clockwise (about its outward normal) from
    the boundary edge leaving v at its first face to the one arriving at its last face. A
    pairing pi (the arriving edge of fan i goes on with the leaving edge of fan pi(i)) puts
    a gap, a hole through v, between the end of fan i and the start of fan pi(i). The
    pairing kept has the least sum over fans of the gap's angle:

    * back to its own start, 2 pi less the fan's corner angles (``theta``, radians): the
      fan is a sheet of its own, closed at v by the hole;
    * on to another fan, the counter-clockwise turn from one edge to the other about the
      two fans' mean normal (``normal``, unit), plus pi (1 - n_i . n_j): in one sheet the
      gaps to the next fan round add up to a full turn less the fans (any other pairing
      costs at least a full turn more); fans that face different ways (two sheets that
      touched along a deleted non-manifold edge, or at a vertex) cost up to 2 pi more.

    So two holes in one sheet that touch at v (a bow tie) come apart, and two sheets each
    keep their own hole. Beyond five fans, or for fans without one arriving and one
    leaving edge each, the nearest leaving edge in angle is taken, one to one.
    """
    fans = sorted(set(fan_of_in))
    if len(ins) == len(outs) == len(fans) == len(set(fan_of_out)) and set(fan_of_out) == set(fans) \
            and 2 <= len(fans) <= 5:
        import itertools

        e_in = dict(zip(fan_of_in, ins))
        e_out = dict(zip(fan_of_out, outs))
        d_in = [vertices[edges[e_in[f], 0]] - vertices[v] for f in fans]
        d_out = [vertices[edges[e_out[f], 1]] - vertices[v] for f in fans]
        n = [normal[f] for f in fans]
        d = len(fans)
        cost = np.empty((d, d))
        for i in range(d):
            for j in range(d):
                if i == j:
                    cost[i, j] = max(0.0, 2 * np.pi - theta[fans[i]])
                    continue
                axis = n[i] + n[j]
                axis = axis / (np.linalg.norm(axis) + 1e-300)
                cost[i, j] = _ccw(d_in[i], d_out[j], axis) + np.pi * (1 - np.dot(n[i], n[j]))
        best = min(itertools.permutations(range(d)), key=lambda p: sum(cost[i, p[i]] for i in range(d)))
        return {e_in[fans[i]]: e_out[fans[best[i]]] for i in range(d)}
    left = list(outs)
    out = {}
    for k in ins:
        if not left:
            break
        du = vertices[edges[k, 0]] - vertices[v]
        dx = [vertices[edges[j, 1]] - vertices[v] for j in left]
        cosine = [np.dot(du, x) / (np.linalg.norm(du) * np.linalg.norm(x) + 1e-300) for x in dx]
        out[k] = left.pop(int(np.argmax(cosine)))
    return out


def hole_loops(vertices: np.ndarray, faces: np.ndarray, topo: EdgeTopology) -> list[np.ndarray]:
    """The holes of a consistently wound, edge-manifold mesh as simple closed vertex loops.

    Unlike :func:`boundary_loops`, a vertex where holes touch (it has several fans of
    faces and as many boundary edges leaving it) does not merge them: at such a vertex
    each arriving boundary edge is paired one to one with a leaving one (see
    :func:`_pair_fans`), and a loop that still visits a vertex more than once is split
    there (:func:`simple_loops`). Every returned loop visits each vertex once, and every
    boundary edge that closes into a loop is in exactly one of them.

    >>> import trimesh
    >>> s = trimesh.creation.icosphere(2)
    >>> fan = np.flatnonzero((s.faces == 0).any(axis=1))
    >>> apart = [fan[0]] + [k for k in fan[1:] if not (np.isin(s.faces[k], s.faces[fan[0]]).sum() == 2)][:1]
    >>> f = np.delete(s.faces, apart, axis=0)         # two triangles that touch at vertex 0 only
    >>> sorted(len(loop) for loop in hole_loops(s.vertices, f, edge_topology(f, len(s.vertices))))
    [3, 3]
    """
    faces = np.asarray(faces, dtype=np.int64)
    edges = np.asarray(topo.boundary_edges, dtype=np.int64)
    n_edges = len(edges)
    if not n_edges:
        return []
    n_v = len(vertices)
    n_out = np.bincount(edges[:, 0], minlength=n_v)
    first_out = np.full(n_v, -1, dtype=np.int64)
    first_out[edges[::-1, 0]] = np.arange(n_edges)[::-1]
    succ = np.where(n_out[edges[:, 1]] == 1, first_out[edges[:, 1]], -1)
    multi = np.flatnonzero(n_out > 1)
    if len(multi):                             # vertices where holes touch: pair their edges
        vv = np.asarray(vertices, dtype=float)
        labels = corner_fans(faces, n_v)
        is_multi = np.zeros(n_v, dtype=bool)
        is_multi[multi] = True
        theta, normal = _fan_measures(vv, faces, labels, is_multi)
        bf = topo.boundary_face

        def fan_at(k: int, vert: int) -> int:
            face = bf[k]
            return int(labels[face, int(np.flatnonzero(faces[face] == vert)[0])])

        ins_at: dict[int, list[int]] = {}
        for k in np.flatnonzero(is_multi[edges[:, 1]]).tolist():
            ins_at.setdefault(int(edges[k, 1]), []).append(k)
        outs_at: dict[int, list[int]] = {}
        for k in np.flatnonzero(is_multi[edges[:, 0]]).tolist():
            outs_at.setdefault(int(edges[k, 0]), []).append(k)
        for v in multi.tolist():
            ins, outs = ins_at.get(v, []), outs_at.get(v, [])
            pairs = _pair_fans(v, ins, outs, [fan_at(k, v) for k in ins], [fan_at(k, v) for k in outs],
                               theta.get(v, {}), normal.get(v, {}), vv, edges)
            for k, j in pairs.items():
                succ[k] = j
    loops = []
    seen = np.zeros(n_edges, dtype=bool)
    for start in range(n_edges):
        if seen[start]:
            continue
        walk, k = [], start
        while k >= 0 and not seen[k]:
            seen[k] = True
            walk.append(k)
            k = int(succ[k])
        if k >= 0 and k in walk:               # closed (a tail leading into the cycle stays open)
            cycle = walk[walk.index(k):]
            loops.extend(simple_loops(edges[cycle, 0]))
    return loops


def orient_faces(faces: np.ndarray, n_vertices: int) -> tuple[np.ndarray, int]:
    """Flip faces so that neighbours agree on their winding (every shared edge runs
    opposite ways in its two faces), one component at a time, its first face kept.

    Vectorised: a breadth-first tree over the faces (scipy), and the flip of each
    face as the parity of 'same-direction' edges on its path to the root (pointer
    jumping). Returns the faces and the number flipped. A surface that cannot be
    oriented (a Moebius strip, a Klein bottle) still has inconsistent edges after
    this; the caller checks.

    >>> f = np.array([[0, 1, 2], [1, 2, 3]])          # the shared edge 1-2 runs the same way
    >>> orient_faces(f, 4)[0].tolist()
    [[0, 1, 2], [3, 2, 1]]
    """
    from scipy.sparse.csgraph import breadth_first_order

    faces = np.asarray(faces, dtype=np.int64)
    n_faces = len(faces)
    directed, order, _, starts, counts = _edge_groups(faces, n_vertices)   # edge k of face f: corners k, k + 1
    two = starts[counts == 2]
    e1, e2 = order[two], order[two + 1]
    fa, fb = e1 // 3, e2 // 3
    same = (directed[e1, 0] == directed[e2, 0]).astype(np.int8)   # 1: the two faces disagree
    ok = fa != fb
    fa, fb, same = fa[ok], fb[ok], same[ok]
    _, comp = connected_components(csr_matrix((np.ones(len(fa), dtype=np.int8), (fa, fb)),
                                              shape=(n_faces, n_faces)), directed=False)
    _, first = np.unique(comp, return_index=True)
    root = n_faces                                    # a virtual root joined to each component's first face
    ra = np.r_[fa, np.full(len(first), root)]
    rb = np.r_[fb, first]
    graph = csr_matrix((np.ones(len(ra), dtype=np.int8), (ra, rb)), shape=(n_faces + 1, n_faces + 1))
    _, pred = breadth_first_order(graph, root, directed=False, return_predecessors=True)
    pred = pred[:n_faces].astype(np.int64)
    # parity of each tree edge (face, its predecessor)
    pair_key = np.r_[fa * n_faces + fb, fb * n_faces + fa]
    pair_same = np.r_[same, same]
    srt = np.argsort(pair_key)
    pair_key, pair_same = pair_key[srt], pair_same[srt]
    is_child = pred >= 0
    is_child &= pred != root
    parity = np.zeros(n_faces, dtype=np.int8)
    child = np.flatnonzero(is_child)
    pos = np.searchsorted(pair_key, child * n_faces + pred[child])
    parity[child] = pair_same[pos]
    up = np.where(is_child, pred, np.arange(n_faces))
    for _ in range(max(1, int(n_faces).bit_length())):
        parity ^= parity[up]
        nxt = up[up]
        if np.array_equal(nxt, up):
            break
        up = nxt
    flip = parity.astype(bool)
    out = faces.copy()
    out[flip] = out[flip][:, ::-1]
    return out, int(flip.sum())
