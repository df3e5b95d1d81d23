"""Scan -> stacked-board prototype: the whole computation, before any file is written.

    Body --(scale)--> scaled mesh --> layer outlines, checked (layers.py) -->
    what the cutter can make of them (toolcheck.py: parts narrower than it dropped,
    slivers opened away) --> alignment rods (rods.py) --> parts with labels
    (labels.py) --> nesting on sheets (nesting.py) --> the prototype as built and
    its errors against the scaled scan, each with its likely cause (prototype.py)

Warnings are few and summarised (one line per kind of finding, with the layers);
the counts per layer are in ``tool`` and ``section_checks`` (and slice.json).
An error of the prototype above prototype.ERROR_LIMIT (volume, h, b_L, b_R,
I_G / m, a_R, a_min) is a warning with its likely cause, first in the list.

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
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Point, Polygon

from ..errors import InputError
from ..geometry.footprint import Footprint, convex_hull_2d
from ..geometry.massprops import MassProperties
from ..geometry.rocking_params import rocking_params, unit_vectors, weakest_direction
from .labels import Label, place_label
from .layers import MERGE, layer_bottoms, layer_sections_checked
from .nesting import Nesting, nest
from .prototype import (
    ERROR_LIMIT,
    LABELS,
    PrototypeComparison,
    base_difference,
    combine,
    compare,
    effect,
    likely_causes,
    stack_mesh,
    stack_moments,
    stack_volume_moments,
)
from .robust import GeometryError
from .robust import difference as _difference
from .robust import intersection as _intersection
from .robust import union_all as _union_all
from .rods import RodPlan, place_rods
from .spec import SliceSpec
from .toolcheck import as_cut, compensate, layer_list, summarise, trim_layer

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
    comparison: PrototypeComparison
    mesh: tuple
    height: float
    warnings: tuple
    timings: dict
    section_checks: tuple = ()
    """per layer, the layers.SectionCheck of each plane it was built from"""
    causes: dict = field(default_factory=dict)
    """comparison key -> likely cause of its error (prototype.likely_causes)"""
    a_min: tuple = (float("nan"), float("nan"))
    """(prototype, scaled scan) uplift acceleration in each one's weakest direction, m/s^2"""

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
    """Everything the prototype needs, computed in memory (see module docstring).

    A polygon operation that fails even on cleaned polygons (robust.py) raises
    robust.GeometryError (an InputError: one line) naming the layer, its height on
    the prototype and on the statue, and what was being done."""
    try:
        return _slice_body(body, spec, direction_deg, front_deg)
    except GeometryError as exc:
        raise GeometryError(f"{exc}; {GEOMETRY_HINT}") from None


