"""Holes that share vertices (issue #24, item 2).

Real scans were refused with "0 open and N non-manifold edges remain after repair": the
faces on a non-manifold edge are deleted, the holes that leaves in two sheets share
vertices, and the hole fill walked them as one loop through those vertices twice and
filled it from a centre point (the spoke to a doubled vertex is on four faces), or lost
some of their edges ("N open edges remain"). Now hole loops are paired per sheet at such
vertices and split there into simple loops, and a flat cap never reuses an edge.

Every fixture is built from a clean closed body (the bundled scans; or the column of
tests/scan_fixtures.py, whose volume, h and a_min are closed-form), the repaired body must
be a closed 2-manifold, and its volume, h (height of the centre of mass) and a_min
(uplift acceleration in the weakest direction) within 0.5 % of the clean body's:

* a second sheet (a tent) along a chain of 1-4 edges of the scan, each then on four faces,
  so that two holes share every vertex of the chain once those faces are deleted;
* balls touching the scan at one vertex, with a face missing there in both: the issue's
  refusal "0 open and 2 non-manifold edges" before the fix;
* flaps (a third face on an edge); bow ties of two or three holes at a vertex; islands of
  two faces between two holes that share two vertices;
* flat holes whose Delaunay caps would reuse an edge (of another cap, or of the mesh);
* random damage of all these kinds at several places (a property over seeds).

Loop splitting and the pairing of loops at shared vertices are also tested on their own."""
from __future__ import annotations

import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from scan_fixtures import column, prism_reference
from statue2model.geometry.body import body_from_mesh
from statue2model.geometry.repair import delete_nonmanifold_edges, fill_holes, repair_mesh
from statue2model.geometry.rocking_params import weakest_direction
from statue2model.geometry.scan import read_scan
from statue2model.geometry.topology import edge_topology, hole_loops, nonmanifold_vertices, simple_loops
from statue2model.io.paths import MESHES_DIR

TOL = 0.005      # the bound: volume, h and a_min within 0.5 % of the clean body's
SCANS = ("maria_barjatinskaja.ply", "dancing_girl.ply")


# ----------------------------------------------------------------------------- helpers

def _assert_closed(v, f):
    topo = edge_topology(f, len(v))
    assert len(topo.boundary_edges) == 0 and topo.n_nonmanifold == 0
    assert topo.winding_consistent
    assert len(nonmanifold_vertices(f, len(v))) == 0
    assert trimesh.Trimesh(v, f, process=False).is_watertight


def _quantities(v, f, **options) -> dict:
    """volume (m^3), h (m) and a_min (m/s^2) of the body the pipeline (repair included) makes
    of (v, f), which must be a closed 2-manifold, and its log."""
    body = body_from_mesh(v, f, **options)
    _assert_closed(body.vertices, body.faces)
    return {"volume": body.mass.volume, "h": float(body.mass.com[2]),
            "a_min": float(weakest_direction(body.mass, body.footprint.hull)[1]), "log": body.log}


def _assert_close(got: dict, ref: dict, tol: float = TOL):
    for key in ("volume", "h", "a_min"):
        assert got[key] == pytest.approx(ref[key], rel=tol), key


@pytest.fixture(scope="module", params=SCANS)
def scan(request):
    """A bundled scan made clean and closed, in file units, and its quantities."""
    raw = read_scan(MESHES_DIR / request.param)
    rep = repair_mesh(raw.vertices, raw.faces)
    v, f = rep.vertices, rep.faces
    _assert_closed(v, f)
    return v, f, _quantities(v, f)


COLUMN_OPTS = {"units": "m", "up": "z"}


@pytest.fixture(scope="module")
def col():
    """The column of scan_fixtures (120-gon prism on a disc base) and its closed-form answers."""
    v, f = column(wall_levels=60)                        # wall triangles about 16 mm on a side
    return v, f, prism_reference()


def _vertex_fan(f, vid):
    """Faces (indices) around vertex ``vid`` in counter-clockwise order (a closed fan)."""
    ring = np.flatnonzero((f == vid).any(axis=1))
    nxt = {}
    for k in ring:
        t = list(f[k])
        i = t.index(vid)
        nxt[t[(i + 1) % 3]] = (t[(i + 2) % 3], k)
    start = next(iter(nxt))
    order, p = [], start
    for _ in range(len(ring)):
        p, k = nxt[p]
        order.append(k)
    return np.array(order)


