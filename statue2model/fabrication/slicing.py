"""Scan -> stacked-board prototype: the whole computation, before any file is written.

    Body --(scale)--> scaled mesh --> layer outlines (layers.py) --> tool checks
    (toolcheck.py) --> alignment rods (rods.py) --> parts with labels (labels.py)
    --> nesting on sheets (nesting.py) --> the prototype as built (prototype.py)

:func:`slice_body` returns a :class:`SliceResult`; ``output.write_slice`` turns it
into files. Layers and parts are numbered from 1 in everything a person reads
(part names '37', or '37A', '37B' when a layer has several parts); indices in the
arrays start at 0.

Example
-------
>>> import trimesh
>>> from statue2model.geometry.body import body_from_mesh
>>> box = trimesh.creation.box((0.30, 0.20, 0.50))
>>> body = body_from_mesh(box.vertices, box.faces, units="m", up="z", density=2650)
>>> res = slice_body(body, SliceSpec(scale=2.0))
>>> res.n_layers, len(res.parts), res.nesting.n_sheets, len(res.rods.rods)
(26, 26, 1, 2)
>>> round(res.comparison.volume, 4)      # 26 boards + 25 glue films: 246.5 mm of the 250 mm
-0.0143
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Point, Polygon

from ..errors import InputError
from ..geometry.footprint import Footprint, convex_hull_2d
from ..geometry.massprops import MassProperties
from ..geometry.rocking_params import rocking_params, weakest_direction
from .labels import Label, place_label
from .layers import layer_bottoms, layer_sections
from .nesting import Nesting, nest
from .prototype import Comparison, compare, stack_mass_properties, stack_mesh
from .rods import RodPlan, place_rods
from .spec import SliceSpec
from .toolcheck import as_cut, check_layer, compensate

MAX_LAYERS = 2000
NEST_GRIDS = (0.005, 0.004)
"""Raster cells of the nesting (m): the finer one is tried when the first leaves
more sheets than the parts' area needs (greedy nesting is not monotonic in it)."""
FRONT_AXIS = {"+x": (0, 0, 1), "-x": (0, 0, 1), "+y": (0, 0, 1), "-y": (0, 0, 1), "+z": (0, -1, 0), "-z": (0, -1, 0)}
"""File axis taken as the statue's front, by up axis: +z for Y-up scans (glTF and most
scanners face the camera along +z), -y for Z-up scans (Blender's front view)."""


@dataclass(frozen=True)
class Part:
    """One piece to cut.

    layer, index : 0-based layer and part numbers; ``name`` as engraved ('37', '37B')
    outline      : the part (true outline, m, in the statue's plan frame)
    cut          : what is written to CUT_OUTSIDE/CUT_INSIDE (``outline``, or the
                   cutter-centre path when compensating)
    holes        : (n, 2) rod-hole centres in this part, m
    label        : engraved label, or None when there is no room
    """

    layer: int
    index: int
    name: str
    outline: Polygon
    cut: Polygon
    holes: np.ndarray
    label: Label | None

    @property
    def area(self) -> float:
        return float(self.outline.area)


@dataclass(frozen=True)
class SliceResult:
    spec: SliceSpec
    source: str
    direction_deg: float
    front_deg: float
    bottoms: np.ndarray
    sections: tuple
    tool: tuple
    rods: RodPlan
    parts: tuple
    nesting: Nesting
    scan_mass: MassProperties
    scan_params: object
    proto_mass: MassProperties
    proto_params: object
    proto_footprint: Footprint
    comparison: Comparison
    mesh: tuple
    height: float
    warnings: tuple
    timings: dict

    @property
    def n_layers(self) -> int:
        return len(self.bottoms)


def front_direction(body) -> float:
    """Plan angle (deg from +x toward +y) of the statue's front in the body frame."""
    axis = np.array(FRONT_AXIS.get(body.up, (0, 0, 1)), dtype=float)
    v = body.rotation @ axis
    if np.hypot(v[0], v[1]) < 1e-6:
        return -90.0
    return float(np.degrees(np.arctan2(v[1], v[0])))


def part_names(counts: list[int]) -> list[list[str]]:
    """'37' for a layer's only part, '37A', '37B', ... when there are several."""
    out = []
    for k, n in enumerate(counts):
        if n == 1:
            out.append([str(k + 1)])
        else:
            out.append([f"{k + 1}{_letters(i)}" for i in range(n)])
    return out


def _letters(i: int) -> str:
    s = ""
    i += 1
    while i:
        i, r = divmod(i - 1, 26)
        s = chr(ord("A") + r) + s
    return s


def scaled_mass(mass: MassProperties, lam: float) -> MassProperties:
    """Mass properties of the same solid, same density, with lengths / lam."""
    return MassProperties(volume=mass.volume / lam**3, mass=mass.mass / lam**3, density=mass.density,
                          com=mass.com / lam, inertia=mass.inertia / lam**5)


