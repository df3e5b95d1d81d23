"""glTF 2.0 geometry (.glb and .gltf), Draco-compressed or not, read without trimesh.

Most public statue scans ship as GLB with ``KHR_draco_mesh_compression``; this
module reads the container itself so that nothing is guessed:

* GLB: the 12-byte header, the JSON chunk and the binary chunk (buffer 0);
  .gltf: the JSON, with buffers embedded as ``data:`` URIs or in files beside it.
  A buffer file is read only from the .gltf's own folder: absolute paths, '..',
  and schemes other than ``data:`` are refused.
* every triangle primitive (mode 4, 5 or 6; indexed or not) of every mesh that a
  node of the default scene places, with the node's transform (``matrix`` or
  translation/rotation/scale) composed down the node hierarchy, as trimesh does;
  faces are flipped under a mirroring transform. Point primitives (mode 0) are
  returned as points when the file has no triangles; lines are skipped.
* ``KHR_draco_mesh_compression`` primitives are decoded with DracoPy;
  ``KHR_mesh_quantization`` (integer and normalized positions) is applied.
* an extension in ``extensionsRequired`` that could change the geometry and is
  not one of these (``EXT_meshopt_compression``, ``EXT_mesh_gpu_instancing``, ...)
  is refused by name. Material, texture and light extensions do not touch the
  geometry and are ignored.

Lengths stay in the file's units (glTF says metres, but scans often ignore it).

Example
-------
>>> import json, struct, numpy as np
>>> from statue2model.geometry.gltf import glb_bytes, parse_glb
>>> pos = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
>>> tree = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36}],
...         "bufferViews": [{"buffer": 0, "byteLength": 36}],
...         "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
...         "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
...         "nodes": [{"mesh": 0, "translation": [0, 0, 5]}], "scenes": [{"nodes": [0]}]}
>>> g = parse_glb(glb_bytes(tree, pos.tobytes()), name="tri.glb")
>>> g.vertices[:, 2].tolist(), g.faces.tolist()
([5.0, 5.0, 5.0], [[0, 1, 2]])
"""
from __future__ import annotations

import base64
import json
import re
import struct
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote

import numpy as np

from ..errors import InputError
from ..io.inputs import open_input

DRACO = "KHR_draco_mesh_compression"
QUANTIZATION = "KHR_mesh_quantization"
SUPPORTED = {DRACO, QUANTIZATION}
"""Geometry extensions this reader implements."""

HARMLESS_PREFIXES = ("KHR_materials_", "KHR_texture_", "EXT_texture_", "MSFT_texture_", "KHR_lights_",
                     "EXT_lights_", "KHR_xmp", "KHR_techniques_", "KHR_animation_pointer")
"""Required extensions that only touch appearance, lights or metadata, never positions."""

_COMPONENT = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_NORMALIZE = {np.int8: 127.0, np.uint8: 255.0, np.int16: 32767.0, np.uint16: 65535.0}
_GLB_MAGIC, _JSON_CHUNK, _BIN_CHUNK = b"glTF", 0x4E4F534A, 0x004E4942


@dataclass(frozen=True)
class GltfGeometry:
    """Triangles (or points) of a glTF file, in the file's units and axes.

    vertices : (n, 3) float64, scene coordinates (node transforms applied)
    faces    : (f, 3) int64, or None when the file holds only points
    log      : what was read (primitive and node counts, Draco, skipped parts)
    """

    vertices: np.ndarray
    faces: np.ndarray | None
    log: tuple[str, ...]


