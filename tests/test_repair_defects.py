"""One synthetic fixture per defect class that real scans show (twin faces, pinched
edges and vertices, messy scans with holes and loose shells, separate pieces,
cavities, repairs too large to trust): each is repaired to the known volume, with
its steps reported, or refused with a line naming the defect, its size and place."""
import numpy as np
import pytest
import trimesh

from statue2model.errors import InputError
from statue2model.geometry.body import body_from_mesh
from statue2model.geometry.repair import repair_mesh
from statue2model.geometry.topology import edge_topology, nonmanifold_vertices


def _sphere(sub=4, r=0.5):
    return trimesh.creation.icosphere(sub, radius=r)


def _volume(res):
    return float(trimesh.Trimesh(res.vertices, res.faces, process=False).volume)


def _assert_closed(res):
    topo = edge_topology(res.faces, len(res.vertices))
    assert topo.is_closed and topo.winding_consistent
    assert len(nonmanifold_vertices(res.faces, len(res.vertices))) == 0
    assert trimesh.Trimesh(res.vertices, res.faces, process=False).is_watertight


def test_twin_face_fin_is_removed_whole():
    """A zero-thickness fin: one triangle twice, opposite windings, on one surface edge."""
    s = _sphere()
    a, b = s.edges_unique[0]
    tip = len(s.vertices)
    v = np.vstack([s.vertices, s.vertices[a] * 1.3])
    f = np.vstack([s.faces, [[a, b, tip], [b, a, tip]]])
    res = repair_mesh(v, f)
    assert any("removed 1 twin face pair" in line for line in res.log)
    assert len(res.faces) == len(s.faces) and len(res.vertices) == len(s.vertices)   # the tip is gone too
    assert _volume(res) == pytest.approx(s.volume, rel=1e-12)
    _assert_closed(res)


def test_twin_of_a_surface_face_is_removed_and_the_gap_closed():
    s = _sphere()
    f = np.vstack([s.faces, s.faces[[7]][:, ::-1]])
    res = repair_mesh(s.vertices, f)
    assert any("twin face pair" in line for line in res.log)
    assert _volume(res) == pytest.approx(s.volume, rel=1e-12)   # a triangle is its own flat cap
    _assert_closed(res)


def test_flaps_on_edges_shared_by_three_and_four_faces_are_cut_out_and_closed():
    s = _sphere(5)
    rng = np.random.default_rng(0)
    edges = s.edges_unique[rng.choice(len(s.edges_unique), 6, replace=False)]
    v, f = [s.vertices], [s.faces]
    n = len(s.vertices)
    for k, (a, b) in enumerate(edges):
        v.append((s.vertices[a] * 1.02)[None])
        f.append([[a, b, n + k]])
    for k, (a, b) in enumerate(edges[::2]):   # a fourth face on every other edge
        v.append((s.vertices[b] * 1.03)[None])
        f.append([[b, a, n + len(edges) + k]])
    v, f = np.vstack(v), np.vstack(f)
    assert edge_topology(f, len(v)).n_nonmanifold == 6
    res = repair_mesh(v, f)
    line = next(x for x in res.log if x.startswith("deleted"))
    assert line == "deleted 21 faces on 6 non-manifold edge(s)"   # 3 x 3 faces + 3 x 4 faces
    assert any(x.startswith("closed") for x in res.log)
    assert res.log[-1].startswith("checked: a closed 2-manifold")
    assert _volume(res) == pytest.approx(s.volume, rel=2e-4)
    _assert_closed(res)


def test_two_holes_touching_at_a_vertex_are_closed_separately():
    """Two holes whose rims touch at one vertex (it has two fans of faces)."""
    s = _sphere(5)
    vf = s.vertex_faces[100]
    ring = vf[vf >= 0]
    # open two holes that touch only at vertex 100: delete two opposite faces of its fan
    kill = np.zeros(len(s.faces), bool)
    kill[ring[[0, 3]]] = True
    f = s.faces[~kill]
    assert 100 in nonmanifold_vertices(f, len(s.vertices))
    res = repair_mesh(s.vertices, f)
    assert res.log[0].startswith("closed 2 holes (0 small, 2 flat;")   # two triangles, not one bow-tie
    assert _volume(res) == pytest.approx(s.volume, rel=1e-4)
    _assert_closed(res)