def _ring(f, vertices):
    """The vertices sharing a face with any of ``vertices``, and those."""
    return np.unique(f[np.isin(f, list(vertices)).any(axis=1)])


def _largest_rim(v, f, gone):
    """Perimeter of the largest hole left by deleting faces ``gone`` from the closed mesh
    (v, f), a hole being a set of deleted faces joined across edges (holes that touch only
    at vertices are separate, as the repair must keep them)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    g = f[gone]
    e = np.sort(g[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    key = e[:, 0] * len(v) + e[:, 1]
    order = np.argsort(key, kind="stable")
    twin = np.flatnonzero(key[order][1:] == key[order][:-1])      # an inner edge: two deleted faces
    a, b = order[twin] // 3, order[twin + 1] // 3
    _, label = connected_components(coo_matrix((np.ones(len(a)), (a, b)), shape=(len(g), len(g))), directed=False)
    _, inverse, count = np.unique(key, return_inverse=True, return_counts=True)
    rim = count[inverse] == 1
    length = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
    if not rim.any():
        return 0.0
    return float(np.bincount(label[np.flatnonzero(rim) // 3], weights=length[rim]).max())


def _places(v, f, rng, n, make, axis=None, share=0.09, free=None, tries=400):
    """Up to ``n`` damages ``make(vertex) -> (faces to delete, vertices touched[, faces whose
    deletion makes the holes the repair must close, if others])`` at random
    vertices with six faces, away from the ends of the longest axis (or of ``axis``), each
    at least two rings from the others, every hole of at most ``share`` of the bounding-box
    diagonal around (the repair closes curved holes up to 0.1: so each is one it must
    close). ``free``: (n,) bool of the vertices still free, updated (shared by calls)."""
    diag = float(np.linalg.norm(np.ptp(v, axis=0)))
    up = int(np.argmax(np.ptp(v, axis=0))) if axis is None else axis
    lo, hi = v[:, up].min(), v[:, up].max()
    ok = (np.bincount(f.ravel(), minlength=len(v)) == 6) & (v[:, up] > lo + 0.15 * (hi - lo)) \
        & (v[:, up] < lo + 0.9 * (hi - lo))
    free = np.ones(len(v), bool) if free is None else free
    out = []
    for vid in rng.permutation(np.flatnonzero(ok))[:tries].tolist():
        if len(out) == n:
            break
        if not free[vid]:
            continue
        gone, touched, *hole = make(vid)
        if len(gone) == 0 or not free[touched].all() or _largest_rim(v, f, (hole or [gone])[0]) > share * diag:
            continue
        free[_ring(f, _ring(f, touched))] = False
        out.append((gone, touched))
    return out


def _neighbours(f, n):
    """(n,) list of the vertices sharing an edge with each vertex."""
    e = f[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    nb = [set() for _ in range(n)]
    for a, b in e.tolist():
        nb[a].add(b)
        nb[b].add(a)
    return nb


def _chain(v, nb, start, k):
    """A path of ``k`` edges from ``start`` along the surface (neighbours ``nb``), as straight
    as the mesh allows."""
    path = [int(start)]
    direction = None
    while len(path) <= k:
        cur = path[-1]
        cand = sorted(c for c in nb[cur] if c not in path)
        def step(c):
            return (v[c] - v[cur]) / np.linalg.norm(v[c] - v[cur])
        nxt = cand[0] if direction is None else max(cand, key=lambda c: float(np.dot(step(c), direction)))
        direction = step(nxt)
        path.append(int(nxt))
    return np.array(path)


def _on_chain(f, path):
    """(faces on the edges of the chain ``path``, its vertices): what the repair will delete."""
    e = np.sort(np.column_stack([path[:-1], path[1:]]), axis=1)
    fe = np.sort(f[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 3, 2), axis=2)
    on = np.zeros(len(f), bool)
    for a, b in e:
        on |= ((fe[:, :, 0] == a) & (fe[:, :, 1] == b)).any(axis=1)
    return np.flatnonzero(on), path


def _sheet_along(v, f, path, size, rows=4):
    """A closed ridge (a tent, ``size`` high and wide) standing on the chain of vertices
    ``path``: its two walls meet along the chain, so each chain edge is on two faces of
    the body and two of the tent (a non-manifold edge), and the tent touches the body
    along that line only. Returns the joined vertices and faces and the tent's volume."""
    mesh = trimesh.Trimesh(v, f, process=False)
    p = v[path]
    n = mesh.vertex_normals[path]
    t = np.gradient(p, axis=0)
    t /= np.linalg.norm(t, axis=1)[:, None]
    s = np.cross(n, t)
    s /= np.linalg.norm(s, axis=1)[:, None]
    left, right = p + size * (n + s), p + size * (n - s)
    section = ([p + (j / rows) * (left - p) for j in range(rows)]
               + [left + (j / rows) * (right - left) for j in range(rows)]
               + [right + (j / rows) * (p - right) for j in range(rows)])
    section = np.stack(section, axis=1)                     # (k, M, 3); column 0 is the chain itself
    k, m = section.shape[:2]
    ids = np.empty((k, m), dtype=np.int64)
    ids[:, 0] = path
    ids[:, 1:] = len(v) + np.arange(k * (m - 1)).reshape(k, m - 1)
    c0, c1 = len(v) + k * (m - 1), len(v) + k * (m - 1) + 1
    new_v = np.vstack([v, section[:, 1:].reshape(-1, 3), section[0].mean(axis=0), section[-1].mean(axis=0)])
    tris = []
    for i in range(k - 1):
        for j in range(m):
            a, b, c, d = ids[i, j], ids[i, (j + 1) % m], ids[i + 1, j], ids[i + 1, (j + 1) % m]
            tris += [[a, b, d], [a, d, c]]
    for j in range(m):
        tris += [[c0, ids[0, (j + 1) % m], ids[0, j]], [c1, ids[-1, j], ids[-1, (j + 1) % m]]]
    tris = np.array(tris)
    used = np.unique(tris)
    remap = np.full(len(new_v), -1)
    remap[used] = np.arange(len(used))
    tent = trimesh.Trimesh(new_v[used], remap[tris], process=False)
    assert tent.is_watertight
    trimesh.repair.fix_normals(tent)
    if tent.volume < 0:
        tent.invert()
    return new_v, np.vstack([f, used[tent.faces]]), float(tent.volume)


