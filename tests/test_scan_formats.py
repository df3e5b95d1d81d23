"""Real scan formats in, right numbers out (issue [7]): Draco-compressed and quantized
glTF, point clouds meshed into closed bodies, and sizes no unit makes plausible."""
import base64
import json
import struct
import time

import DracoPy
import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from statue2model.errors import InputError
from statue2model.geometry.body import body_from_mesh, load_body
from statue2model.geometry.scan import read_scan
from statue2model.geometry.units import detect_units, resolve_units
from statue2model.io.paths import default_scan


# ---------------------------------------------------------------- glTF helpers


def _glb(tree: dict, binary: bytes) -> bytes:
    """A GLB 2.0 container: header, JSON chunk (space padded), BIN chunk (zero padded)."""
    js = json.dumps(tree).encode()
    js += b" " * (-len(js) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks


def _draco_tree(mesh: trimesh.Trimesh, nodes=None, required=("KHR_draco_mesh_compression",)):
    blob = DracoPy.encode(mesh.vertices, mesh.faces, quantization_bits=14)
    pos_id = next(a["unique_id"] for a in DracoPy.decode(blob).attributes if a["attribute_type"] == 0)
    tree = {
        "asset": {"version": "2.0"},
        "extensionsUsed": sorted(set(required) | {"KHR_draco_mesh_compression"}),
        "extensionsRequired": list(required),
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(blob)}],
        "accessors": [  # draco primitives keep their accessors, without bufferView
            {"componentType": 5126, "count": len(mesh.vertices), "type": "VEC3",
             "min": mesh.bounds[0].tolist(), "max": mesh.bounds[1].tolist()},
            {"componentType": 5125, "count": 3 * len(mesh.faces), "type": "SCALAR"},
        ],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0}, "indices": 1, "mode": 4,
            "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": pos_id}}},
        }]}],
        "nodes": nodes if nodes is not None else [{"mesh": 0}],
        "scene": 0,
    }
    tree["scenes"] = [{"nodes": [i for i in range(len(tree["nodes"]))
                                 if not any(i in n.get("children", []) for n in tree["nodes"])]}]
    return tree, blob