def _slice_body(body, spec: SliceSpec, direction_deg: float | None, front_deg: float | None) -> SliceResult:
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
    raw, checks = layer_sections_checked(v, body.faces, bottoms, spec.board, spec.policy, spec.tolerance)
    warnings.extend(section_warnings(checks, bottoms, spec, lam, scan_mass.volume))
    clock["sections"] = time.perf_counter() - t0

    t = time.perf_counter()

    def on_layer(k: int, fn, *args, **kwargs):
        """fn(*args, **kwargs); a GeometryError (robust.py) names layer k and its heights."""
        try:
            return fn(*args, **kwargs)
        except GeometryError as exc:
            raise GeometryError(f"layer {k + 1} ({_z_text(bottoms, spec, lam, [k + 1])}): {exc}") from None

    trimmed = [on_layer(k, trim_layer, s, spec.tool) for k, s in enumerate(raw)]
    secs = [k for k, _, _ in trimmed]
    tool = tuple(r for _, r, _ in trimmed)
    removed = [x for _, _, x in trimmed]
    warnings.extend(summarise(tool, spec.tool, float(sum(s.area for s in raw))))
    warnings.extend(empty_layer_warnings(raw, secs, checks, bottoms, spec, lam))
    if secs[0].is_empty:
        raise InputError(f"layer 1 holds nothing a {spec.tool * 1000:g} mm cutter can cut: the prototype has no base "
                         "(check the scan's base, --scale and --tool)")
    clock["tool checks"] = time.perf_counter() - t

    t = time.perf_counter()
    plan = place_rods(secs, spec.pitch, spec.board, spec.hole, spec.wall)
    warnings.extend(rod_warnings(plan.warnings))
    clock["rods"] = time.perf_counter() - t

    t = time.perf_counter()
    names = part_names([len(s.geoms) for s in secs])
    parts = []
    no_label, no_label_geos = [], []
    for k, sec in enumerate(secs):
        centres = plan.holes[k]
        for i, poly in enumerate(sec.geoms):
            inside = centres[shapely.contains_xy(poly, centres[:, 0], centres[:, 1])] if len(centres) else centres
            try:
                keep_out = (_union_all([Point(c).buffer(0.5 * spec.hole + spec.wall, quad_segs=8) for c in inside],
                                       what=f"the rod holes of part {names[k][i]}") if len(inside) else None)
                label = place_label(poly, names[k][i], front_deg, keep_out=keep_out, tool_diameter=0.0)
            except GeometryError:      # a label is not worth failing the run: marked by hand
                label = None
                no_label_geos.append(names[k][i])
            if label is None:
                no_label.append(names[k][i])
            cut = on_layer(k, compensate, MultiPolygon([poly]), spec.tool).geoms[0] if spec.compensate else poly
            parts.append(Part(k, i, names[k][i], poly, cut, inside.reshape(-1, 2), label))
    if no_label:
        why = (f" (on {', '.join(no_label_geos)} the geometry library failed even on cleaned polygons)"
               if no_label_geos else "")
        warnings.append(f"no room for an engraved label on part(s) {', '.join(no_label)}{why}: mark them by hand")
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
    built = [on_layer(k, as_cut, s, spec.tool) for k, s in enumerate(secs)]
    moments = stack_moments(built, spec.pitch, spec.board, spec.glue, plan.holes, spec.hole, plan.rods, rod=spec.rod)
    proto_mass = combine(moments, (spec.osb_density, spec.glue_density, spec.rod_density))
    # the same materials, all at the board's density: what the densities of glue and rods do
    uniform = combine(moments, tuple(spec.osb_density if rho > 0 else 0.0
                                     for rho in (spec.osb_density, spec.glue_density, spec.rod_density)))
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
    a_min = (weakest_direction(proto_mass, proto_hull)[1], weakest_direction(scan_mass, hull)[1])
    comparison = compare(proto_mass, proto_params, scan_mass, scan_params, height, *a_min)
    extra = _policy_effect(v, body.faces, bottoms, raw, spec, scan_mass, direction_deg)
    causes = _causes(comparison, spec, lam, bottoms, raw, secs, built, removed, tool, checks, scan_mass,
                     proto_mass, uniform, moments, plan, height, hull, proto_hull, direction_deg, extra)
    for i, key in enumerate(comparison.failing()):      # first: they matter most
        warnings.insert(i, f"the prototype's {LABELS[key]} is {getattr(comparison, key) * 100:+.1f} % off the scaled "
                        f"scan (limit +-{ERROR_LIMIT * 100:g} %); likely cause: {causes[key]}")
    mesh = stack_mesh(built, spec.pitch, spec.board, spec.glue)
    clock["prototype"] = time.perf_counter() - t
    return SliceResult(
        spec=spec, source=body.source, direction_deg=float(direction_deg), front_deg=float(front_deg),
        bottoms=bottoms, sections=tuple(secs), tool=tool, rods=plan, parts=tuple(parts), nesting=nesting,
        scan_mass=scan_mass, scan_params=scan_params, proto_mass=proto_mass, proto_params=proto_params,
        proto_footprint=proto_fp, comparison=comparison, mesh=mesh, height=height,
        warnings=tuple(warnings), timings=clock, section_checks=tuple(checks), causes=causes,
        a_min=(float(a_min[0]), float(a_min[1])),
    )