def _ball_at(v, f, vid, share):
    """A closed ball (an icosphere, ``share`` of the body's volume) on the body at vertex
    ``vid`` (one of its vertices is ``vid``): it touches the body there only where the body is
    convex, and dips into it a little where it is not. Returns the joined vertices and faces
    and the index of one ball face at ``vid``."""
    mesh = trimesh.Trimesh(v, f, process=False)
    radius = (share * mesh.volume * 3 / (4 * np.pi)) ** (1 / 3)
    ball = trimesh.creation.icosphere(3, radius=radius)
    n = mesh.vertex_normals[vid]
    tip = int(np.argmin(ball.vertices @ n))                 # the ball's vertex facing the body
    bv = ball.vertices - ball.vertices[tip] + v[vid]
    keep = np.ones(len(bv), bool)
    keep[tip] = False
    idx = np.empty(len(bv), dtype=np.int64)
    idx[tip] = vid
    idx[keep] = len(v) + np.arange(keep.sum())
    at_tip = int(np.flatnonzero((ball.faces == tip).any(axis=1))[0])
    return np.vstack([v, bv[keep]]), np.vstack([f, idx[ball.faces]]), len(f) + at_tip


def _random_patches(f, rng, n_patches, max_size):
    """Face indices of ``n_patches`` patches of 1..max_size faces, each grown at random from a
    seed face (patches may touch or overlap)."""
    mesh = trimesh.Trimesh(np.zeros((f.max() + 1, 3)), f, process=False)
    nbrs = [[] for _ in range(len(f))]
    for a, b in mesh.face_adjacency:
        nbrs[a].append(b)
        nbrs[b].append(a)
    gone: set[int] = set()
    for seed in rng.choice(len(f), n_patches, replace=False):
        patch, front = {int(seed)}, [int(seed)]
        size = int(rng.integers(1, max_size + 1))
        while front and len(patch) < size:
            grow = front[int(rng.integers(len(front)))]
            cand = [x for x in nbrs[grow] if x not in patch]
            if not cand:
                front.remove(grow)
                continue
            x = cand[int(rng.integers(len(cand)))]
            patch.add(x)
            front.append(x)
        gone |= patch
    return np.array(sorted(gone))