def test_messy_scan_repaired_to_its_volume_with_every_step_reported():
    """Dozens of non-manifold edges, loose shells, flipped faces and 100+ boundary edges."""
    s = _sphere(5)
    rng = np.random.default_rng(3)
    v, f = [s.vertices], [s.faces.copy()]
    n = len(s.vertices)
    edges = s.edges_unique[rng.choice(len(s.edges_unique), 30, replace=False)]
    for k, (a, b) in enumerate(edges):           # 30 flaps: 30 non-manifold edges
        v.append((s.vertices[a] * 1.01)[None])
        f.append([[a, b, n + k]])
    f0 = f[0]
    holes = rng.choice(len(f0), 40, replace=False)   # 40 missing faces: 120 boundary edges
    keep = np.ones(len(f0), bool)
    keep[holes] = False
    flipped = rng.choice(np.flatnonzero(keep), 25, replace=False)
    f0[flipped] = f0[flipped][:, ::-1]                # inconsistent winding
    f[0] = f0[keep]
    off = n + len(edges)
    for k in range(4):                                # loose scraps: tiny closed tetrahedra and an open flap
        tet = trimesh.creation.icosphere(0, radius=0.004)
        v.append(tet.vertices + [0.7 + 0.02 * k, 0, 0])
        f.append(tet.faces + off)
        off += len(tet.vertices)
    v.append(np.array([[0, 0.8, 0], [0.01, 0.8, 0], [0, 0.81, 0]]))
    f.append([[off, off + 1, off + 2]])
    v, f = np.vstack(v), np.vstack(f)
    topo = edge_topology(f, len(v))
    assert topo.n_nonmanifold >= 30 and len(topo.boundary_edges) >= 100 and not topo.winding_consistent
    res = repair_mesh(v, f)
    text = "\n".join(res.log)
    for step in ("deleted", "non-manifold edge", "loose", "winding", "closed", "checked: a closed 2-manifold"):
        assert step in text
    assert _volume(res) == pytest.approx(s.volume, rel=2e-3)
    _assert_closed(res)


def test_floating_second_body_is_refused_with_its_size_and_place():
    a = trimesh.creation.box((0.3, 0.3, 0.3))
    b = a.copy()
    b.apply_translation((0, 0, 1.0))   # 0.7 m above the first
    m = trimesh.util.concatenate([a, b])
    with pytest.raises(InputError, match=r"1 piece\(s\) not joined to the main body .* centred at \(0, 0, 1\)"):
        repair_mesh(m.vertices, m.faces)
    with pytest.raises(InputError, match="not joined to the main body"):
        body_from_mesh(m.vertices, m.faces, units="m")


def test_small_floating_piece_is_dropped_with_a_count():
    a = trimesh.creation.box((0.3, 0.3, 0.6))
    b = trimesh.creation.box((0.03, 0.03, 0.03))     # 0.1 % of the volume, 0.2 m beside it
    b.apply_translation((0.4, 0, 0))
    m = trimesh.util.concatenate([a, b])
    res = repair_mesh(m.vertices, m.faces)
    assert any("dropped 1 loose piece(s) not joined to the body (12 faces, 0.050% of its volume)" in x
               or "dropped 1 loose fragment" in x for x in res.log)
    assert _volume(res) == pytest.approx(0.3 * 0.3 * 0.6, rel=1e-12)


def test_loose_piece_between_the_limits_is_dropped_by_the_shell_step():
    a = trimesh.creation.box((0.3, 0.3, 0.6))
    b = trimesh.creation.box((0.06, 0.06, 0.06))     # 0.4 % of the volume: above the fragment limit
    b.apply_translation((0.5, 0, 0))
    m = trimesh.util.concatenate([a, b])
    res = repair_mesh(m.vertices, m.faces)
    assert "dropped 1 loose piece(s) not joined to the body (12 faces, 0.400% of its volume)" in res.log
    assert _volume(res) == pytest.approx(0.054, rel=1e-12)


def test_plinth_touching_the_figure_face_to_face_is_united():
    plinth = trimesh.creation.box((0.6, 0.6, 0.2))
    figure = trimesh.creation.box((0.2, 0.2, 1.0))
    figure.apply_translation((0, 0, 0.6))            # stands on the plinth's top face
    m = trimesh.util.concatenate([plinth, figure])
    res = repair_mesh(m.vertices, m.faces)
    assert any(x.startswith("united 2") for x in res.log)
    assert _volume(res) == pytest.approx(0.6 * 0.6 * 0.2 + 0.2 * 0.2 * 1.0, rel=1e-9)
    _assert_closed(res)


@pytest.mark.parametrize("inner_inverted", [True, False])
def test_closed_shell_inside_the_body_is_a_cavity(inner_inverted):
    outer = trimesh.creation.box((1.0, 1.0, 1.0))
    inner = trimesh.creation.box((0.5, 0.5, 0.5))
    f_in = inner.faces[:, ::-1] if inner_inverted else inner.faces
    v = np.vstack([outer.vertices, inner.vertices])
    f = np.vstack([outer.faces, f_in + len(outer.vertices)])
    res = repair_mesh(v, f)
    assert "kept 1 closed shell(s) inside the body as cavities" in res.log
    assert _volume(res) == pytest.approx(1 - 0.125, rel=1e-12)


def test_a_fill_that_would_change_the_body_materially_is_refused():
    s = _sphere()
    bite = np.linalg.norm(s.triangles_center - [0.5, 0, 0], axis=1) < 0.45
    with pytest.raises(InputError, match=r"could change its volume by up to 1.09% \(limit 0.5%\).*centred at \(0.298"):
        repair_mesh(s.vertices, s.faces[~bite], max_hole=2.0)


def test_clean_scan_takes_the_fast_path():
    s = _sphere(5)
    res = repair_mesh(s.vertices, s.faces)
    assert res.log == () and res.warnings == ()