def read_gltf(path: Path) -> GltfGeometry:
    """Geometry of a .glb or .gltf file (see the module docstring)."""
    path = Path(path)
    data = path.read_bytes()
    if data[:4] == _GLB_MAGIC:
        return parse_glb(data, name=path.name, folder=path.parent)
    if path.suffix.lower() == ".glb":
        raise InputError(f"cannot read {path.name}: not a GLB file (it does not start with 'glTF')")
    try:
        tree = json.loads(data.decode("utf-8-sig"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise InputError(f"cannot read {path.name}: not glTF JSON ({exc})".splitlines()[0]) from None
    return _geometry(tree, None, path.name, path.parent)


def parse_glb(data: bytes, *, name: str = "scan.glb", folder: Path | None = None) -> GltfGeometry:
    """Geometry of GLB bytes; ``folder`` is where external buffers may be read from."""
    if len(data) < 20 or data[:4] != _GLB_MAGIC:
        raise InputError(f"cannot read {name}: not a GLB file")
    version, length = struct.unpack_from("<II", data, 4)
    if version != 2:
        raise InputError(f"{name} is glTF version {version}: only glTF 2.0 can be read; re-export it as glTF 2.0")
    if length > len(data):
        raise InputError(f"cannot read {name}: the file is truncated ({len(data)} of {length} bytes)")
    chunks, at = [], 12
    while at + 8 <= length:
        size, kind = struct.unpack_from("<II", data, at)
        if at + 8 + size > length:
            raise InputError(f"cannot read {name}: a GLB chunk runs past the end of the file")
        chunks.append((kind, data[at + 8:at + 8 + size]))
        at += 8 + size
    if not chunks or chunks[0][0] != _JSON_CHUNK:
        raise InputError(f"cannot read {name}: the GLB has no JSON chunk first")
    try:
        tree = json.loads(chunks[0][1].decode("utf-8-sig"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise InputError(f"cannot read {name}: bad JSON in the GLB ({exc})".splitlines()[0]) from None
    binary = next((c for k, c in chunks[1:] if k == _BIN_CHUNK), None)
    return _geometry(tree, binary, name, folder)


def glb_bytes(tree: dict, binary: bytes = b"") -> bytes:
    """A GLB container around a glTF JSON ``tree`` and its binary chunk (both padded to 4 bytes)."""
    js = json.dumps(tree, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    binary = binary + b"\0" * (-len(binary) % 4)
    body = struct.pack("<II", len(js), _JSON_CHUNK) + js
    if binary:
        body += struct.pack("<II", len(binary), _BIN_CHUNK) + binary
    return _GLB_MAGIC + struct.pack("<II", 2, 12 + len(body)) + body


def check_extensions(tree: dict, name: str) -> None:
    """Refuse a file whose required extensions could change the geometry and are not supported."""
    required = tree.get("extensionsRequired") or []
    for ext in required:
        if ext in SUPPORTED or str(ext).startswith(HARMLESS_PREFIXES):
            continue
        hint = " without compression" if "compress" in str(ext).lower() or "meshopt" in str(ext).lower() else " without it"
        raise InputError(f"{name} needs the glTF extension {ext}, which statue2model cannot read: re-export it{hint}")


def _geometry(tree, binary: bytes | None, name: str, folder: Path | None) -> GltfGeometry:
    if not isinstance(tree, dict):
        raise InputError(f"cannot read {name}: the glTF JSON is not an object")
    version = str((tree.get("asset") or {}).get("version", ""))
    if not version.startswith("2"):
        raise InputError(f"{name} is glTF version {version or 'unknown'}: only glTF 2.0 can be read; re-export it as glTF 2.0")
    check_extensions(tree, name)
    try:
        return _Reader(tree, binary, name, folder).run()
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(f"cannot read {name}: malformed glTF ({type(exc).__name__}: {exc})".splitlines()[0]) from None


class _Reader:
    def __init__(self, tree: dict, binary: bytes | None, name: str, folder: Path | None):
        self.tree, self.binary, self.name, self.folder = tree, binary, name, folder
        self.buffers: dict[int, bytes] = {}

    # -- bytes -------------------------------------------------------------------
    def buffer(self, i: int) -> bytes:
        if i not in self.buffers:
            spec = self.tree["buffers"][i]
            uri = spec.get("uri")
            if uri is None:
                if i != 0 or self.binary is None:
                    raise InputError(f"cannot read {self.name}: buffer {i} has no data (no uri and no GLB binary chunk)")
                data = self.binary
            else:
                data = self._uri(uri)
            if len(data) < int(spec.get("byteLength", 0)):
                raise InputError(f"cannot read {self.name}: buffer {i} holds {len(data)} bytes, "
                                 f"{spec['byteLength']} declared")
            self.buffers[i] = data
        return self.buffers[i]

    def _uri(self, uri: str) -> bytes:
        if uri.startswith("data:"):
            head, _, payload = uri.partition(",")
            if not head.endswith(";base64"):
                raise InputError(f"cannot read {self.name}: a data: buffer that is not base64")
            try:
                return base64.b64decode(payload, validate=False)
            except ValueError:
                raise InputError(f"cannot read {self.name}: a data: buffer is not valid base64") from None
        rel = unquote(uri)
        parts = re.split(r"[\\/]", rel)
        if re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:", rel) or rel.startswith(("/", "\\")) or ".." in parts:
            raise InputError(
                f"{self.name} points to the buffer '{uri}', which statue2model will not open: "
                "only files beside the .gltf (no absolute path, '..' or URL scheme) or embedded data: buffers"
            )
        if self.folder is None:
            raise InputError(f"cannot read {self.name}: it refers to an external buffer '{uri}'")
        folder = self.folder.resolve()
        target = (folder / rel).resolve()
        if folder not in target.parents:
            raise InputError(f"{self.name} points to the buffer '{uri}' outside its folder: refused")
        if not target.exists():
            raise InputError(f"{self.name} needs the buffer file '{uri}', which is missing beside it")
        with open_input(target, f"{self.name}'s buffer file") as f:    # a regular file only (never a FIFO)
            return f.read()

    def view(self, i: int) -> tuple[bytes, int, int | None]:
        """(buffer bytes, start offset, byteStride) of bufferView ``i`` (bounds checked)."""
        v = self.tree["bufferViews"][i]
        data = self.buffer(int(v["buffer"]))
        start, length = int(v.get("byteOffset", 0)), int(v["byteLength"])
        if start < 0 or length < 0 or start + length > len(data):
            raise InputError(f"cannot read {self.name}: bufferView {i} runs past the end of its buffer")
        return data[:start + length], start, v.get("byteStride")

    def accessor(self, i: int) -> np.ndarray:
        """(count, width) array of accessor ``i``, normalized integers scaled to [-1, 1] or [0, 1]."""
        a = self.tree["accessors"][i]
        dtype = np.dtype(_COMPONENT[int(a["componentType"])])
        width, count = _WIDTH[a["type"]], int(a["count"])
        if "bufferView" in a:
            data, start, stride = self.view(int(a["bufferView"]))
            start += int(a.get("byteOffset", 0))
            item = dtype.itemsize * width
            stride = int(stride or item)
            if count and start + stride * (count - 1) + item > len(data):
                raise InputError(f"cannot read {self.name}: accessor {i} runs past the end of its bufferView")
            raw = np.frombuffer(data, np.uint8, count=stride * (count - 1) + item if count else 0, offset=start)
            if count:
                rows = np.lib.stride_tricks.as_strided(raw, (count, item), (stride, 1))
                out = np.ascontiguousarray(rows).view(dtype).reshape(count, width)
            else:
                out = np.zeros((0, width), dtype)
        else:
            out = np.zeros((count, width), dtype)
        if "sparse" in a:
            out = out.copy()
            sp = a["sparse"]
            n = int(sp["count"])
            idx = self._plain(sp["indices"], np.dtype(_COMPONENT[int(sp["indices"]["componentType"])]), 1, n)
            vals = self._plain(sp["values"], dtype, width, n)
            out[idx.ravel().astype(np.int64)] = vals
        if a.get("normalized") and dtype.type in _NORMALIZE:
            return np.maximum(out.astype(np.float64) / _NORMALIZE[dtype.type], -1.0)
        return out

    def _plain(self, spec: dict, dtype: np.dtype, width: int, count: int) -> np.ndarray:
        data, start, _ = self.view(int(spec["bufferView"]))
        start += int(spec.get("byteOffset", 0))
        if start + dtype.itemsize * width * count > len(data):
            raise InputError(f"cannot read {self.name}: a sparse accessor runs past its bufferView")
        return np.frombuffer(data, dtype, count=width * count, offset=start).reshape(count, width)

    # -- primitives ------------------------------------------------------------------
    def primitive(self, prim: dict) -> tuple[np.ndarray, np.ndarray | None, bool]:
        """(positions (n, 3) float64, faces (f, 3) or None for points, was Draco)."""
        mode = int(prim.get("mode", 4))
        ext = (prim.get("extensions") or {}).get(DRACO)
        if ext is not None:
            pos, idx = self.draco(ext, prim)
            if idx is None and mode != 0:  # a Draco point cloud in a triangle primitive
                return pos[:0], np.zeros((0, 3), np.int64), True
        else:
            pos = self.accessor(int(prim["attributes"]["POSITION"]))
            idx = self.accessor(int(prim["indices"])).ravel() if "indices" in prim else None
        pos = np.asarray(pos, dtype=np.float64).reshape(-1, 3)
        if mode == 0:
            return (pos if idx is None else pos[idx.astype(np.int64)]), None, ext is not None
        if mode not in (4, 5, 6):
            return pos[:0], np.zeros((0, 3), np.int64), ext is not None
        idx = np.arange(len(pos), dtype=np.int64) if idx is None else np.asarray(idx, dtype=np.int64).ravel()
        if idx.size and (idx.min() < 0 or idx.max() >= len(pos)):
            raise InputError(f"cannot read {self.name}: a primitive's indices point past its {len(pos)} vertices")
        if mode == 4:
            faces = idx[: len(idx) // 3 * 3].reshape(-1, 3)
        elif mode == 5:  # strip: every other triangle reversed to keep the winding
            k = np.arange(max(len(idx) - 2, 0))
            odd = k % 2 == 1
            faces = np.column_stack([idx[k + odd], idx[k + 1 - odd], idx[k + 2]])
        else:  # fan around the first vertex
            k = np.arange(1, max(len(idx) - 1, 1))
            faces = np.column_stack([idx[k], idx[k + 1], np.full(len(k), idx[0] if len(idx) else 0)])
        return pos, faces, ext is not None

    def draco(self, ext: dict, prim: dict) -> tuple[np.ndarray, np.ndarray | None]:
        try:
            import DracoPy
        except ImportError as exc:
            raise InputError(f"{self.name} is Draco-compressed and needs DracoPy ({exc}): "
                             "pip install DracoPy") from None
        data, start, _ = self.view(int(ext["bufferView"]))
        try:
            decoded = DracoPy.decode(data[start:])
        except Exception as exc:  # DracoPy raises its own failure types
            raise InputError(f"cannot read {self.name}: Draco decoding failed ({exc})".splitlines()[0]) from None
        uid = int(ext["attributes"]["POSITION"])
        found = [a for a in decoded.attributes if int(a["unique_id"]) == uid]
        if found:
            pos = np.asarray(found[0]["data"]).reshape(-1, 3)
        else:
            pos = np.asarray(decoded.points).reshape(-1, 3)
        acc = self.tree["accessors"][int(prim["attributes"]["POSITION"])]
        if acc.get("normalized") and pos.dtype.type in _NORMALIZE:
            pos = np.maximum(pos.astype(np.float64) / _NORMALIZE[pos.dtype.type], -1.0)
        faces = getattr(decoded, "faces", None)
        if faces is None or len(faces) == 0:
            return pos, None
        return pos, np.asarray(faces, dtype=np.int64).ravel()

    # -- scene -----------------------------------------------------------------------
    def placements(self) -> list[tuple[int, np.ndarray]]:
        """(mesh index, 4x4 world matrix) for every mesh the default scene places."""
        nodes = self.tree.get("nodes") or []
        scenes = self.tree.get("scenes") or []
        if scenes:
            roots = scenes[int(self.tree.get("scene", 0))].get("nodes", [])
        elif nodes:
            children = {int(c) for n in nodes for c in n.get("children", [])}
            roots = [i for i in range(len(nodes)) if i not in children]
        else:
            return [(m, np.eye(4)) for m in range(len(self.tree.get("meshes") or []))]
        out: list[tuple[int, np.ndarray]] = []
        stack = [(int(r), np.eye(4), frozenset()) for r in roots]
        while stack:
            i, parent, seen = stack.pop()
            if i in seen:
                raise InputError(f"cannot read {self.name}: the node hierarchy has a cycle")
            node = nodes[i]
            world = parent @ _local_matrix(node)
            if "mesh" in node:
                out.append((int(node["mesh"]), world))
            stack.extend((int(c), world, seen | {i}) for c in node.get("children", []))
        return out

    def run(self) -> GltfGeometry:
        meshes = self.tree.get("meshes") or []
        tri_v, tri_f, pts = [], [], []
        n_prim = n_draco = n_skipped = 0
        offset = 0
        cache: dict[int, list] = {}
        placements = self.placements()
        for mesh_i, world in placements:
            if mesh_i not in cache:
                cache[mesh_i] = [self.primitive(p) for p in meshes[mesh_i].get("primitives", [])]
            for pos, faces, was_draco in cache[mesh_i]:
                n_prim += 1
                n_draco += was_draco
                v = pos @ world[:3, :3].T + world[:3, 3]
                if faces is None:
                    pts.append(v)
                    continue
                if len(faces) == 0:
                    n_skipped += 1
                    continue
                if np.linalg.det(world[:3, :3]) < 0:
                    faces = faces[:, ::-1]  # a mirroring transform turns the winding inside out
                tri_v.append(v)
                tri_f.append(faces + offset)
                offset += len(v)
        log = [f"read glTF: {n_prim} primitive(s) placed by {len(placements)} node(s)"
               + (f", {n_draco} Draco-compressed" if n_draco else "")]
        if n_skipped:
            log.append(f"skipped {n_skipped} glTF primitive(s) without triangles (lines or empty)")
        if tri_f:
            if pts:
                log.append(f"ignored {sum(len(p) for p in pts)} loose glTF points next to the triangles")
            return GltfGeometry(np.vstack(tri_v), np.vstack(tri_f), tuple(log))
        if pts:
            return GltfGeometry(np.vstack(pts), None, tuple(log))
        raise InputError(f"{self.name} holds no triangle mesh")


def _local_matrix(node: dict) -> np.ndarray:
    """4x4 local transform of a glTF node: ``matrix`` (column-major) or T @ R @ S."""
    if "matrix" in node:
        return np.asarray(node["matrix"], dtype=np.float64).reshape(4, 4).T
    m = np.eye(4)
    x, y, z, w = (float(c) for c in node.get("rotation", (0.0, 0.0, 0.0, 1.0)))
    n = x * x + y * y + z * z + w * w
    s = 2.0 / n if n > 0 else 0.0
    m[:3, :3] = [
        [1 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)],
        [s * (x * y + z * w), 1 - s * (x * x + z * z), s * (y * z - x * w)],
        [s * (x * z - y * w), s * (y * z + x * w), 1 - s * (x * x + y * y)],
    ]
    m[:3, :3] = m[:3, :3] * np.asarray(node.get("scale", (1.0, 1.0, 1.0)), dtype=np.float64)
    m[:3, 3] = node.get("translation", (0.0, 0.0, 0.0))
    return m