def _loop_edges(loops):
    return sorted((int(a), int(b)) for loop in loops for a, b in zip(loop, np.roll(loop, -1)))


# ----------------------------------------------------------------------------- loops on their own

@pytest.mark.parametrize("loop, pieces", [
    ([0, 1, 2, 0, 3, 4], [[0, 1, 2], [0, 3, 4]]),                       # figure of eight
    ([5, 1, 6, 2, 5, 3, 6, 4], [[5, 1, 6, 2], [5, 3, 6, 4]]),           # two holes through the same two vertices
    ([0, 1, 2, 0, 3, 4, 0, 5, 6], [[0, 1, 2], [0, 3, 4], [0, 5, 6]]),   # three holes at one vertex
    ([0, 1, 2, 3, 1, 4, 5], [[1, 2, 3], [0, 1, 4, 5]]),
    ([7, 8, 9], [[7, 8, 9]]),
])
def test_simple_loops_split_at_every_repeated_vertex(loop, pieces):
    got = simple_loops(np.array(loop))
    assert sorted(p.tolist() for p in got) == sorted(pieces)
    for p in got:
        assert len(set(p.tolist())) == len(p)                       # simple
    assert _loop_edges(got) == _loop_edges([np.array(loop)])       # every edge once, same direction


def test_simple_loops_keep_every_edge_of_random_walks():
    """Random closed walks that could be a hole's rim (no directed edge twice, never an edge
    and its reverse): split into simple loops that hold every edge exactly once."""
    rng = np.random.default_rng(5)
    tried = 0
    while tried < 300:
        loop = rng.integers(0, 9, size=int(rng.integers(3, 40)))
        edges = _loop_edges([loop])
        if any(u == w for u, w in edges) or len(set(edges)) < len(edges) or any((w, u) in edges for u, w in edges):
            continue
        tried += 1
        got = simple_loops(loop)
        for p in got:
            assert len(set(p.tolist())) == len(p) >= 3
        assert _loop_edges(got) == edges


def test_hole_loops_are_simple_and_use_every_boundary_edge_once(scan):
    v, f, _ = scan
    rng = np.random.default_rng(2)
    keep = np.ones(len(f), bool)
    keep[_random_patches(f, rng, 60, 6)] = False
    ff = f[keep]
    topo = edge_topology(ff, len(v))
    loops = hole_loops(v, ff, topo)
    for loop in loops:
        assert len(set(loop.tolist())) == len(loop) >= 3
    assert _loop_edges(loops) == sorted(map(tuple, topo.boundary_edges.tolist()))


# ----------------------------------------------------------------------------- non-manifold edges

@pytest.mark.parametrize("seed", range(16))
def test_sheet_touching_along_a_chain_of_edges(scan, seed):
    """The class of the refused scans: a second sheet (a tent about 1.5 edges high) touches the
    scan along a chain of 1-4 of its edges, each then on four faces. The repair deletes them;
    two holes share every vertex of the chain (four at its inner vertices, where each sheet
    also has a bow tie). Each hole is walked on its own sheet (a loop never mixes scan and
    tent vertices), closed, and the body keeps volume, h and a_min within 0.5 %. (Before
    the fix, 5 of these 32 were refused with open edges left, boundary edges the walk lost
    at the chain's vertices, and every one had loops mixing the two sheets.)"""
    v, f, ref = scan
    k = 1 + seed % 4
    rng = np.random.default_rng(seed)
    nb = _neighbours(f, len(v))
    (_, path), = _places(v, f, rng, 1, lambda vid: _on_chain(f, _chain(v, nb, vid, k)))
    edge = float(np.linalg.norm(np.diff(v[path], axis=0), axis=1).mean())
    vv, ff, _ = _sheet_along(v, f, path, 1.5 * edge, rows=2)
    topo = edge_topology(ff, len(vv))
    assert topo.n_nonmanifold == k
    cut, n_cut = delete_nonmanifold_edges(ff, len(vv), topo)
    assert n_cut == 4 * k
    for loop in hole_loops(vv, cut, edge_topology(cut, len(vv))):
        own = np.setdiff1d(loop, path)
        assert (own < len(v)).all() or (own >= len(v)).all()        # one sheet's hole
    got = _quantities(vv, ff)
    assert f"deleted {4 * k} faces on {k} non-manifold edge(s)" in got["log"]
    _assert_close(got, ref)


