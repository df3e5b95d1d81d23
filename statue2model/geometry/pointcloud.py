"""Point clouds to closed surfaces (open3d, imported only here).

A scan that arrives as bare points (PLY without faces, PCD, XYZ) is meshed by
screened Poisson reconstruction, which yields a watertight surface when the
points cover the whole object (including its base). Normals are estimated from
the 30 nearest neighbours and oriented consistently before reconstruction.

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.pointcloud import reconstruct_surface
>>> rng = np.random.default_rng(0)
>>> p = rng.normal(size=(20000, 3)); p /= np.linalg.norm(p, axis=1, keepdims=True)
>>> v, f, note = reconstruct_surface(0.2 * p)
>>> note.startswith("reconstructed a surface from 20000 points")
True
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError


def _open3d():
    try:
        import open3d
    except ImportError as exc:  # also raised when libusb-1.0 is missing
        raise InputError(
            f"point clouds need open3d ({exc}); install it with 'pip install open3d' "
            "(on Debian/Ubuntu also 'apt-get install libusb-1.0-0')"
        ) from None
    return open3d


def read_points(path: Path) -> np.ndarray:
    """(n, 3) points of a PCD/XYZ/PTS/PLY point cloud file."""
    o3d = _open3d()
    try:
        cloud = o3d.io.read_point_cloud(str(path))
    except Exception as exc:
        raise InputError(f"cannot read {path.name} as a point cloud: {exc}") from None
    points = np.asarray(cloud.points, dtype=float)
    if len(points) == 0:
        raise InputError(f"{path.name} holds no points (or is not a valid point cloud file)")
    return points


def reconstruct_surface(points: np.ndarray, depth: int = 8) -> tuple[np.ndarray, np.ndarray, str]:
    """Closed triangle surface through ``points`` ((n, 3), any unit): (vertices, faces, note)."""
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3:
        raise InputError("a point cloud needs three coordinates per point")
    if not np.isfinite(points).all():
        raise InputError(f"the point cloud has {int((~np.isfinite(points).all(axis=1)).sum())} points with NaN or infinite coordinates")
    if len(points) < 100:
        raise InputError(f"the point cloud has only {len(points)} points: too few to reconstruct a surface")
    o3d = _open3d()
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(30))
    cloud.orient_normals_consistent_tangent_plane(15)
    mesh, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=depth)
    vertices = np.asarray(mesh.vertices, dtype=float)
    faces = np.asarray(mesh.triangles, dtype=np.int64)
    if len(faces) == 0:
        raise InputError("surface reconstruction from the point cloud produced no triangles")
    note = f"reconstructed a surface from {len(points)} points (Poisson, depth {depth}, {len(faces)} faces)"
    return vertices, faces, note
