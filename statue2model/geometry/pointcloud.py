"""Point clouds to closed surfaces (open3d, imported only here).

A scan that arrives as bare points (PLY without faces, PCD, XYZ) is meshed by
screened Poisson reconstruction, then cleaned until it is one closed,
edge- and vertex-manifold surface that the rest of the pipeline accepts:

1. normals from the 30 nearest neighbours, oriented consistently (tangent-plane graph);
2. Poisson at an octree depth chosen from the point spacing (voxel about two to
   four spacings, depth 6 to 9) unless one is given;
3. surface that Poisson invented away from the data is cut off: vertices farther
   than half a voxel (or half a point spacing) from every point *and* of low density (below the 2nd
   percentile of the supported vertices' densities), e.g. the balloon under a
   scan without its base;
4. degenerate and repeated triangles, non-manifold edges and vertices are cut
   out, only the largest connected piece is kept, and every hole left is closed
   by a fan to its centroid (repeated a few times);
5. the result must be closed with a positive volume; otherwise the next depths
   are tried, and if none works :class:`InputError` says what stayed open.

How well the surface follows the points is measured as the distance from each
point to the surface (median and 95th percentile, also relative to the points'
bounding-box diagonal); above :data:`WARN_P95` of the diagonal the result carries
a warning.

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.pointcloud import reconstruct
>>> rng = np.random.default_rng(0)
>>> p = rng.normal(size=(20000, 3)); p /= np.linalg.norm(p, axis=1, keepdims=True)
>>> r = reconstruct(0.2 * p)
>>> r.note.startswith("reconstructed a surface from 20000 points")
True
>>> r.p95_relative < 0.01, r.warnings
(True, ())
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, missing_extra

WARN_P95 = 0.01
"""95th percentile of the point-to-surface distance, as a fraction of the bounding-box
diagonal, above which the reconstruction is flagged."""

MAX_POINTS = 400_000
"""Larger clouds are thinned to this many points (a fixed random subset) before meshing."""

DEPTHS = (6, 9)
"""Range of Poisson octree depths tried."""

_ROUNDS = 8


@dataclass(frozen=True)
class Reconstruction:
    """A closed surface through a point cloud, and how closely it follows the points.

    vertices, faces : (n, 3) float and (f, 3) int, the points' units, outward winding
    depth           : Poisson octree depth used
    n_points        : points used (after thinning)
    median_distance, p95_distance : point-to-surface distances (the points' units)
    diagonal        : bounding-box diagonal of the points (the points' units)
    log             : what was done, one line each (the first is :attr:`note`)
    warnings        : what the user should check (also in ``log``, prefixed 'warning:')
    """

    vertices: np.ndarray
    faces: np.ndarray
    depth: int
    n_points: int
    median_distance: float
    p95_distance: float
    diagonal: float
    log: tuple[str, ...]
    warnings: tuple[str, ...]

    @property
    def note(self) -> str:
        return self.log[0]

    @property
    def median_relative(self) -> float:
        return self.median_distance / self.diagonal

    @property
    def p95_relative(self) -> float:
        return self.p95_distance / self.diagonal


def _open3d():
    try:
        import open3d
    except ImportError as exc:  # also raised when libusb-1.0 is missing
        if isinstance(exc, ModuleNotFoundError):
            raise missing_extra("pointcloud", "meshing a point cloud") from None
        raise InputError(f"open3d does not load ({exc}): on Debian/Ubuntu it needs the system library "
                         "libusb-1.0-0 ('bash .ci/install --extras pointcloud' installs it)") from None
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


def reconstruct(points: np.ndarray, depth: int | None = None) -> Reconstruction:
    """Closed surface through ``points`` ((n, 3), any unit), see the module docstring.

    depth : Poisson octree depth; None chooses it from the point spacing.
    """
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3:
        raise InputError("a point cloud needs three coordinates per point")
    if not np.isfinite(points).all():
        raise InputError(f"the point cloud has {int((~np.isfinite(points).all(axis=1)).sum())} points with NaN or infinite coordinates")
    if len(points) < 100:
        raise InputError(f"the point cloud has only {len(points)} points: too few to reconstruct a surface")
    if depth is not None and not (isinstance(depth, (int, np.integer)) and 1 <= depth <= 12):
        raise InputError(f"the Poisson depth must be a whole number from 1 to 12, got {depth}")
    o3d = _open3d()
    from scipy.spatial import cKDTree

    log: list[str] = []
    n_read = len(points)
    if n_read > MAX_POINTS:
        keep = np.sort(np.random.default_rng(0).choice(n_read, MAX_POINTS, replace=False))
        points = points[keep]
        log.append(f"thinned the point cloud from {n_read} to {MAX_POINTS} points (a fixed random subset)")
    diagonal = float(np.linalg.norm(np.ptp(points, axis=0)))
    size = float(np.ptp(points, axis=0).max())
    if not diagonal > 0:
        raise InputError("all points of the point cloud coincide: it has zero size")
    centred = points - points.mean(axis=0)
    sv = np.linalg.svd(centred[:: max(1, len(points) // 20000)], compute_uv=False)
    if sv[2] < 1e-6 * sv[0]:
        shape = "on a line" if sv[1] < 1e-6 * sv[0] else "in one plane"
        raise InputError(f"all points of the point cloud lie {shape}: it encloses no volume")
    tree = cKDTree(points)
    spacing = float(np.median(tree.query(points, k=2)[0][:, 1]))
    if not spacing > 0:
        spacing = diagonal / np.sqrt(len(points))  # many repeated points
    # a jitter of 1e-6 of the diagonal keeps the Delaunay step of the normal orientation
    # (qhull) off exactly cospherical or coplanar inputs, where it fails or takes minutes
    work = points + np.random.default_rng(0).normal(scale=1e-6 * diagonal, size=points.shape)
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(work))
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(30))
    try:
        cloud.orient_normals_consistent_tangent_plane(10)
    except RuntimeError as exc:
        raise InputError(f"could not orient the point cloud's normals ({str(exc).splitlines()[0]})") from None

    if depth is None:
        auto = int(np.floor(np.log2(1.1 * size / (2.0 * spacing))))
        first = int(np.clip(auto, *DEPTHS))
        tries = [first] + [d for d in (first - 1, first + 1) if DEPTHS[0] <= d <= DEPTHS[1]]
    else:
        tries = [int(depth)] + [d for d in (depth - 1, depth + 1) if DEPTHS[0] <= d <= DEPTHS[1] and d != depth]
    failures = []
    for d in tries:
        mesh, dens = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=d)
        v = np.asarray(mesh.vertices, dtype=float)
        f = np.asarray(mesh.triangles, dtype=np.int64)
        if len(f) == 0:
            failures.append(f"depth {d}: no triangles")
            continue
        voxel = 1.1 * size / 2**d
        f, n_cut = _cut_unsupported(v, f, np.asarray(dens), tree, 0.5 * max(voxel, spacing))
        v, f, info, problem = _make_closed(o3d, v, f)
        if problem is None:
            break
        failures.append(f"depth {d}: {problem}")
    else:
        raise InputError(
            f"could not mesh the point cloud of {len(points)} points into a closed surface "
            f"(Poisson {'; '.join(failures)}): check that the points cover the whole object "
            "and carry little noise, or mesh it in a scan editor first"
        )
    vol = _signed_volume(v, f)
    if vol < 0:
        f = f[:, ::-1]

    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(v.astype(np.float32)), o3d.core.Tensor(f.astype(np.uint32)))
    dist = scene.compute_distance(o3d.core.Tensor(points.astype(np.float32))).numpy().astype(float)
    med, p95 = float(np.median(dist)), float(np.percentile(dist, 95))

    note = (
        f"reconstructed a surface from {len(points)} points (Poisson, depth {d}, {len(f)} faces); "
        f"points to surface: median {med:.3g}, 95th percentile {p95:.3g} file units "
        f"({100 * med / diagonal:.2f} % and {100 * p95 / diagonal:.2f} % of the {diagonal:.4g} diagonal)"
    )
    log.insert(0, note)
    if failures:
        log.append(f"Poisson depth {tries[0]} did not give a closed surface ({'; '.join(failures)}), used depth {d}")
    fixes = []
    if n_cut:
        fixes.append(f"cut {n_cut} triangles Poisson added away from the points")
    if info["removed"]:
        fixes.append(f"cut {info['removed']} triangles at non-manifold edges or vertices")
    if info["dropped"]:
        fixes.append(f"dropped {info['dropped']} loose piece(s) ({100 * info['dropped_area']:.2g} % of the area)")
    if info["filled"]:
        fixes.append(f"closed {info['filled']} hole(s) with fans ({info['hole_faces']} triangles)")
    if fixes:
        log.append("cleaned the reconstructed surface: " + ", ".join(fixes))
    warnings = []
    if p95 > WARN_P95 * diagonal:
        warnings.append(
            f"5 % of the points lie more than {100 * p95 / diagonal:.2g} % of the bounding-box diagonal "
            f"({p95:.3g} file units) from the reconstructed surface (over {100 * WARN_P95:g} %): "
            "the point cloud may be noisy or have gaps; check the volume"
        )
    if info["dropped_area"] > 0.05:
        warnings.append(
            f"dropped loose pieces that made {100 * info['dropped_area']:.0f} % of the reconstructed area: "
            "check that the point cloud holds one object"
        )
    log.extend("warning: " + w for w in warnings)
    return Reconstruction(v, f, d, len(points), med, p95, diagonal, tuple(log), tuple(warnings))


def _cut_unsupported(v, f, dens, tree, reach) -> tuple[np.ndarray, int]:
    """Drop triangles at vertices farther than ``reach`` from every point and of low Poisson density."""
    d = tree.query(v)[0]
    near = d <= reach
    if not near.any():
        return f, 0
    low = dens < np.quantile(dens[near], 0.02)
    bad = (d > reach) & low
    if not bad.any():
        return f, 0
    mask = bad[f].any(axis=1)
    return f[~mask], int(mask.sum())


def _signed_volume(v, f) -> float:
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def _areas(v, f) -> np.ndarray:
    return 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)


def _row_keys(rows: np.ndarray, n: int) -> np.ndarray:
    """One sortable key per row of non-negative ints below ``n`` (equal keys = equal rows)."""
    rows = np.asarray(rows, dtype=np.int64)
    if float(n) ** rows.shape[1] < 2.0**62:
        key = np.zeros(len(rows), np.int64)
        for j in range(rows.shape[1]):
            key = key * n + rows[:, j]
        return key
    return np.unique(rows, axis=0, return_inverse=True)[1].ravel()


def _edges(f):
    """Directed edges (3f, 2) and, for each, how many faces share its undirected edge."""
    e = np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    key = _row_keys(np.sort(e, axis=1), int(f.max()) + 1)
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    return e, cnt[inv.ravel()]


def _largest_piece(v, f) -> tuple[np.ndarray, int, float]:
    """Faces of the largest edge-connected piece (by area), pieces dropped, and their area."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    e, _ = _edges(f)
    n = len(v)
    graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    fl = label[f[:, 0]]
    area = np.bincount(fl, weights=_areas(v, f))
    best = int(np.argmax(area))
    keep = fl == best
    pieces = int(np.count_nonzero(np.bincount(fl)) - 1)
    return f[keep], pieces, float(area.sum() - area[best])


def _make_closed(o3d, v, f) -> tuple[np.ndarray, np.ndarray, dict, str | None]:
    """Cut out non-manifold parts, keep the largest piece, fan-fill holes; None or the problem left."""
    info = {"removed": 0, "dropped": 0, "dropped_area": 0.0, "filled": 0, "hole_faces": 0}
    total_area = float(_areas(v, f).sum())
    dropped_area = 0.0
    problem = None
    for _ in range(_ROUNDS):
        f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])]
        _, first = np.unique(_row_keys(np.sort(f, axis=1), len(v)), return_index=True)
        f = f[np.sort(first)]
        if len(f) == 0:
            return v, f, info, "nothing left after cleaning"
        f, pieces, area = _largest_piece(v, f)
        info["dropped"] += pieces
        dropped_area += area
        mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(v), o3d.utility.Vector3iVector(f.astype(np.int32)))
        bad = set(np.asarray(mesh.get_non_manifold_vertices()).tolist())
        bad |= set(np.asarray(mesh.get_non_manifold_edges(allow_boundary_edges=True)).ravel().tolist())
        e, count = _edges(f)
        boundary = e[count == 1]
        out = np.bincount(boundary[:, 0], minlength=len(v)) if len(boundary) else np.zeros(len(v), int)
        bad |= set(np.nonzero(out > 1)[0].tolist())  # two holes meeting at a vertex
        if not bad and not len(boundary):
            info["dropped_area"] = dropped_area / total_area if total_area > 0 else 0.0
            if len(np.unique(_row_keys(e, len(v)))) != len(e):
                return v, f, info, "the faces are not consistently wound"
            if _signed_volume(v, f) == 0:
                return v, f, info, "the surface encloses no volume"
            return v, f, info, None
        if bad:
            mask = np.isin(f, np.fromiter(bad, np.int64)).any(axis=1)
            info["removed"] += int(mask.sum())
            f = f[~mask]
            problem = f"{len(bad)} non-manifold vertices left"
            continue  # re-check before filling
        nxt = dict(zip(boundary[:, 0].tolist(), boundary[:, 1].tolist()))
        loops, seen, broken = [], set(), set()
        for start in nxt:
            if start in seen:
                continue
            loop = [start]
            seen.add(start)
            c = nxt[start]
            while c != start and c in nxt and c not in seen:
                loop.append(c)
                seen.add(c)
                c = nxt[c]
            (loops if c == start else broken).append(loop)
        if broken:  # the boundary does not run round: the winding flips there
            cut = np.isin(f, np.concatenate([np.asarray(b) for b in broken])).any(axis=1)
            info["removed"] += int(cut.sum())
            f = f[~cut]
            problem = "a hole whose rim is wound both ways"
            continue
        new_v, new_f = [v], [f]
        base = len(v)
        for loop in loops:
            ring = np.asarray(loop)
            new_v.append(v[ring].mean(axis=0)[None])
            # boundary edge a->b lies on a face as a->b; the filling face runs b->a
            new_f.append(np.column_stack([np.roll(ring, -1), ring, np.full(len(ring), base)]))
            base += 1
            info["filled"] += 1
            info["hole_faces"] += len(ring)
        v, f = np.vstack(new_v), np.vstack(new_f)
        problem = f"{len(boundary)} open edges left"
    return v, f, info, problem