def test_many_sheets_and_flaps_on_a_column_give_its_closed_form(col):
    """Six tents along chains of 1-4 wall edges and a flap on the column: its closed form."""
    v, f, ref = col
    rng = np.random.default_rng(4)
    vv, ff = v, f
    n_nme = 0
    nb = _neighbours(f, len(v))
    for _, path in _places(v, f, rng, 6, lambda vid: _on_chain(f, _chain(v, nb, vid, int(rng.integers(1, 5)))),
                           axis=2):
        edge = float(np.linalg.norm(np.diff(v[path], axis=0), axis=1).mean())
        vv, ff, _ = _sheet_along(vv, ff, path, 0.5 * edge)
        n_nme += len(path) - 1
    assert n_nme >= 6
    mid = v[f][:, :, 2].mean(axis=1)
    a, b = f[rng.choice(np.flatnonzero((mid > 0.3) & (mid < 0.7))), :2]
    vv = np.vstack([vv, v[a] * [1.02, 1.02, 1.0]])        # and a flap: a third face on an edge
    ff = np.vstack([ff, [[a, b, len(vv) - 1]]])
    assert edge_topology(ff, len(vv)).n_nonmanifold == n_nme + 1
    _assert_close(_quantities(vv, ff, **COLUMN_OPTS), ref, tol=1e-3)


def test_flaps_on_scan_edges(scan):
    """A third face on 12 edges of the scan (each then on three faces)."""
    v, f, ref = scan
    rng = np.random.default_rng(8)
    faces = f[rng.choice(len(f), 12, replace=False)]
    vv, ff = [v], [f]
    for k, (a, b, c) in enumerate(faces):
        vv.append((v[a] + 0.5 * (v[c] - v[a]) + 0.3 * (v[b] - v[a]))[None])   # a third face on a-b
        ff.append([[a, b, len(v) + k]])
    vv, ff = np.vstack(vv), np.vstack(ff)
    assert edge_topology(ff, len(vv)).n_nonmanifold == 12
    _assert_close(_quantities(vv, ff), ref)


# ----------------------------------------------------------------------------- holes touching at vertices

@pytest.mark.parametrize("pattern", [(0, 3), (0, 2, 4), (0, 2), (0, 1, 3, 4)],
                         ids=["bow tie", "three holes at a vertex", "bow tie, uneven", "two two-face holes"])
def test_holes_touching_at_a_vertex(scan, pattern):
    v, f, ref = scan
    rng = np.random.default_rng(len(pattern))
    keep = np.ones(len(f), bool)
    places = _places(v, f, rng, 5, lambda vid: (_vertex_fan(f, vid)[list(pattern)], [vid]))
    for gone, _ in places:
        keep[gone] = False
    ff = f[keep]
    assert len(places) == 5 and len(nonmanifold_vertices(ff, len(v))) >= 5
    _assert_close(_quantities(v, ff), ref)


def test_two_bodies_touching_at_a_vertex_each_with_a_hole_there(scan):
    """Two balls (0.2 % of the volume each) touch the scan at one vertex each; a face at that
    vertex is missing in the scan and in the ball. The holes of the two sheets pass through
    the same vertex: walked as one loop through it twice and filled from a centre point, the
    spoke to that vertex was on four faces ("0 open and 2 non-manifold edges remain after
    repair", the issue's refusal). Now each sheet's hole is closed on its own, the vertex
    split and the balls dropped as loose pieces (or united where they dip into the scan)."""
    v, f, ref = scan
    rng = np.random.default_rng(21)
    vv, ff = v, f
    kill = []
    for gone, (vid,) in _places(v, f, rng, 2, lambda vid: (_vertex_fan(f, vid)[:1], [vid])):
        kill.extend(gone.tolist())
        vv, ff, at_tip = _ball_at(vv, ff, vid, 0.002)
        kill.append(at_tip)
    keep = np.ones(len(ff), bool)
    keep[kill] = False
    ff = ff[keep]
    assert len(nonmanifold_vertices(ff, len(vv))) == 2
    got = _quantities(vv, ff)
    assert "split 2 non-manifold vertex(es) where separate sheets meet" in got["log"]
    dropped = [x for x in got["log"] if x.startswith("dropped") and "loose piece" in x]
    assert all("(1280 faces" in x or "(2560 faces" in x for x in dropped)   # a ball's faces are counted
    _assert_close(got, ref)


