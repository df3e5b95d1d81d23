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
    inconsistent_face  : (i,) one face of each shared edge that runs the same way in both faces
    face_component     : (f,) component label of each face (faces sharing an edge are joined)
    n_components       : number of connected components
    """

    boundary_edges: np.ndarray
    boundary_face: np.ndarray
    nonmanifold_face: np.ndarray
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
        return EdgeTopology(
            boundary_edges=vertex_map[self.boundary_edges[b]],
            boundary_face=face_map[self.boundary_face[b]],
            nonmanifold_face=face_map[self.nonmanifold_face[face_keep[self.nonmanifold_face]]],
            inconsistent_face=face_map[self.inconsistent_face[face_keep[self.inconsistent_face]]],
            face_component=labels[self.face_component[face_keep]],
            n_components=int(keep.sum()),
        )


def edge_topology(faces: np.ndarray, n_vertices: int) -> EdgeTopology:
    """Analyse the edges of ``faces`` ((f, 3) int indices into n_vertices vertices)."""
    faces = np.asarray(faces, dtype=np.int64)
    n_faces = len(faces)
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    lo = np.minimum(directed[:, 0], directed[:, 1])
    hi = np.maximum(directed[:, 0], directed[:, 1])
    key = lo * np.int64(n_vertices) + hi
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    starts = np.flatnonzero(np.r_[True, sorted_key[1:] != sorted_key[:-1]])
    counts = np.diff(np.r_[starts, len(sorted_key)])

    boundary_index = order[starts[counts == 1]]
    nonmanifold_face = order[starts[counts > 2]] // 3

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
