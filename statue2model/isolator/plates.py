"""The two wooden plates of the rolling-ball isolator: solids, CNC files, the section's shapes.

Each plate is a square board (``side`` x ``side`` x ``thickness``) carved with n
spherical grooves: caps of a sphere of radius R, ``depth`` deep, whose opening
circle (radius a = sqrt(2 R depth - depth^2)) lies in the carved face. Balls of
radius r roll between facing grooves; the top plate carries the statue.

Frames and conventions (SI units, m):

* Each plate in its own frame: plate centre at x = y = 0, lower face z = 0,
  upper face z = thickness. The bottom plate is carved in its upper face (groove
  sphere centred at z = thickness - depth + R); the top plate is its mirror
  z -> thickness - z (grooves open downward, in its lower face), with the same
  x, y, so the grooves face each other when the plates are stacked. Assembled,
  with the balls at the bottom of the grooves, the top plate's lower face is a gap
  2 (r - depth) above the bottom plate's upper face.
* Fuse (release mechanism): for each centre in ``fuse_centres``, a seat (cap of a
  sphere of radius r_f, the fuse ball's, ``fuse_seat_depth`` deep) in both plates,
  and a drop hole (flat-bottomed cylinder, ``fuse_hole_diameter`` x
  ``fuse_hole_depth``) in the bottom plate only: a released ball falls, the top plate
  needs no hole. The hole's centre is ``fuse_hole_offset`` from the seat's centre,
  radially outward from the plate centre (along +x for a seat at the plate centre).
* Wood left: at least MIN_BOTTOM under every cutout, and MIN_WALL between any two
  cutouts of a face and between a cutout and the plate's edge.
* Files: the 3D files (STL, 3MF) and the DXF are written in millimetres (3MF is
  millimetres by definition; CAM reads STL as mm), one DXF per plate, origin at
  the plate centre. The top plate's DXF is drawn as its carved (lower) face is
  seen on the machine, i.e. the plate flipped about its y axis (x -> -x).

Tessellation. Every cutter is a surface of revolution whose vertices are computed
directly in float64 (not through a 2D polygon library, which rounds): rings of
``segments`` vertices, the groove's deepest point a single vertex exactly at
z = thickness - depth, and the last ring exactly on the face at radius a. The
profile of a cap is sampled every dtheta = dphi sin(theta_o) in polar angle
(dphi = 2 pi / segments, theta_o the cap's half-angle), so the faces at the rim are
about square. All vertices lie on the sphere, the polyhedral cap is convex and
inscribed, so it removes a little less than the exact cap: if delta is the largest
distance from a face's plane to the sphere (R minus that plane's distance to the
sphere centre), the polyhedron contains the concentric sphere of radius R - delta,
and the deficit per cap is at most cap_volume(R, d) - cap_volume(R - delta, d - delta),
about delta times the cap's area 2 pi R d, with delta ~ R dphi^2 sin^2(theta_o) / 4.
The faces lie on average about half as deep as their worst point: the measured
deficit is 0.50-0.55 of this bound, and falls as 1 / segments^2 (relative to the cap:
2.9e-4 at 256 segments, 4.7e-6 at 2048 for R = 0.30 m, d = 12 mm; about 20 / segments^2
for any shallow cap).
A drop hole is a regular inscribed polygon prism: its deficit is exact,
h r^2 (pi - (m / 2) sin(2 pi / m)). ``volume_deficit_bound`` adds these up.

Example
-------
>>> geom = PlateGeometry(side=0.40, thickness=0.03, R=0.30, depth=0.012,
...                      groove_centres=((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)),
...                      ball_radius=0.0183)
>>> round(geom.opening_radius * MM, 3), round(geom.gap * MM, 1)        # mm
(84.0, 12.6)
>>> round(geom.removed_volume * 1e6, 2)                                # cm^3, four caps
535.63
>>> solid = plate_solid(geom, segments=64)
>>> solid.status().name, solid.genus()
('NoError', 0)
>>> deficit = geom.removed_volume - (geom.side ** 2 * geom.thickness - solid.volume())
>>> 0 < deficit <= volume_deficit_bound(geom, segments=64)
True
>>> to_trimesh(plate_solid(geom, "top", segments=64)).is_watertight
True
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..fabrication.dxf import CUT_OUTSIDE, DRILL, MM, new_document
from ..io.files import atomic_write, prepare_dir

MIN_BOTTOM = 0.005   # m of wood left under any cutout
MIN_WALL = 0.005     # m of wood between two cutouts of a face, and between a cutout and the edge
ABOVE = 0.002        # m the cutters rise above the carved face (no coplanar faces in the booleans)
POCKET = "POCKET"    # DXF layer: opening circles of the spherical pockets (machined from the 3D file)
POCKET_COLOUR = 4
MIN_SEGMENTS = 8
WHICH = ("bottom", "top")


# --------------------------------------------------------------------------- caps

def _check_cap(R: float, depth: float, max_depth: float) -> None:
    if not (math.isfinite(R) and R > 0):
        raise InputError(f"sphere radius must be positive, got {R!r}")
    if not (math.isfinite(depth) and 0 <= depth <= max_depth):
        raise InputError(f"cap depth must be in [0, {max_depth:g}] m for R = {R:g} m, got {depth!r}")


def cap_opening_radius(R: float, depth: float) -> float:
    """Radius (m) of the circle a cap of a sphere of radius R, ``depth`` deep, opens on:
    sqrt(2 R d - d^2)."""
    _check_cap(R, depth, 2 * R)
    return math.sqrt(depth * (2 * R - depth))


def cap_volume(R: float, depth: float) -> float:
    """Volume (m^3) of a cap of a sphere of radius R, ``depth`` deep: pi d^2 (3 R - d) / 3."""
    _check_cap(R, depth, 2 * R)
    return math.pi * depth * depth * (3 * R - depth) / 3


def depth_for_opening(R: float, a: float) -> float:
    """Depth (m, <= R) of the cap of a sphere of radius R opening on a circle of radius a:
    R - sqrt(R^2 - a^2), computed as a^2 / (R + sqrt(R^2 - a^2)) (no cancellation)."""
    _check_cap(R, a, R)
    return a * a / (R + math.sqrt((R - a) * (R + a)))


def _cap_profile(R: float, depth: float, face_z: float, segments: int) -> np.ndarray:
    """(rho, z) profile of a cap cutter below the face z = face_z: deepest point on the
    axis, sphere samples, the rim exactly (a, face_z), then a wall up to face_z + ABOVE."""
    a = cap_opening_radius(R, depth)
    theta_o = math.atan2(a, R - depth)
    dphi = 2 * math.pi / segments
    k = max(2, math.ceil(theta_o / (dphi * math.sin(theta_o))))
    theta = theta_o * np.arange(1, k) / k
    zc = face_z - depth + R
    prof = [(0.0, face_z - depth)]
    prof += list(zip(R * np.sin(theta), zc - R * np.cos(theta)))
    prof += [(a, face_z), (a, face_z + ABOVE), (0.0, face_z + ABOVE)]
    return np.array(prof, dtype=float)


def _cap_deficit_bound(R: float, depth: float, segments: int) -> float:
    """Upper bound (m^3) on cap_volume(R, depth) minus the volume of the tessellated cap
    (see the module docstring): largest face-to-sphere distance delta, then the cap of the
    inscribed concentric sphere of radius R - delta."""
    prof = _cap_profile(R, depth, 0.0, segments)[:-2]          # axis .. rim, on the sphere
    c = np.array([0.0, 0.0, R - depth])                         # sphere centre (face at z = 0)
    dphi = 2 * math.pi / segments
    p0 = np.column_stack([prof[:-1, 0], np.zeros(len(prof) - 1), prof[:-1, 1]]) - c
    p1 = np.column_stack([prof[1:, 0], np.zeros(len(prof) - 1), prof[1:, 1]]) - c
    p2 = np.column_stack([prof[1:, 0] * math.cos(dphi), prof[1:, 0] * math.sin(dphi), prof[1:, 1]]) - c
    n = np.cross(p1 - p0, p2 - p0)
    dist = np.abs(np.einsum("ij,ij->i", n, p0)) / np.linalg.norm(n, axis=1)
    delta = R - float(dist.min())
    return cap_volume(R, depth) - cap_volume(R - delta, max(float(depth - delta), 0.0))


def _cylinder_deficit(radius: float, height: float, segments: int) -> float:
    """Exact volume (m^3) a regular inscribed ``segments``-gon prism misses of the cylinder."""
    return height * radius * radius * (math.pi - 0.5 * segments * math.sin(2 * math.pi / segments))


# --------------------------------------------------------------------------- geometry

@dataclass(frozen=True)
class PlateGeometry:
    """One isolator plate (both plates share it), m. See the module docstring for the frames."""

    side: float
    thickness: float
    R: float
    depth: float
    groove_centres: tuple
    ball_radius: float
    fuse_centres: tuple = ()
    fuse_ball_radius: float = 0.0
    fuse_seat_depth: float = 0.0
    fuse_hole_diameter: float = 0.0
    fuse_hole_depth: float = 0.0
    fuse_hole_offset: float = 0.0
    liner: float = 0.0

    @classmethod
    def from_design(cls, d: dict, where: str = "design") -> PlateGeometry:
        """From the JSON of ``statue2model isolator design`` (a dict); fuse seats, if the
        design has a fuse, sit at its ``fuse["centres"]`` (m) or, without them, between the
        grooves (on the diagonals, halfway to the centre)."""
        try:
            return cls(side=float(d["side"]), thickness=float(d["thickness"]), R=float(d["R"]),
                       depth=float(d["depth"]), groove_centres=tuple(tuple(c) for c in d["groove_centres"]),
                       ball_radius=float(d["r"]), liner=float(d.get("liner") or 0.0),
                       **_fuse_geometry(d.get("fuse") or {}, d))
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise InputError(f"{where} is not an isolator design ({exc})") from None

    def __post_init__(self):
        for name in ("side", "thickness", "R", "depth", "ball_radius", "fuse_ball_radius",
                     "fuse_seat_depth", "fuse_hole_diameter", "fuse_hole_depth", "fuse_hole_offset", "liner"):
            value = getattr(self, name)
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise InputError(f"plate {name} must be a number, got {value!r}") from None
            if not math.isfinite(value) or value < 0:
                raise InputError(f"plate {name} must be a finite non-negative length in m, got {value!r}")
            object.__setattr__(self, name, value)
        object.__setattr__(self, "groove_centres", _points("groove_centres", self.groove_centres))
        object.__setattr__(self, "fuse_centres", _points("fuse_centres", self.fuse_centres))
        for name in ("side", "thickness", "R", "depth", "ball_radius"):
            if getattr(self, name) <= 0:
                raise InputError(f"plate {name} must be positive, got {getattr(self, name)!r}")
        if not self.groove_centres:
            raise InputError("a plate needs at least one groove centre")
        if self.depth >= self.R:
            raise InputError(f"groove depth {self.depth:g} m must be less than its radius R = {self.R:g} m")
        if self.cut_depth >= self.thickness - MIN_BOTTOM + 1e-12:
            raise InputError(f"groove depth {self.cut_depth * MM:.1f} mm leaves less than {MIN_BOTTOM * MM:g} mm "
                             f"of a {self.thickness * MM:.1f} mm plate under the groove")
        if not self.depth < self.ball_radius < self.R:
            raise InputError(f"ball radius {self.ball_radius:g} m must lie between the groove depth "
                             f"{self.depth:g} m (else the plates touch) and R = {self.R:g} m")
        if self.fuse_centres:
            rf, zf = self.fuse_ball_radius, self.fuse_seat_depth
            if not (rf > 0 and 0 < zf < rf):
                raise InputError(f"fuse needs a ball radius > 0 and a seat depth in (0, r_f), got {rf:g}, {zf:g} m")
            if zf >= self.thickness - MIN_BOTTOM:
                raise InputError(f"fuse seat depth {zf:g} m leaves less than {MIN_BOTTOM * MM:g} mm of wood")
            if self.fuse_hole_diameter <= 2 * rf:
                raise InputError(f"fuse hole diameter {self.fuse_hole_diameter * MM:.1f} mm must exceed "
                                 f"the fuse ball's diameter {2 * rf * MM:.1f} mm")
            if not 0 < self.fuse_hole_depth < self.thickness - MIN_BOTTOM:
                raise InputError(f"fuse hole depth must be in (0, {(self.thickness - MIN_BOTTOM) * MM:.1f}) mm, "
                                 f"got {self.fuse_hole_depth * MM:.1f} mm")
            if self.fuse_hole_offset <= 0:
                raise InputError("fuse hole offset (seat centre to hole centre) must be positive")
        _check_layout(self)

    # ---- derived sizes
    @property
    def cut_R(self) -> float:
        """Radius of the sphere the plate is carved with (the rolling surface's R plus a liner), m."""
        return self.R + self.liner

    @property
    def cut_depth(self) -> float:
        """Depth of the carved cap (the rolling surface's depth plus a liner), m."""
        return self.depth + self.liner

    @property
    def opening_radius(self) -> float:
        """Radius of each groove's opening circle in the carved face (the liner's rim included), m."""
        return cap_opening_radius(self.cut_R, self.cut_depth)

    @property
    def fuse_seat_radius(self) -> float:
        """Radius of a fuse seat's opening circle, m (0 without a fuse)."""
        return cap_opening_radius(self.fuse_ball_radius, self.fuse_seat_depth) if self.fuse_centres else 0.0

    @property
    def fuse_hole_centres(self) -> tuple:
        """((x, y), ...) of the drop holes: ``fuse_hole_offset`` from each seat, radially
        outward from the plate centre (+x for a seat at the centre)."""
        out = []
        for x, y in self.fuse_centres:
            rho = math.hypot(x, y)
            ux, uy = (x / rho, y / rho) if rho > 1e-12 else (1.0, 0.0)
            out.append((x + self.fuse_hole_offset * ux, y + self.fuse_hole_offset * uy))
        return tuple(out)

    @property
    def gap(self) -> float:
        """Clearance between the plates' carved faces with the balls at the bottom of the grooves, m."""
        return 2 * (self.ball_radius - self.depth)

    @property
    def removed_volume(self) -> float:
        """Wood removed from the bottom plate, m^3: grooves, fuse seats and drop holes."""
        holes = len(self.fuse_centres) * math.pi * (0.5 * self.fuse_hole_diameter) ** 2 * self.fuse_hole_depth
        return self.top_removed_volume + holes

    @property
    def top_removed_volume(self) -> float:
        """Wood removed from the top plate, m^3: grooves and fuse seats (no drop holes)."""
        seats = len(self.fuse_centres) * cap_volume(self.fuse_ball_radius, self.fuse_seat_depth) \
            if self.fuse_centres else 0.0
        return len(self.groove_centres) * cap_volume(self.cut_R, self.cut_depth) + seats

    def circles(self, which: str = "bottom") -> list[tuple[str, float, float, float]]:
        """Cutouts of the carved face as (kind, x, y, opening radius): kind is
        'groove', 'seat' or 'hole' (holes only in the bottom plate)."""
        _check_which(which)
        out = [("groove", x, y, self.opening_radius) for x, y in self.groove_centres]
        out += [("seat", x, y, self.fuse_seat_radius) for x, y in self.fuse_centres]
        if which == "bottom":
            out += [("hole", x, y, 0.5 * self.fuse_hole_diameter) for x, y in self.fuse_hole_centres]
        return out


def _points(name: str, pts) -> tuple:
    try:
        arr = np.asarray(pts, dtype=float).reshape(-1, 2) if len(pts) else np.zeros((0, 2))
    except (TypeError, ValueError):
        raise InputError(f"plate {name} must be a sequence of (x, y) pairs in m") from None
    if not np.isfinite(arr).all():
        raise InputError(f"plate {name} must be finite")
    return tuple((float(x), float(y)) for x, y in arr)


def _check_layout(geom: PlateGeometry) -> None:
    half = 0.5 * geom.side
    count: dict[str, int] = {}
    labelled = []
    for kind, x, y, r in geom.circles("bottom"):
        count[kind] = count.get(kind, 0) + 1
        label = f"{kind} {count[kind]} at ({x * MM:.1f}, {y * MM:.1f}) mm"
        edge = half - max(abs(x), abs(y)) - r
        if edge < MIN_WALL - 1e-12:
            where = "outside the plate" if edge < 0 else f"{edge * MM:.1f} mm from the plate's edge"
            raise InputError(f"{label} (opening radius {r * MM:.1f} mm) is {where}: "
                             f"at least {MIN_WALL * MM:g} mm of wood is needed")
        labelled.append((label, x, y, r))
    for i, (la, xa, ya, ra) in enumerate(labelled):
        for lb, xb, yb, rb in labelled[i + 1:]:
            wall = math.hypot(xa - xb, ya - yb) - ra - rb
            if wall < MIN_WALL - 1e-12:
                what = "overlap" if wall < 0 else f"are only {wall * MM:.1f} mm apart"
                raise InputError(f"{la} and {lb} {what}: at least {MIN_WALL * MM:g} mm of wood is needed between them")


def _check_segments(segments) -> int:
    if not isinstance(segments, (int, np.integer)) or segments < MIN_SEGMENTS:
        raise InputError(f"segments must be an integer >= {MIN_SEGMENTS}, got {segments!r}")
    return int(segments)


def _check_which(which: str) -> None:
    if which not in WHICH:
        raise InputError(f"plate must be 'bottom' or 'top', got {which!r}")


# --------------------------------------------------------------------------- solids

def _revolve(profile: np.ndarray, segments: int, centre=(0.0, 0.0)):
    """Manifold of revolution of a (rho, z) profile that starts and ends on the axis
    (rho = 0) and runs outward, up, back to the axis; float64 vertices, exact rings."""
    import manifold3d as m3d

    m = segments
    inner = profile[1:-1]
    phi = 2 * math.pi * np.arange(m) / m
    c, s = np.cos(phi), np.sin(phi)
    rings = np.stack([np.column_stack([rho * c + centre[0], rho * s + centre[1], np.full(m, z)])
                      for rho, z in inner])
    verts = np.vstack([[centre[0], centre[1], profile[0, 1]], rings.reshape(-1, 3),
                       [centre[0], centre[1], profile[-1, 1]]])
    i = np.arange(m)
    ip = (i + 1) % m
    top = len(verts) - 1
    tris = [np.column_stack([np.zeros(m, int), 1 + ip, 1 + i])]             # fan from the lower axis point
    for j in range(len(inner) - 1):
        lo, up = 1 + j * m, 1 + (j + 1) * m
        tris.append(np.column_stack([lo + i, lo + ip, up + ip]))
        tris.append(np.column_stack([lo + i, up + ip, up + i]))
    last = 1 + (len(inner) - 1) * m
    tris.append(np.column_stack([last + i, last + ip, np.full(m, top)]))  # fan to the upper axis point
    mesh = m3d.Mesh64(vert_properties=np.ascontiguousarray(verts, dtype=np.float64),
                      tri_verts=np.ascontiguousarray(np.vstack(tris), dtype=np.uint64))
    return m3d.Manifold(mesh)


def _cutters(geom: PlateGeometry, which: str, segments: int) -> list:
    """Cutters of the bottom-plate frame (carved face z = thickness)."""
    t = geom.thickness
    out = []
    groove = _cap_profile(geom.cut_R, geom.cut_depth, t, segments)
    out += [_revolve(groove, segments, c) for c in geom.groove_centres]
    if geom.fuse_centres:
        seat = _cap_profile(geom.fuse_ball_radius, geom.fuse_seat_depth, t, segments)
        out += [_revolve(seat, segments, c) for c in geom.fuse_centres]
        if which == "bottom":
            rh, z0 = 0.5 * geom.fuse_hole_diameter, t - geom.fuse_hole_depth
            hole = np.array([(0.0, z0), (rh, z0), (rh, t + ABOVE), (0.0, t + ABOVE)])
            out += [_revolve(hole, segments, c) for c in geom.fuse_hole_centres]
    return out


def plate_solid(geom: PlateGeometry, which: str = "bottom", segments: int = 256):
    """The plate as a ``manifold3d.Manifold`` in its own frame (m): the box
    [-side/2, side/2]^2 x [0, thickness] minus the grooves (and the fuse's seats, and
    drop holes in the bottom plate); ``which='top'`` gives the mirror z -> thickness - z.
    ``segments`` vertices on every ring of the cutters."""
    import manifold3d as m3d

    _check_which(which)
    segments = _check_segments(segments)
    s, t = geom.side, geom.thickness
    box = m3d.Manifold.cube((s, s, t)).translate((-0.5 * s, -0.5 * s, 0.0))
    solid = m3d.Manifold.batch_boolean([box] + _cutters(geom, which, segments), m3d.OpType.Subtract)
    if which == "top":
        solid = solid.mirror((0.0, 0.0, 1.0)).translate((0.0, 0.0, t))
    if solid.status() != m3d.Error.NoError:               # pragma: no cover - a manifold3d bug
        raise RuntimeError(f"plate boolean failed: {solid.status()}")
    return solid


def volume_deficit_bound(geom: PlateGeometry, segments: int = 256, which: str = "bottom") -> float:
    """Upper bound (m^3) on the wood the tessellated cutters of ``plate_solid(geom, which,
    segments)`` leave in place compared with the exact ``removed_volume`` (the cutters are
    inscribed: the solid is never smaller than the exact plate). See the module docstring."""
    _check_which(which)
    segments = _check_segments(segments)
    bound = len(geom.groove_centres) * _cap_deficit_bound(geom.cut_R, geom.cut_depth, segments)
    if geom.fuse_centres:
        nf = len(geom.fuse_centres)
        bound += nf * _cap_deficit_bound(geom.fuse_ball_radius, geom.fuse_seat_depth, segments)
        if which == "bottom":
            bound += nf * _cylinder_deficit(0.5 * geom.fuse_hole_diameter, geom.fuse_hole_depth, segments)
    return bound


def to_trimesh(solid):
    """A ``manifold3d.Manifold`` as a ``trimesh.Trimesh`` (float64 vertices, unchanged)."""
    from ..compute.interrupts import checked_import

    trimesh = checked_import("trimesh")   # trimesh drops a Ctrl-C during its import

    mesh = solid.to_mesh64()
    verts = np.asarray(mesh.vert_properties, dtype=float)[:, :3]
    faces = np.asarray(mesh.tri_verts).astype(np.int64)
    return trimesh.Trimesh(verts, faces, process=False)


# --------------------------------------------------------------------------- files

def _write_dxf(geom: PlateGeometry, which: str, path: Path) -> Path:
    doc = new_document(f"isolator {which} plate")
    doc.layers.add(POCKET, color=POCKET_COLOUR)
    msp = doc.modelspace()
    flip = -1.0 if which == "top" else 1.0         # the top plate's carved face, seen on the machine
    h = 0.5 * geom.side * MM
    msp.add_lwpolyline([(-h, -h), (h, -h), (h, h), (-h, h)], close=True, dxfattribs={"layer": CUT_OUTSIDE})
    for kind, x, y, r in geom.circles(which):
        centre = (flip * x * MM, y * MM)
        if kind == "hole":
            msp.add_circle(centre, r * MM, dxfattribs={"layer": DRILL})
        else:
            msp.add_circle(centre, r * MM, dxfattribs={"layer": POCKET})
            if kind == "groove":
                msp.add_point(centre, dxfattribs={"layer": DRILL})
    return atomic_write(path, lambda p: doc.saveas(p))


def section_shapes(geom: PlateGeometry, y0: float):
    """Sections (x, z) in m at the plane y = y0 of the assembly: bottom plate, top plate,
    ball discs (main and fuse), as shapely geometries (drawn by
    :func:`statue2model.report.isolator_plots.plot_plates_section`)."""
    from shapely.geometry import Point, box
    from shapely.ops import unary_union

    s, t, res = geom.side, geom.thickness, 128

    def plate(which):
        cuts = []
        for x, y in geom.groove_centres:
            e = abs(y - y0)
            if e < geom.opening_radius:
                cuts.append(Point(x, t - geom.cut_depth + geom.cut_R).buffer(math.sqrt(geom.cut_R ** 2 - e * e),
                                                                             quad_segs=4 * res))
        for x, y in geom.fuse_centres:
            e, rf = abs(y - y0), geom.fuse_ball_radius
            if e < geom.fuse_seat_radius:
                cuts.append(Point(x, t - geom.fuse_seat_depth + rf).buffer(math.sqrt(rf * rf - e * e), quad_segs=res))
        if which == "bottom":
            for x, y in geom.fuse_hole_centres:
                e, rh = abs(y - y0), 0.5 * geom.fuse_hole_diameter
                if e < rh:
                    w = math.sqrt(rh * rh - e * e)
                    cuts.append(box(x - w, t - geom.fuse_hole_depth, x + w, t + 1.0))
        return box(-0.5 * s, 0.0, 0.5 * s, t).difference(unary_union(cuts)) if cuts else box(-0.5 * s, 0, 0.5 * s, t)

    from shapely.affinity import scale, translate

    bottom = plate("bottom")
    top = translate(scale(plate("top"), 1.0, -1.0, origin=(0, 0.5 * t)), 0.0, t + geom.gap)
    balls = [Point(x, t - geom.depth + geom.ball_radius).buffer(math.sqrt(geom.ball_radius ** 2 - (y - y0) ** 2), quad_segs=res)
             for x, y in geom.groove_centres if abs(y - y0) < geom.ball_radius]
    fuse = [Point(x, t - geom.fuse_seat_depth + geom.fuse_ball_radius).buffer(
                math.sqrt(geom.fuse_ball_radius ** 2 - (y - y0) ** 2), quad_segs=res)
            for x, y in geom.fuse_centres if abs(y - y0) < geom.fuse_ball_radius]
    return bottom, top, balls, fuse


_NS_3MF = ('xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02" '
           'xmlns:b="http://schemas.microsoft.com/3dmanufacturing/beamlattice/2017/02" '
           'xmlns:m="http://schemas.microsoft.com/3dmanufacturing/material/2015/02" '
           'xmlns:p="http://schemas.microsoft.com/3dmanufacturing/production/2015/06" '
           'xmlns:s="http://schemas.microsoft.com/3dmanufacturing/slice/2015/07" '
           'xmlns:sc="http://schemas.microsoft.com/3dmanufacturing/securecontent/2019/04"')
_NS_3MF_ITEM = ('xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02" '
                'xmlns:m="http://schemas.microsoft.com/3dmanufacturing/material/2015/02" '
                'xmlns:p="http://schemas.microsoft.com/3dmanufacturing/production/2015/06" '
                'xmlns:b="http://schemas.microsoft.com/3dmanufacturing/beamlattice/2017/02" '
                'xmlns:s="http://schemas.microsoft.com/3dmanufacturing/slice/2015/07" '
                'xmlns:sc="http://schemas.microsoft.com/3dmanufacturing/securecontent/2019/04"')
_DECL = "<?xml version='1.0' encoding='utf-8'?>\n"
_RELS_3MF = (_DECL + '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
             '<Relationship Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel" '
             'Target="/3D/3dmodel.model" Id="rel0"/></Relationships>')
_TYPES_3MF = (_DECL + '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">' + "".join(
    f'<Default Extension="{e}" ContentType="{t}"/>' for e, t in (
        ("jpeg", "image/jpeg"), ("jpg", "image/jpeg"),
        ("model", "application/vnd.ms-package.3dmanufacturing-3dmodel+xml"), ("png", "image/png"),
        ("rels", "application/vnd.openxmlformats-package.relationships+xml"),
        ("texture", "application/vnd.ms-package.3dmanufacturing-3dmodeltexture"))) + "</Types>")


def write_3mf(vertices: np.ndarray, faces: np.ndarray, path) -> None:
    """One mesh as a 3MF file (millimetres: ``vertices`` in mm). The same package, member for member
    and character for character (fresh UUIDs aside), as trimesh's 3MF export of the mesh alone (one
    object ``geometry_0``, one build item, identity transform), written directly: every coordinate as
    Python's shortest round-trip text of the float64 (numpy prints the same). Deflated at level 1
    (trimesh: 5): a plate's 14 MB of XML in 0.07 s instead of 0.18 s, the file 3.0 MB instead of 2.4."""
    import uuid
    import zipfile

    v = np.asarray(vertices, dtype=np.float64).reshape(-1).tolist()
    f = np.asarray(faces, dtype=np.int64).reshape(-1).tolist()
    model = "".join([
        _DECL, f'<model {_NS_3MF} unit="millimeter"><resources>',
        f'<object id="1" name="geometry_0" type="model" p:UUID="{uuid.uuid4()}"><mesh><vertices>',
        ('<vertex x="{}" y="{}" z="{}" />' * (len(v) // 3)).format(*v), "</vertices><triangles>",
        ('<triangle v1="{}" v2="{}" v3="{}" />' * (len(f) // 3)).format(*f),
        f'</triangles></mesh></object></resources><build p:UUID="{uuid.uuid4()}"><item {_NS_3MF_ITEM} objectid="1" '
        f'transform="1.0 0.0 0.0 0.0 1.0 0.0 0.0 0.0 1.0 0.0 0.0 0.0" p:UUID="{uuid.uuid4()}" '
        'partnumber="geometry_0"/></build></model>'])
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=1) as z:
        z.writestr("3D/3dmodel.model", model.encode("utf-8"))
        z.writestr("_rels/.rels", _RELS_3MF.encode("utf-8"))
        z.writestr("[Content_Types].xml", _TYPES_3MF.encode("utf-8"))


def write_plates(geom: PlateGeometry, out_dir, segments: int = 256) -> dict[str, Path]:
    """Write the plates' fabrication files to ``out_dir`` and return their paths:

    bottom_stl, top_stl   bottom_plate.stl, top_plate.stl (mm, each in its own frame)
    bottom_3mf, top_3mf   bottom_plate.3mf, top_plate.3mf (mm; :func:`write_3mf`)
    bottom_dxf, top_dxf   bottom_plate.dxf, top_plate.dxf (mm, origin at the plate centre):
                          outline CUT_OUTSIDE; groove and seat opening circles POCKET;
                          groove centres DRILL points; drop holes DRILL circles

    The dimensioned section (plates_section.png / .svg) is drawn by
    :func:`statue2model.report.isolator_plots.plot_plates_section`.
    """
    out = prepare_dir(out_dir)
    paths: dict[str, Path] = {}
    for which in WHICH:
        mesh = to_trimesh(plate_solid(geom, which, segments))
        mesh.apply_scale(MM)
        paths[f"{which}_stl"] = atomic_write(out / f"{which}_plate.stl",
                                             lambda p, m=mesh: m.export(p, file_type="stl"))
        paths[f"{which}_3mf"] = atomic_write(out / f"{which}_plate.3mf",
                                             lambda p, m=mesh: write_3mf(m.vertices, m.faces, p))
        paths[f"{which}_dxf"] = _write_dxf(geom, which, out / f"{which}_plate.dxf")
    return paths


def _fuse_geometry(fuse: dict, d: dict) -> dict:
    """Fuse seats at fuse["centres"], else between the grooves (on the diagonals, halfway to the centre), m."""
    if not fuse:
        return {}
    rf = float(fuse["ball_radius"])
    centres = ([tuple(map(float, c)) for c in fuse["centres"]] if fuse.get("centres")
               else [(0.5 * x, 0.5 * y) for x, y in d["groove_centres"]])
    z = float(fuse["seat_depth"])
    hole = max(2.4 * rf, 2 * rf + 0.002)
    seat = (2 * rf * z - z * z) ** 0.5
    return {"fuse_centres": tuple(centres), "fuse_ball_radius": rf, "fuse_seat_depth": z,
            "fuse_hole_diameter": hole, "fuse_hole_depth": min(max(2.2 * rf, 0.003), float(d["thickness"]) - 0.006),
            "fuse_hole_offset": seat + hole / 2 + 0.006}