def _plain_tree(mesh: trimesh.Trimesh, uri=None):
    """Uncompressed glTF of ``mesh``: (tree, binary) with float32 positions and uint32 indices."""
    pos = mesh.vertices.astype(np.float32).tobytes()
    idx = mesh.faces.astype(np.uint32).tobytes()
    buffer = {"byteLength": len(pos) + len(idx)}
    if uri is not None:
        buffer["uri"] = uri
    tree = {
        "asset": {"version": "2.0"},
        "buffers": [buffer],
        "bufferViews": [{"buffer": 0, "byteLength": len(pos)}, {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(mesh.vertices), "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5125, "count": 3 * len(mesh.faces), "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    }
    return tree, pos + idx


def _volume(raw):
    m = trimesh.Trimesh(raw.vertices, raw.faces, process=False)
    assert m.is_watertight and m.is_winding_consistent
    return m.volume


# ---------------------------------------------------------------- Draco and glTF


def test_draco_glb_reads_like_the_uncompressed_mesh(tmp_path):
    ico = trimesh.creation.icosphere(3, radius=0.3)
    path = tmp_path / "scan.glb"
    path.write_bytes(_glb(*_draco_tree(ico)))
    raw = read_scan(path)
    assert raw.kind == "mesh" and len(raw.faces) == len(ico.faces)
    assert any("1 Draco-compressed" in s for s in raw.log)
    step = 0.6 / (2**14 - 1)  # 14-bit quantisation over the 0.6 m extent
    dist, _ = cKDTree(ico.vertices).query(raw.vertices)
    assert dist.max() <= step
    assert _volume(raw) == pytest.approx(ico.volume, rel=1e-3)


def test_draco_glb_loads_as_a_body(tmp_path):
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    path = tmp_path / "box.glb"
    path.write_bytes(_glb(*_draco_tree(box)))
    body = load_body(path, up="z")
    assert body.mass.volume == pytest.approx(0.054, rel=1e-3)
    assert body.height == pytest.approx(0.9, rel=1e-3)


def test_draco_glb_node_transforms_compose_down_the_hierarchy(tmp_path):
    ico = trimesh.creation.icosphere(2, radius=0.3)
    q = [0.0, 0.0, np.sin(np.pi / 4), np.cos(np.pi / 4)]  # glTF (x, y, z, w): 90 deg about z
    nodes = [
        {"name": "parent", "children": [1], "rotation": q, "scale": [2.0, 2.0, 2.0], "translation": [0, 0, 1.0]},
        {"name": "child", "mesh": 0, "translation": [1.0, 0.5, 0.0]},
        {"name": "mirrored copy", "mesh": 0, "matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1]},
    ]
    path = tmp_path / "moved.glb"
    path.write_bytes(_glb(*_draco_tree(ico, nodes)))
    raw = read_scan(path)
    parent = trimesh.transformations.compose_matrix(
        scale=[2, 2, 2], angles=[0, 0, np.pi / 2], translate=[0, 0, 1.0])
    first = ico.copy().apply_transform(parent @ trimesh.transformations.translation_matrix([1, 0.5, 0]))
    second = ico.copy().apply_translation([10, 0, 0])
    ref = trimesh.util.concatenate([first, second])
    assert np.allclose(raw.vertices.min(axis=0), ref.bounds[0], atol=1e-3)
    assert np.allclose(raw.vertices.max(axis=0), ref.bounds[1], atol=1e-3)
    assert _volume(raw) == pytest.approx(9 * ico.volume, rel=1e-3)  # x8 scaled, plus the mirrored copy outward
    near = raw.vertices[:, 0] < 5
    assert raw.vertices[near].mean(axis=0) == pytest.approx([-1, 2, 1], abs=1e-3)  # (1,.5,0) x2, turned, +z


@pytest.mark.parametrize("ext", ["EXT_meshopt_compression", "EXT_mesh_gpu_instancing"])
def test_unsupported_required_extension_is_named(tmp_path, ext):
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    path = tmp_path / "scan.glb"
    path.write_bytes(_glb(*_draco_tree(box, required=("KHR_draco_mesh_compression", ext))))
    with pytest.raises(InputError, match=f"scan.glb needs the glTF extension {ext}, which statue2model cannot read"):
        read_scan(path)


def test_appearance_extensions_do_not_stop_reading(tmp_path):
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    path = tmp_path / "scan.glb"
    path.write_bytes(_glb(*_draco_tree(box, required=("KHR_draco_mesh_compression", "KHR_materials_unlit"))))
    assert _volume(read_scan(path)) == pytest.approx(0.054, rel=1e-3)


def test_quantized_positions_with_a_stride(tmp_path):
    """KHR_mesh_quantization: normalized int16 positions (8-byte stride) scaled back by the node."""
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    half = 0.45
    pos = np.zeros((8, 4), np.int16)
    pos[:, :3] = np.round(box.vertices / half * 32767)
    idx = box.faces.astype(np.uint32)
    binary = pos.tobytes() + idx.tobytes()
    tree = {
        "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"], "buffers": [{"byteLength": len(binary)}],
        "bufferViews": [{"buffer": 0, "byteLength": pos.nbytes, "byteStride": 8},
                        {"buffer": 0, "byteOffset": pos.nbytes, "byteLength": idx.nbytes}],
        "accessors": [{"bufferView": 0, "componentType": 5122, "normalized": True, "count": 8, "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5125, "count": idx.size, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0, "scale": [half] * 3}], "scenes": [{"nodes": [0]}],
    }
    path = tmp_path / "quantized.glb"
    path.write_bytes(_glb(tree, binary))
    raw = read_scan(path)
    assert np.allclose(raw.vertices, box.vertices, atol=half / 32767)
    assert _volume(raw) == pytest.approx(0.054, rel=1e-4)


def test_gltf_with_an_external_bin_beside_it(tmp_path):
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    tree, binary = _plain_tree(box, uri="box%20data.bin")
    (tmp_path / "box data.bin").write_bytes(binary)
    (tmp_path / "box.gltf").write_text(json.dumps(tree))
    assert _volume(read_scan(tmp_path / "box.gltf")) == pytest.approx(0.054, rel=1e-6)
    embedded, _ = _plain_tree(box, uri="data:application/octet-stream;base64," + base64.b64encode(binary).decode())
    (tmp_path / "embedded.gltf").write_text(json.dumps(embedded))
    assert _volume(read_scan(tmp_path / "embedded.gltf")) == pytest.approx(0.054, rel=1e-6)


@pytest.mark.parametrize("uri", ["../box.bin", "sub/../../box.bin", "/etc/passwd", "C:/scans/box.bin",
                                 "file:///etc/passwd", "https://example.org/box.bin", "..%2Fbox.bin"])
def test_gltf_buffer_paths_outside_its_folder_are_refused(tmp_path, uri):
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.9))
    tree, binary = _plain_tree(box, uri=uri)
    (tmp_path / "box.bin").write_bytes(binary)
    inner = tmp_path / "inner"
    inner.mkdir()
    (inner / "scan.gltf").write_text(json.dumps(tree))
    with pytest.raises(InputError, match="which statue2model will not open") as exc:
        read_scan(inner / "scan.gltf")
    assert "\n" not in str(exc.value)


def test_gltf_missing_buffer_file(tmp_path):
    tree, _ = _plain_tree(trimesh.creation.box(), uri="gone.bin")
    (tmp_path / "scan.gltf").write_text(json.dumps(tree))
    with pytest.raises(InputError, match="needs the buffer file 'gone.bin'"):
        read_scan(tmp_path / "scan.gltf")


# ---------------------------------------------------------------- point clouds


@pytest.mark.slow
def test_point_cloud_sampled_on_the_default_scan_is_a_closed_body(tmp_path):
    mesh = trimesh.load(default_scan(), process=False)
    points, _ = trimesh.sample.sample_surface(mesh, 30000, seed=0)
    path = tmp_path / "dancing_girl.xyz"
    np.savetxt(path, points)
    start = time.perf_counter()
    raw = read_scan(path)
    body = load_body(path)
    elapsed = time.perf_counter() - start
    print(f"30,000 points: read + body twice in {elapsed:.1f} s")
    assert raw.kind == "point cloud"
    assert _volume(raw) > 0
    rec = raw.reconstruction
    assert rec.median_relative < 0.001 and rec.p95_relative < 0.005  # measured 0.03 % and 0.17 %
    assert not raw.warnings and not any(s.startswith("warning:") for s in raw.log)
    assert "95th percentile" in raw.log[0]
    reference = load_body(default_scan())
    assert body.mass.volume == pytest.approx(reference.mass.volume, rel=0.03)
    assert body.height == pytest.approx(reference.height, rel=0.01)
    assert body.up == reference.up


@pytest.mark.slow
def test_noisy_point_cloud_is_flagged(tmp_path):
    rng = np.random.default_rng(3)
    p = rng.normal(size=(6000, 3))
    p = 0.2 * p / np.linalg.norm(p, axis=1, keepdims=True) + rng.normal(scale=0.01, size=p.shape)
    path = tmp_path / "noisy.xyz"
    np.savetxt(path, p)
    raw = read_scan(path)
    assert raw.reconstruction.p95_relative > 0.01
    assert len(raw.warnings) >= 1 and "from the reconstructed surface" in raw.warnings[0]
    assert "warning: " + raw.warnings[0] in raw.log


def test_flat_point_cloud_is_refused(tmp_path):
    rng = np.random.default_rng(0)
    path = tmp_path / "flat.xyz"
    np.savetxt(path, np.column_stack([rng.uniform(size=(2000, 2)), np.full(2000, 0.3)]))
    with pytest.raises(InputError, match="lie in one plane"):
        read_scan(path)


# ---------------------------------------------------------------- units


@pytest.mark.parametrize("extent", [9e29, 3e-9, 1e4 / 0.0254 * 1.01])
def test_no_plausible_unit_is_an_error(extent):
    with pytest.raises(InputError, match="none is a plausible size for a museum object") as exc:
        detect_units(extent)
    msg = str(exc.value)
    assert f"{extent:.3g} file units across" in msg and "pass --units or --height" in msg
    for u, s in (("m", 1.0), ("mm", 1e-3), ("cm", 1e-2), ("in", 0.0254)):
        assert f"{extent * s:.3g} m in {u}" in msg


def test_implausible_scan_is_refused_but_height_or_units_still_work():
    box = trimesh.creation.box(extents=(2e-9, 3e-9, 9e-9))
    with pytest.raises(InputError, match="none is a plausible size"):
        body_from_mesh(box.vertices, box.faces, up="z")
    body = body_from_mesh(box.vertices, box.faces, up="z", height=0.9)
    assert body.mass.volume == pytest.approx(0.054, rel=1e-6)
    tiny = trimesh.creation.box(extents=(0.004, 0.003, 0.009))  # a 9 mm object in m: 'auto' refuses it
    with pytest.raises(InputError, match="none is a plausible size"):
        body_from_mesh(tiny.vertices, tiny.faces, up="z")
    assert resolve_units("m", 0.03).sure is False  # but --units m accepts it, flagged


def test_several_units_fit_lists_each_size_and_flags_inches():
    choice = detect_units(70.0)  # a 70-unit statue: 7 cm in mm (too small to be taken), 0.7 m in cm, 1.78 m in in
    assert (choice.units, choice.sure) == ("cm", False)
    assert choice.note.startswith("units unsure: assumed cm (0.7 m across)")
    assert "in would give 1.78 m" in choice.note
    small = detect_units(130.0)  # 13 cm in mm, 1.3 m in cm, 3.3 m in inches
    assert small.units == "mm" and "cm would give 1.3 m" in small.note and "could be inches" in small.note
    wide = detect_units(400.0)  # 0.4 m in mm, 4 m in cm: not small, so no inch hint
    assert wide.units == "mm" and "cm would give 4 m" in wide.note and "could be inches" not in wide.note
    assert detect_units(1.8).sure and detect_units(494.0).sure


def test_provisional_scale_when_not_strict():
    choice = resolve_units("auto", 9e29, strict=False)
    assert choice.scale == pytest.approx(1 / 9e29) and not choice.sure
    with pytest.raises(InputError):
        resolve_units("auto", 9e29)