def _island(f, a, b):
    """Faces to delete so that the two faces on edge a-b stay as an island joined to the rest
    at a and b only: every other face around their far corners goes."""
    on_ab = np.flatnonzero(np.isin(f, [a, b]).sum(axis=1) == 2)
    far = [int(np.setdiff1d(f[k], [a, b])[0]) for k in on_ab]
    around = np.flatnonzero(np.isin(f, far).any(axis=1))
    return np.setdiff1d(around, on_ab)


def _island_at(f, rng):
    """Damage maker for :func:`_places`: an island at an edge of the vertex. The repair drops
    the two-face island as a loose fragment (it shares no edge with the rest), so the hole
    it must close is the island's and the two holes' together."""
    def make(vid):
        ring = _ring(f, [vid])
        b = int(rng.choice(ring[ring != vid]))
        gone = _island(f, vid, b)
        on_ab = np.flatnonzero(np.isin(f, [vid, b]).sum(axis=1) == 2)
        return gone, np.unique(f[gone]), np.union1d(gone, on_ab)
    return make


def test_island_between_two_holes_sharing_two_vertices_is_walked_as_two_loops(scan):
    """hole_loops on its own: two holes either side of an island (the faces a-b-x and b-a-y),
    in one sheet (the fans at a and b face the same way), are taken as the two holes, one
    through a, x, b and the other through a, y, b, not as the rim around both and the
    island's own rim."""
    v, f, _ = scan
    rng = np.random.default_rng(11)
    ends = {}

    def make(vid):
        ring = _ring(f, [vid])
        b = int(rng.choice(ring[ring != vid]))
        ends[vid] = b
        return _island(f, vid, b), [vid, b]

    places = _places(v, f, rng, 6, make)
    assert len(places) == 6
    for gone, (a, b) in places:
        keep = np.ones(len(f), bool)
        keep[gone] = False
        ff = f[keep]
        x, y = (int(np.setdiff1d(t, [a, b])[0]) for t in f[np.isin(f, [a, b]).sum(axis=1) == 2])
        loops = [set(loop.tolist()) for loop in hole_loops(v, ff, edge_topology(ff, len(v)))]
        assert len(loops) == 2
        assert all({a, b} <= loop for loop in loops)
        assert sorted(len({x, y} & loop) for loop in loops) == [1, 1]


def test_two_holes_sharing_two_vertices_around_an_island(scan):
    """The full repair of islands: the two-face island is dropped as a loose fragment and the
    rim around it and both holes closed."""
    v, f, ref = scan
    rng = np.random.default_rng(3)
    keep = np.ones(len(f), bool)
    places = _places(v, f, rng, 4, _island_at(f, rng))
    for gone, *_ in places:
        keep[gone] = False
    ff = f[keep]
    assert len(places) == 4
    _assert_close(_quantities(v, ff), ref)


def test_island_on_the_column_gives_its_closed_form(col):
    v, f, ref = col
    rng = np.random.default_rng(6)
    keep = np.ones(len(f), bool)
    for gone, *_ in _places(v, f, rng, 3, _island_at(f, rng), axis=2):
        keep[gone] = False
    _assert_close(_quantities(v, f[keep], **COLUMN_OPTS), ref, tol=1e-3)


# ----------------------------------------------------------------------------- flat caps sharing a diagonal

def _pyramid(base, apex):
    """A closed pyramid: base polygon (k, 3) wound so that it faces away from ``apex``."""
    k = len(base)
    v = np.vstack([base, apex])
    f = [[i, (i + 1) % k, k] for i in range(k)]
    f += [[0, i + 1, i] for i in range(1, k - 1)][::-1]
    m = trimesh.Trimesh(v, f, process=False)
    if m.volume < 0:
        m.invert()
    return np.asarray(m.vertices), np.asarray(m.faces), float(m.volume)