def _z_text(bottoms, spec: SliceSpec, lam: float, layers: list[int]) -> str:
    """Mid-board heights of 1-based ``layers`` on the prototype and on the statue."""
    lo = float(bottoms[min(layers) - 1] + 0.5 * spec.board)
    hi = float(bottoms[max(layers) - 1] + 0.5 * spec.board)
    span = f"{lo * 1000:.1f}" + (f"-{hi * 1000:.1f}" if hi > lo else "")
    real = f"{lo * lam * 1000:.0f}" + (f"-{hi * lam * 1000:.0f}" if hi > lo else "")
    return f"z = {span} mm on the prototype, {real} mm on the statue"


GEOMETRY_HINT = ("the scan's surface is nearly degenerate there (slivers, edges that nearly coincide): repair it near "
                 "that height, or move the section planes with a slightly different --board or --tolerance")
"""The advice that ends a GeometryError of the slice (robust.py)."""


ROD_LINES = 6
"""More rod warnings than this are summarised (all of them stay in slice.json, rods.warnings)."""


def rod_warnings(lines) -> list[str]:
    """The rod plan's warnings, or when there are more than ROD_LINES, one line per kind
    (parts too small for a hole, joints with fewer than two rods) with the layers."""
    import re

    lines = list(lines)
    if len(lines) <= ROD_LINES:
        return lines
    small, joints, other = [], [], []
    for line in lines:
        m = re.match(r"layer (\d+) part \S+ is too small", line)
        j = re.match(r"joint (\d+)/\d+", line)
        if m:
            small.append(int(m.group(1)))
        elif j:
            joints.append(int(j.group(1)))
        else:
            other.append(line)
    out = []
    if small:
        out.append(f"{len(small)} part(s) too small for a rod hole with its walls (no alignment rod: place them by "
                   f"their outline), on {layer_list(small)}")
    if joints:
        out.append(f"{len(joints)} glue joint(s) crossed by fewer than two rods, above {layer_list(joints)} "
                   "(each listed in slice.json, rods.warnings)")
    return out + other


def section_warnings(checks, bottoms, spec: SliceSpec, lam: float, scan_volume: float) -> list[str]:
    """What the section checks (layers.SectionCheck per plane, per layer) found: loops
    rebuilt from the noded segments, overlapping shells, inside-out folds, gaps closed."""
    out = []

    def where(pred):
        return [k + 1 for k, cs in enumerate(checks) if any(pred(c) for c in cs)]

    rebuilt = where(lambda c: c.repaired)
    if rebuilt:
        out.append(f"{layer_list(rebuilt)}: the filled section loops disagreed with the winding-number integral of "
                   "the scan's surface; the outline was rebuilt from the noded segments (layers.py)")
    over = where(lambda c: c.overlap > 0)
    if over:
        most = max(c.overlap for cs in checks for c in cs)
        twice = sum(np.mean([c.overlap for c in cs]) for cs in checks) * spec.pitch
        out.append(f"{layer_list(over)} ({_z_text(bottoms, spec, lam, over)}): the scan's surface overlaps itself "
                   f"(winding number 2 or more over up to {most * 1e6:.0f} mm^2 of a layer: intersecting shells); "
                   f"the boards take the union, while the scan's volume counts the overlap twice "
                   f"(about {twice * 1e6:.1f} cm^3 at this scale, {twice / scan_volume * 100:.2f} % of it)")
    inv = where(lambda c: c.inverted > 0)
    if inv:
        most = max(c.inverted for cs in checks for c in cs)
        out.append(f"{layer_list(inv)}: the scan's surface folds inside out (winding number below 0 over up to "
                   f"{most * 1e6:.1f} mm^2 of a layer); those bits are cut as solid")
    gaps = where(lambda c: c.merged > 0)
    if gaps:
        out.append(f"{layer_list(gaps)}: section points up to {MERGE * 1e6:g} um apart were joined (the scan is "
                   "not closed there)")
    return out


