"""Reading and cleaning raw scans: each repair says what it did, and a mesh that
cannot be closed is refused."""
import numpy as np
import pytest
import trimesh

from statue2model.errors import InputError
from statue2model.geometry.body import body_from_mesh, load_body
from statue2model.geometry.repair import repair_mesh
from statue2model.geometry.scan import read_scan
from statue2model.io.paths import MESHES_DIR, default_scan


def _volume(res):
    return trimesh.Trimesh(res.vertices, res.faces, process=False).volume


def test_default_scan_drops_its_sliver_and_stands_y_up():
    body = load_body(default_scan())
    assert any("loose fragment" in s for s in body.log)
    assert body.up == "+y" and body.units == "m"
    assert body.height == pytest.approx(1.80, abs=0.005)
    assert body.vertices[:, 2].min() == 0.0
    assert body.footprint.contains(body.mass.com[:2]) > 0.1  # well inside a 0.6 m plinth
    assert not body.warnings


def test_bundled_scans_units_and_axes():
    nef = load_body(MESHES_DIR / "nefertiti_bust.obj")
    assert nef.units == "mm" and nef.up == "+y"
    assert 0.4 < nef.height < 0.6
    maria = load_body(MESHES_DIR / "maria_barjatinskaja.ply")
    assert maria.up == "+y" and maria.height == pytest.approx(1.878, abs=0.005)


def test_welds_an_unwelded_stl(tmp_path):
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    path = tmp_path / "box.stl"
    box.export(path)  # STL stores three vertices per face
    raw = read_scan(path)
    assert len(raw.vertices) == 36
    body = body_from_mesh(raw.vertices, raw.faces)
    assert any("welded 28 duplicate vertices" in s for s in body.log)
    assert body.mass.volume == pytest.approx(0.2 * 0.3 * 0.9, rel=1e-6)  # STL stores float32


@pytest.mark.parametrize("suffix", [".obj", ".ply", ".off", ".glb", ".stl"])
def test_reads_every_mesh_format(tmp_path, suffix):
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    path = tmp_path / f"box{suffix}"
    box.export(path)
    body = load_body(path, up="z")
    assert body.mass.volume == pytest.approx(0.054, rel=1e-6)


def test_closes_a_small_hole_and_a_flat_open_base():
    sphere = trimesh.creation.icosphere(4, radius=0.5)
    res = repair_mesh(sphere.vertices, sphere.faces[1:])
    assert res.log[0].startswith("closed 1 hole (0 small, 1 flat;")
    assert res.log[-1].startswith("checked: a closed 2-manifold")
    cyl = trimesh.creation.cylinder(radius=0.2, height=1.0, sections=48)
    bottom = cyl.triangles_center[:, 2] < -0.499
    res = repair_mesh(cyl.vertices, cyl.faces[~bottom])
    assert res.log[0].startswith("closed 1 hole (0 small, 1 flat;")
    assert _volume(res) == pytest.approx(cyl.volume, rel=1e-12)


def test_closes_a_small_curved_hole_with_a_fan():
    sphere = trimesh.creation.icosphere(4, radius=0.5)
    pair = sphere.face_adjacency[0]  # two neighbouring faces: a 4-vertex, non-planar hole
    keep = np.ones(len(sphere.faces), bool)
    keep[pair] = False
    res = repair_mesh(sphere.vertices, sphere.faces[keep])
    assert res.log[0].startswith("closed 1 hole (1 small, 0 flat;")
    assert _volume(res) == pytest.approx(sphere.volume, rel=1e-3)


def test_refuses_a_large_curved_opening():
    sphere = trimesh.creation.icosphere(4, radius=0.5)
    c = sphere.triangles_center
    bite = np.linalg.norm(c - [0.5, 0, 0], axis=1) < 0.45
    with pytest.raises(InputError, match="not a closed volume"):
        repair_mesh(sphere.vertices, sphere.faces[~bite])


def test_fixes_inverted_and_inconsistent_winding():
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    res = repair_mesh(box.vertices, box.faces[:, ::-1])
    assert res.log == ("turned 1 inside-out component(s) outward",)
    assert _volume(res) == pytest.approx(0.054, rel=1e-12)
    f = box.faces.copy()
    f[3] = f[3][::-1]
    res = repair_mesh(box.vertices, f)
    assert "made the face winding consistent" in res.log
    assert _volume(res) == pytest.approx(0.054, rel=1e-12)


def test_drops_degenerate_and_repeated_faces():
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    f = np.vstack([box.faces, box.faces[[2]][:, [1, 2, 0]], [[0, 0, 1]]])
    res = repair_mesh(box.vertices, f)
    assert res.log == ("dropped 1 degenerate faces", "dropped 1 duplicate faces")
    assert len(res.faces) == 12
    assert _volume(res) == pytest.approx(0.054, rel=1e-12)


def test_refuses_two_coarse_boxes_joined_at_an_edge():
    a = trimesh.creation.box(extents=(1, 1, 1))
    b = a.copy()
    b.apply_translation((1, 0, 0))
    c = a.copy()
    c.apply_translation((0, 0, 1))
    d = b.copy()
    d.apply_translation((0, 0, 1))  # two boxes touching along one edge only
    mesh = trimesh.util.concatenate([a, d])
    with pytest.raises(InputError, match="after deleting .* faces around non-manifold edges"):
        repair_mesh(mesh.vertices, mesh.faces)


@pytest.mark.slow
def test_point_cloud_is_reconstructed(tmp_path):
    """A cylinder sampled as bare points (XYZ and face-less PLY) becomes a closed body."""
    rng = np.random.default_rng(1)
    r, h, n = 0.1, 0.3, 12000
    side = int(n * (2 * np.pi * r * h) / (2 * np.pi * r * h + 2 * np.pi * r * r))
    t = rng.uniform(0, 2 * np.pi, side)
    pts = [np.column_stack([r * np.cos(t), r * np.sin(t), rng.uniform(0, h, side)])]
    for z in (0.0, h):
        k = (n - side) // 2
        rr, tt = r * np.sqrt(rng.uniform(0, 1, k)), rng.uniform(0, 2 * np.pi, k)
        pts.append(np.column_stack([rr * np.cos(tt), rr * np.sin(tt), np.full(k, z)]))
    pts = np.vstack(pts)
    xyz = tmp_path / "cyl.xyz"
    np.savetxt(xyz, pts)
    body = load_body(xyz, up="z")
    assert body.kind == "point cloud"
    assert any("reconstructed a surface" in s for s in body.log)
    # Poisson rounds the rims: volume and height within a few per cent
    assert body.mass.volume == pytest.approx(np.pi * r * r * h, rel=0.05)
    assert body.height == pytest.approx(h, rel=0.03)
    ply = tmp_path / "cyl.ply"
    trimesh.PointCloud(pts).export(ply)
    assert load_body(ply, up="z").kind == "point cloud"