@pytest.mark.parametrize("h1, h2", [(1.2, 0.9), (0.1, 0.08)], ids=["steep", "low"])
def test_two_pyramids_on_rhombi_sharing_a_diagonal(h1, h2):
    """Two pyramids on either side of the plane z = 0, on two rhombi that share their short
    diagonal a-b (then on four faces). Deleting those leaves two flat holes through a and b.
    Steep pyramids meet at a and b as one sheet (the union's surface): the holes are taken
    as the two flat pieces of the first rhombus outside the second. Low ones face opposite
    ways: each keeps its own hole, and a Delaunay cap of each would use a-b again (four
    faces again): the second is cut at the midpoint of a-b. Volume: the two pyramids."""
    s, l1, l2 = 0.3, 1.0, 0.7
    a, b = [0, -s, 0], [0, s, 0]
    v1, f1, vol1 = _pyramid(np.array([a, [l1, 0, 0], b, [-l1, 0, 0]], float), np.array([0.1, 0.05, h1]))
    v2, f2, vol2 = _pyramid(np.array([a, [0.2, 0, 0], b, [-l2, 0, 0]], float), np.array([-0.2, 0.0, -h2]))
    assert vol1 == pytest.approx(2 * s * l1 * h1 / 3) and vol2 == pytest.approx(s * (0.2 + l2) * h2 / 3)
    v = np.vstack([v1, v2])
    f = np.vstack([f1, f2 + len(v1)])
    res = repair_mesh(v, f)                               # welding makes a-b one edge on four faces
    assert "deleted 4 faces on 1 non-manifold edge(s)" in res.log
    _assert_closed(res.vertices, res.faces)
    assert trimesh.Trimesh(res.vertices, res.faces, process=False).volume == pytest.approx(vol1 + vol2, rel=1e-9)


def test_fill_never_reuses_an_edge_of_another_cap():
    """fill_holes on its own, on the low pyramids with the faces on a-b deleted: both flat
    holes are capped, one of them cut at the midpoint of a-b; every edge on two faces."""
    s = 0.3
    a, b = [0, -s, 0], [0, s, 0]
    v1, f1, _ = _pyramid(np.array([a, [1, 0, 0], b, [-1, 0, 0]], float), np.array([0, 0, 0.1]))
    v2, f2, _ = _pyramid(np.array([a, [0.5, 0, 0], b, [-0.5, 0, 0]], float), np.array([0, 0, -0.1]))
    v = np.vstack([v1, v2[[1, 3, 4]]])                  # the second pyramid shares a (0) and b (2)
    f = np.vstack([f1, np.array([0, 5, 2, 6, 7])[f2]])
    assert edge_topology(f, len(v)).n_nonmanifold == 1
    f = f[np.isin(f, [0, 2]).sum(axis=1) < 2]           # what the repair deletes
    topo = edge_topology(f, len(v))
    loops = hole_loops(v, f, topo)
    assert sorted(sorted(loop.tolist()) for loop in loops) == [[0, 1, 2, 3], [0, 2, 5, 6]]   # a hole each
    vv, ff, holes = fill_holes(v, f, topo, max_perimeter=0.0, flat_tol=1e-9)
    assert [h.how for h in holes] == ["flat", "flat"]
    assert edge_topology(ff, len(vv)).is_closed
    assert len(vv) == len(v) + 1 and np.allclose(vv[-1], [0, 0, 0])   # the midpoint of a-b
    assert (np.isin(ff, [0, 2]).sum(axis=1) == 2).sum() == 2           # a-b itself: on one cap only


def test_fill_never_reuses_an_edge_of_the_mesh():
    """Two tetrahedra a-x-b-t1 and a-b-y-t2 joined along a-b, their bottoms (one flat quad
    a-x-b-y) missing: the Delaunay cap of the quad would add a-b, already on two faces. The
    cap is cut at the midpoint of a-b; the volume is the two tetrahedra's."""
    v = np.array([[0, -0.3, 0], [1, 0, 0], [0, 0.3, 0], [-1, 0, 0], [0.4, 0, 0.5], [-0.4, 0, 0.6]], float)
    a, x, b, y, t1, t2 = range(6)
    f = np.array([[a, t1, x], [x, t1, b], [b, t1, a], [b, t2, y], [y, t2, a], [a, t2, b]])
    if trimesh.Trimesh(v, np.vstack([f, [[a, x, b], [a, b, y]]]), process=False).volume < 0:
        f = f[:, ::-1]
    vol = sum(abs(np.linalg.det(np.array([v[p] - v[q[0]] for p in q[1:]]))) / 6
              for q in ([a, x, b, t1], [a, b, y, t2]))
    topo = edge_topology(f, len(v))
    vv, ff, holes = fill_holes(v, f, topo, max_perimeter=0.0, flat_tol=1e-9)
    assert [h.how for h in holes] == ["flat"]
    assert edge_topology(ff, len(vv)).is_closed
    assert len(vv) == 7 and np.allclose(vv[-1], [0, 0, 0])
    res = repair_mesh(v, f)
    _assert_closed(res.vertices, res.faces)
    assert trimesh.Trimesh(res.vertices, res.faces, process=False).volume == pytest.approx(vol, rel=1e-12)