def empty_layer_warnings(raw, secs, checks, bottoms, spec: SliceSpec, lam: float) -> list[str]:
    """Why each empty layer is empty: a gap in the body (no surface crosses it), planes
    that touch the surface without enclosing any area, or only parts narrower than
    the cutter."""
    gap = [k + 1 for k, s in enumerate(raw) if s.is_empty and all(c.segments == 0 for c in checks[k])]
    touch = [k + 1 for k, s in enumerate(raw) if s.is_empty and any(c.segments for c in checks[k])]
    narrow = [k + 1 for k, (r, s) in enumerate(zip(raw, secs)) if s.is_empty and not r.is_empty]
    out = []
    if gap:
        out.append(f"{layer_list(gap)} ({_z_text(bottoms, spec, lam, gap)}) cut nothing: the scan has a gap there "
                   "(separate bodies above each other); the boards are left out and what is above rests on "
                   "nothing below")
    if touch:
        why = ("the sections through the board have nothing in common (policy core)" if spec.policy == "core"
               else "the section planes meet the scan's surface but enclose no area")
        out.append(f"{layer_list(touch)} ({_z_text(bottoms, spec, lam, touch)}) "
                   f"{'is' if len(touch) == 1 else 'are'} empty: {why}")
    if narrow:
        out.append(f"{layer_list(narrow)} {'holds' if len(narrow) == 1 else 'hold'} only parts narrower than the "
                   f"{spec.tool * 1000:g} mm cutter: left empty")
    return out


def _policy_effect(v, faces, bottoms, raw, spec: SliceSpec, scan_mass, direction_deg) -> dict:
    """For the envelope and core policies: what the boards gain or lose against the
    sections at mid-board (prototype.effect), by design of the policy."""
    if spec.policy == "mid":
        return {}
    from .layers import layer_sections

    axis = unit_vectors(direction_deg)[1]
    mid = layer_sections(v, faces, bottoms, spec.board, "mid", spec.tolerance)
    step = "the {} policy against the mid-board sections (layer {})"
    gain = stack_volume_moments([_difference(r, m, what=step.format(spec.policy, k + 1))
                                 for k, (r, m) in enumerate(zip(raw, mid))], spec.pitch, spec.pitch)
    loss = stack_volume_moments([_difference(m, r, what=step.format(spec.policy, k + 1))
                                 for k, (r, m) in enumerate(zip(raw, mid))], spec.pitch, spec.pitch)
    plus, minus = effect(scan_mass, gain, 1.0, axis), effect(scan_mass, loss, -1.0, axis)
    what = "the union" if spec.policy == "envelope" else "the common part"
    return {f"the {spec.policy} policy (each board is {what} of the sections through it)":
            {k: plus[k] + minus[k] for k in plus}}


