"""Reading scans: triangle meshes through trimesh, point clouds through open3d.

Supported: meshes .stl .obj .ply .off, glTF 2.0 .glb .gltf (read by
:mod:`statue2model.geometry.gltf`, Draco-compressed or not); point clouds .ply
(vertices only) .pcd .xyz .xyzn .pts, and glTF point primitives. A point cloud is
turned into a closed surface by Poisson reconstruction
(:mod:`statue2model.geometry.pointcloud`), which imports open3d only on that path.

Example
-------
>>> from statue2model.geometry.scan import read_scan
>>> from statue2model.io.paths import default_scan
>>> raw = read_scan(default_scan())
>>> raw.kind, raw.faces.shape
('mesh', (19294, 3))
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..compute.interrupts import checked_import, interrupt_checkpoint
from ..errors import InputError
from ..io.inputs import input_problem, open_input
from .gltf import read_gltf

if TYPE_CHECKING:
    from .pointcloud import Reconstruction

MESH_SUFFIXES = (".stl", ".obj", ".ply", ".off", ".glb", ".gltf")
"""File types read as a surface mesh."""
CLOUD_SUFFIXES = (".pcd", ".xyz", ".xyzn", ".pts")
"""File types read as a point cloud (meshed with open3d, the ``[pointcloud]`` extra)."""
GLTF_SUFFIXES = (".glb", ".gltf")
SCAN_SUFFIXES = MESH_SUFFIXES + CLOUD_SUFFIXES
"""Every file type a scan may have: the one list (folder runs, the command line, :func:`load_scan`)."""


@dataclass(frozen=True)
class RawScan:
    """What a file holds, in the file's own units and axes.

    vertices : (n, 3) float
    faces    : (f, 3) int (a point cloud's reconstructed surface for kind 'point cloud')
    kind     : 'mesh' or 'point cloud'
    log      : what was done while reading (warnings too, prefixed 'warning:')
    warnings : what the user should check (the same lines without the prefix)
    reconstruction : for a point cloud, the surface and its point-to-surface distances
    """

    path: Path
    vertices: np.ndarray
    faces: np.ndarray
    kind: str
    log: tuple[str, ...]
    warnings: tuple[str, ...] = ()
    reconstruction: Reconstruction | None = None


def _check_file(path: Path) -> None:
    problem = input_problem(path)
    if problem == "not found":
        raise InputError(f"file not found: {path}")
    if problem is not None:
        raise InputError(f"{path}: {problem}")
    if path.stat().st_size == 0:
        raise InputError(f"file is empty: {path}")
    suffix = path.suffix.lower()
    if suffix not in SCAN_SUFFIXES:
        known = ", ".join(sorted(SCAN_SUFFIXES))
        raise InputError(f"unsupported file type '{suffix or path.name}': use one of {known}")


class _NoFiles:
    """A trimesh resolver that opens nothing: a scan's references to other files (an OBJ's
    ``mtllib``, a PLY's texture) name paths statue2model does not trust or need (materials and
    textures play no part in the geometry), so they are never resolved."""

    def get(self, name):
        raise OSError(f"statue2model does not open files a scan refers to ({name})")

    __getitem__ = get

    def keys(self):
        return []


def _load_trimesh(path: Path):
    # trimesh catches BaseException around its optional imports and in its loaders: a Ctrl-C
    # landing there would be dropped and the command go on; the checkpoint raises it again
    trimesh = checked_import("trimesh")
    try:
        with open_input(path, "scan") as f, interrupt_checkpoint():   # a regular file only: never blocks on a FIFO
            loaded = trimesh.load(f, file_type=path.suffix.lower().lstrip("."), resolver=_NoFiles(),
                                  skip_materials=True, process=False)
    except InputError:
        raise
    except Exception as exc:  # trimesh raises many kinds on corrupt files
        raise InputError(f"cannot read {path.name}: {exc}".splitlines()[0]) from None
    if isinstance(loaded, trimesh.Scene):
        meshes = [g for g in loaded.dump() if isinstance(g, trimesh.Trimesh)]
        if not meshes:
            clouds = [g for g in loaded.dump() if isinstance(g, trimesh.PointCloud)]
            if clouds:
                return np.vstack([c.vertices for c in clouds]), None
            raise InputError(f"{path.name} holds no triangle mesh")
        loaded = trimesh.util.concatenate(meshes)
    if isinstance(loaded, trimesh.PointCloud):
        return np.asarray(loaded.vertices, dtype=float), None
    if not isinstance(loaded, trimesh.Trimesh):
        raise InputError(f"{path.name} holds no triangle mesh")
    faces = np.asarray(loaded.faces)
    vertices = np.asarray(loaded.vertices, dtype=float)
    if len(faces) == 0:
        return vertices, None
    return vertices, faces


def read_scan(path: str | Path, *, poisson_depth: int | None = None) -> RawScan:
    """Read a mesh or a point cloud file (see the module docstring for formats).

    poisson_depth : octree depth for a point cloud's surface (None: from the point spacing).
    """
    path = Path(path)
    _check_file(path)
    suffix = path.suffix.lower()
    log: list[str] = []
    if suffix in CLOUD_SUFFIXES:
        points = None
    else:
        if suffix in GLTF_SUFFIXES:
            geo = read_gltf(path)
            points, faces = geo.vertices, geo.faces
            log.extend(geo.log)
        else:
            points, faces = _load_trimesh(path)
        if faces is not None:
            if len(points) == 0 or len(faces) == 0:
                raise InputError(f"{path.name} has no vertices")
            return RawScan(path, points, faces, "mesh", tuple(log))
    from .pointcloud import read_points, reconstruct

    if points is None:
        points = read_points(path)
    rec = reconstruct(points, depth=poisson_depth)
    return RawScan(path, rec.vertices, rec.faces, "point cloud", tuple(log) + rec.log, rec.warnings, rec)