def test_islands_on_a_flat_base_give_the_closed_form(col):
    """Islands on the column's flat base (dropped as fragments, the rims around them capped
    flat): the column's closed form to 1e-9."""
    v, f, ref = col
    rng = np.random.default_rng(9)
    base = np.flatnonzero((np.abs(v[:, 2]) < 1e-12) & (np.hypot(v[:, 0], v[:, 1]) < 0.2)
                          & (np.bincount(f.ravel(), minlength=len(v)) == 6))
    keep = np.ones(len(f), bool)
    chosen = []
    for vid in rng.permutation(base):
        ring = _ring(f, [vid])
        if any(np.isin(ring, _ring(f, _ring(f, [c]))).any() for c in chosen):
            continue
        keep[_island(f, int(vid), int(ring[ring != vid][0]))] = False
        chosen.append(vid)
        if len(chosen) == 4:
            break
    _assert_close(_quantities(v, f[keep], **COLUMN_OPTS), ref, tol=1e-9)


# ----------------------------------------------------------------------------- random damage (property)

def _damage(v, f, rng, nb):
    """A clean closed mesh damaged at random places, each apart from the others: bow ties of
    two to four holes at a vertex, islands between two holes sharing two vertices, sheets
    touching along a chain of 1-3 edges (non-manifold edges) and small patches of 1-4
    faces deleted (``nb``: :func:`_neighbours`). Returns the vertices, the faces and how many
    of each were made."""
    patterns = [(0, 3), (0, 2, 4), (0, 2), (0, 1, 3, 4), (0, 1, 3)]

    def bow_tie(vid):
        return _vertex_fan(f, vid)[list(patterns[int(rng.integers(len(patterns)))])], [vid]

    def sheet(vid):
        return _on_chain(f, _chain(v, nb, vid, int(rng.integers(1, 4))))

    def patch(vid):
        faces = [int(rng.choice(_vertex_fan(f, vid)))]
        for _ in range(int(rng.integers(0, 4))):
            near = np.flatnonzero(np.isin(f, f[faces]).sum(axis=1) == 2)
            faces.append(int(rng.choice(np.setdiff1d(near, faces))))
        return np.array(faces), np.unique(f[faces])

    kinds = [("bow tie", bow_tie, 4), ("island", _island_at(f, rng), 2), ("sheet", sheet, 2), ("patch", patch, 12)]
    free = np.ones(len(v), bool)
    keep = np.ones(len(f), bool)
    sheets, done = [], {}
    for name, make, count in kinds:
        places = _places(v, f, rng, count, make, free=free)
        done[name] = len(places)
        for gone, touched, *_ in places:
            if name == "sheet":
                sheets.append(np.asarray(touched))
            else:
                keep[gone] = False
    vv, ff = v, f[keep]
    for path in sheets:
        edge = float(np.linalg.norm(np.diff(v[path], axis=0), axis=1).mean())
        vv, ff, _ = _sheet_along(vv, ff, path, 1.5 * edge, rows=2)
    return vv, ff, done


@pytest.fixture(scope="module", params=SCANS + ("nefertiti_bust.obj",))
def any_scan(request):
    raw = read_scan(MESHES_DIR / request.param)
    rep = repair_mesh(raw.vertices, raw.faces)
    return rep.vertices, rep.faces, _quantities(rep.vertices, rep.faces), _neighbours(rep.faces, len(rep.vertices))


@given(seed=st.integers(0, 2**31 - 1))
@settings(max_examples=6, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
def test_random_damage_is_repaired_to_the_clean_body(any_scan, seed):
    """Property over seeds: random damage of every kind above, at several places of a real
    scan, is repaired to a closed 2-manifold with volume, h and a_min within 0.5 %."""
    v, f, ref, nb = any_scan
    vv, ff, done = _damage(v, f, np.random.default_rng(seed), nb)
    assert done["bow tie"] + done["island"] + done["sheet"] >= 4 and done["patch"] >= 6, done
    _assert_close(_quantities(vv, ff), ref)