def _causes(comparison, spec, lam, bottoms, raw, secs, built, removed, tool, checks, scan_mass, proto_mass,
            uniform, moments, plan, height, hull, proto_hull, direction_deg, extra=None) -> dict:
    """Likely cause of each error of the comparison (prototype.likely_causes), from
    what is known to differ: material taken out or left by the cutter, rod holes,
    the top board against the scan's top, the densities of glue and rods,
    overlapping shells, and the first board against the base."""
    axis = unit_vectors(direction_deg)[1]
    n_drop = sum(r.dropped_parts for r in tool)
    n_thin = sum(r.thin_features for r in tool)
    effects = dict(extra or {})
    if n_drop or n_thin:
        label = " and ".join(b for b in (f"{n_drop} part(s) narrower than the cutter dropped" if n_drop else "",
                                         f"{n_thin} sliver(s) opened away" if n_thin else "") if b)
        effects[label] = effect(scan_mass, stack_volume_moments(removed, spec.pitch, spec.pitch), -1.0, axis)
    added = [_difference(b, s, what=f"the wood the cutter leaves on layer {k + 1}") if not s.is_empty else b
             for k, (b, s) in enumerate(zip(built, secs))]
    if any(a.area > 0 for a in added):
        effects["wood the cutter leaves in inside corners and narrow gaps"] = effect(
            scan_mass, stack_volume_moments(added, spec.pitch, spec.pitch), 1.0, axis)
    over = np.array([np.mean([c.overlap - 2 * c.inverted for c in cs]) for cs in checks]) * spec.pitch
    if np.any(over != 0):
        z = bottoms + 0.5 * spec.board
        dv = -float(over.sum())
        zc = float((over * z).sum() / over.sum()) if over.sum() else float(scan_mass.com[2])
        inverted = any(c.inverted > 0 for cs in checks for c in cs)
        effects["overlapping shells that the scan's volume counts twice"
                + (" and inside-out folds it subtracts" if inverted else "")] = {
            "volume": dv / scan_mass.volume, "h": dv * (zc - scan_mass.com[2]) / scan_mass.volume / scan_mass.com[2],
            "I_G_per_mass": 0.0}
    holes = [_intersection(_union_all([Point(c).buffer(0.5 * spec.hole, quad_segs=32) for c in plan.holes[k]],
                                      what=f"the rod holes of layer {k + 1}"), b,
                           what=f"the rod holes of layer {k + 1}")
             if len(plan.holes[k]) else None for k, b in enumerate(built)]
    if any(h is not None for h in holes):
        drilled = effect(scan_mass, stack_volume_moments(holes, spec.pitch, spec.pitch), -1.0, axis)
        label = "rod holes"
        if spec.rod_density > 0:
            rods = effect(scan_mass, moments[2].result() if moments[2].m > 0 else None, 1.0, axis)
            drilled = {k: drilled[k] + rods[k] for k in drilled}
            label = f"rod holes ({spec.hole * 1000:g} mm) less the rods ({spec.rod * 1000:g} mm) in them"
        effects[label] = drilled
    top = float(bottoms[-1] + spec.board)
    if abs(top - height) > 1e-6 and not built[-1].is_empty:
        cap = stack_volume_moments([built[-1]], 1.0, abs(top - height))
        if cap is not None:
            cap = MassProperties(volume=cap.volume, mass=cap.mass, density=1.0,
                                 com=cap.com + (0.0, 0.0, min(top, height)), inertia=cap.inertia)
        effects[f"the top board {'reaching' if top > height else 'stopping'} {abs(top - height) * 1000:.1f} mm "
                f"{'above' if top > height else 'below'} the scan's top"] = effect(
            scan_mass, cap, 1.0 if top > height else -1.0, axis)
    if uniform.mass != proto_mass.mass:
        def ig(mp):
            return float(axis @ mp.inertia @ axis) / mp.mass
        effects["glue films and rods denser than the board"] = {
            "volume": 0.0, "h": float(proto_mass.com[2] / uniform.com[2] - 1.0),
            "I_G_per_mass": ig(proto_mass) / ig(uniform) - 1.0}
    notes = {}
    gap = [k + 1 for k, s in enumerate(raw) if s.is_empty and all(c.segments == 0 for c in checks[k])]
    if gap:
        for key in ("volume", "I_G_per_mass", "h"):
            notes[key] = f"{layer_list(gap)} cut nothing of the scan (a gap in it)"
    base = base_difference(hull, proto_hull, scan_mass.com, proto_mass.com, direction_deg)
    first = {"mid": f"its section {0.5 * spec.board * 1000:g} mm up",
             "envelope": f"the union of its sections from 0 to {spec.board * 1000:g} mm",
             "core": f"the common part of its sections from 0 to {spec.board * 1000:g} mm"}[spec.policy]
    return likely_causes(comparison, base, effects, notes, first, spec.pitch)