def slice_body(body, spec: SliceSpec, direction_deg: float | None = None,
               front_deg: float | None = None) -> SliceResult:
    """Everything the prototype needs, computed in memory (see module docstring)."""
    clock = {}
    t0 = time.perf_counter()
    lam = spec.scale
    v = body.vertices / lam
    height = float(v[:, 2].max())
    n_est = math.ceil(height / spec.pitch)
    if n_est > MAX_LAYERS:
        raise InputError(f"{n_est} layers of {spec.pitch * 1000:g} mm for a {height * 1000:.0f} mm prototype: "
                         f"more than {MAX_LAYERS}; check --scale and --board")
    if n_est < 2:
        raise InputError(f"the {height * 1000:.1f} mm prototype is thinner than two {spec.pitch * 1000:g} mm "
                         "layers; check --scale and --board")
    scan_mass = scaled_mass(body.mass, lam)
    hull = body.footprint.hull / lam
    if direction_deg is None:
        direction_deg, _ = weakest_direction(body.mass, body.footprint.hull)
    scan_params = rocking_params(scan_mass, hull, direction_deg)
    if front_deg is None:
        front_deg = front_direction(body)
    warnings: list[str] = list(body.warnings)

    bottoms = layer_bottoms(height, spec.board, spec.glue, spec.policy)
    secs = layer_sections(v, body.faces, bottoms, spec.board, spec.policy, spec.tolerance)
    empty = [k + 1 for k, s in enumerate(secs) if s.is_empty]
    if empty:
        warnings.append(f"layers {_ranges(empty)} have no section (the scan has a gap there)")
    clock["sections"] = time.perf_counter() - t0

    t = time.perf_counter()
    tool = tuple(check_layer(s, spec.tool) for s in secs)
    for k, rep in enumerate(tool):
        if not rep.clean:
            warnings.append(f"layer {k + 1}: {rep.describe(spec.tool)}")
    clock["tool checks"] = time.perf_counter() - t

    t = time.perf_counter()
    plan = place_rods(secs, spec.pitch, spec.board, spec.hole, spec.wall)
    warnings.extend(plan.warnings)
    clock["rods"] = time.perf_counter() - t

    t = time.perf_counter()
    names = part_names([len(s.geoms) for s in secs])
    parts = []
    no_label = []
    for k, sec in enumerate(secs):
        centres = plan.holes[k]
        for i, poly in enumerate(sec.geoms):
            inside = centres[shapely.contains_xy(poly, centres[:, 0], centres[:, 1])] if len(centres) else centres
            keep_out = (shapely.union_all([Point(c).buffer(0.5 * spec.hole + spec.wall, quad_segs=8)
                                           for c in inside]) if len(inside) else None)
            label = place_label(poly, names[k][i], front_deg, keep_out=keep_out, tool_diameter=0.0)
            if label is None:
                no_label.append(names[k][i])
            cut = compensate(MultiPolygon([poly]), spec.tool).geoms[0] if spec.compensate else poly
            parts.append(Part(k, i, names[k][i], poly, cut, inside.reshape(-1, 2), label))
    if no_label:
        warnings.append(f"no room for an engraved label on part(s) {', '.join(no_label)}: mark them by hand")
    clock["labels"] = time.perf_counter() - t

    t = time.perf_counter()
    outlines = [p.outline for p in parts]
    labels = [f"layer {p.layer + 1} part {p.name}" for p in parts]
    nesting = nest(outlines, spec.sheet, spec.spacing, edge_margin=spec.edge, grid=NEST_GRIDS[0], names=labels)
    usable = (spec.sheet[0] - 2 * spec.edge) * (spec.sheet[1] - 2 * spec.edge)
    least = math.ceil(sum(p.area for p in parts) / usable)
    for grid in NEST_GRIDS[1:]:
        if nesting.n_sheets <= least:
            break
        finer = nest(outlines, spec.sheet, spec.spacing, edge_margin=spec.edge, grid=grid, names=labels)
        if finer.n_sheets < nesting.n_sheets:
            nesting = finer
    clock["nesting"] = time.perf_counter() - t

    t = time.perf_counter()
    built = [as_cut(s, spec.tool) for s in secs]
    proto_mass = stack_mass_properties(
        built, spec.pitch, spec.board, spec.glue, plan.holes, spec.hole, plan.rods,
        (spec.osb_density, spec.glue_density, spec.rod_density), rod=spec.rod)
    base = built[0]
    ring = shapely.get_coordinates(base.convex_hull.exterior)[:-1]
    proto_hull = convex_hull_2d(ring)
    proto_fp = Footprint(
        polygons=tuple((np.asarray(p.exterior.coords)[:-1], tuple(np.asarray(h.coords)[:-1] for h in p.interiors))
                       for p in shapely.get_parts(shapely.orient_polygons(base))),
        hull=proto_hull, area=float(base.area), hull_area=float(base.convex_hull.area), tol=0.0)
    if proto_fp.contains(proto_mass.com[:2]) <= 0:
        warnings.append("the prototype as built would not stand: its centre of mass is outside the first board")
    proto_params = rocking_params(proto_mass, proto_hull, direction_deg)
    comparison = compare(proto_mass, proto_params, scan_mass, scan_params, height)
    mesh = stack_mesh(built, spec.pitch, spec.board, spec.glue)
    clock["prototype"] = time.perf_counter() - t
    return SliceResult(
        spec=spec, source=body.source, direction_deg=float(direction_deg), front_deg=float(front_deg),
        bottoms=bottoms, sections=tuple(secs), tool=tool, rods=plan, parts=tuple(parts), nesting=nesting,
        scan_mass=scan_mass, scan_params=scan_params, proto_mass=proto_mass, proto_params=proto_params,
        proto_footprint=proto_fp, comparison=comparison, mesh=mesh, height=height,
        warnings=tuple(warnings), timings=clock,
    )


def _ranges(numbers: list[int]) -> str:
    out, start, prev = [], None, None
    for n in numbers:
        if start is None:
            start = prev = n
        elif n == prev + 1:
            prev = n
        else:
            out.append(f"{start}-{prev}" if prev > start else str(start))
            start = prev = n
    if start is not None:
        out.append(f"{start}-{prev}" if prev > start else str(start))
    return ", ".join(out)
