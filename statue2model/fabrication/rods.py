"""Alignment rods: vertical bars through the stacked boards that register each layer.

A rod of diameter ``rod`` passes through holes of diameter ``hole`` = rod +
clearance. A hole centre is admissible in a part when the hole keeps a wall of at
least ``wall`` to the part's edge, i.e. the centre lies in the part eroded by
hole/2 + wall. A rod through layers a..b needs its centre admissible in all of
them; each *segment* [a, b] of the stack gets its own rods.

Rules (thesis ch. 6.2.2: two bars per layer):

* every part (island) of every layer gets two holes, as far apart as the common
  admissible region of the segment allows, and at least ``spread`` times the
  largest spacing that part alone would allow (so a segment stops where the stack
  narrows, e.g. at a neck, instead of pinning a torso with two rods 2 cm apart);
  where the stack splits into several island groups (legs), each group gets its
  own pair;
* a part too small for a hole with its walls, or for two, gets what fits (one or
  none) and is reported;
* segments are found greedily from the base up and made as long as the rules
  allow; consecutive segments share one layer, which then carries both pairs of
  holes (at least hole + wall apart), so every glue joint is crossed by rods;
  a joint no pair of rods can cross is reported with the reason.

Example
-------
>>> from shapely.geometry import MultiPolygon, Point
>>> stack = [MultiPolygon([Point(0, 0).buffer(0.10 - 0.002 * k)]) for k in range(20)]
>>> plan = place_rods(stack, pitch=0.0095, board=0.009, hole=0.0082, wall=0.005)
>>> len(plan.segments), [len(h) for h in plan.holes][:3]
(1, [2, 2, 2])
>>> round(plan.rods[0].length, 4)                     # through all 20 boards
0.1895
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Point, Polygon

from ..errors import InputError
from . import robust

EXTRA = 1e-4
"""Extra inset of hole centres (m), so the wall holds with margin after rounding."""


@dataclass(frozen=True)
class Rod:
    """One vertical bar: centre (x, y) in m, through layers first..last (inclusive)."""

    x: float
    y: float
    first: int
    last: int
    z_bottom: float
    z_top: float

    @property
    def length(self) -> float:
        return self.z_top - self.z_bottom


@dataclass(frozen=True)
class RodPlan:
    """Rods, the hole centres they make in each layer, and what could not be done.

    rods        : tuple of Rod
    segments    : tuple of (first, last) layer ranges, bottom first
    holes       : per layer, an (n, 2) array of hole centres, m
    hole        : hole diameter, m
    unaligned   : glue joints (k, k + 1) that no rod crosses
    warnings    : one line per problem (layer and part numbers are 1-based, as engraved)
    """

    rods: tuple
    segments: tuple
    holes: tuple
    hole: float
    unaligned: tuple
    warnings: tuple

    def to_dict(self) -> dict:
        return {
            "hole_diameter": self.hole,
            "segments": [[a + 1, b + 1] for a, b in self.segments],
            "rods": [{"x": r.x, "y": r.y, "first_layer": r.first + 1, "last_layer": r.last + 1,
                      "z_bottom": r.z_bottom, "z_top": r.z_top, "length": r.length} for r in self.rods],
            "unaligned_joints": [[k + 1, k + 2] for k in self.unaligned],
        }


def _parts(section: MultiPolygon) -> list[Polygon]:
    return list(robust.as_multipolygon(section).geoms)


def _diameter(points: np.ndarray) -> tuple[float, np.ndarray]:
    """Farthest pair among ``points`` (n, 2): (distance, (2, 2))."""
    if len(points) == 1:
        return 0.0, np.vstack([points[0], points[0]])
    if len(points) > 3:
        hull = shapely.convex_hull(shapely.multipoints(points))
        if isinstance(hull, Polygon):
            points = np.asarray(hull.exterior.coords)[:-1]
    d2 = ((points[:, None, :] - points[None, :, :]) ** 2).sum(axis=-1)
    i, j = np.unravel_index(np.argmax(d2), d2.shape)
    return float(np.sqrt(d2[i, j])), np.vstack([points[i], points[j]])


def _vertices(geom) -> np.ndarray:
    return shapely.get_coordinates(geom.boundary if not geom.is_empty else geom)


@dataclass
class _Part:
    layer: int
    index: int
    poly: Polygon
    admissible: object      # shapely geometry of admissible hole centres


@dataclass
class _Link:
    """Part ``lower`` of layer k glued to part ``upper`` of layer k + 1."""

    lower: _Part
    upper: _Part
    capacity: int           # rods that can cross this joint: 0, 1 or 2
    need: float             # least spacing of two rods crossing it (strict rule), m


class _Planner:
    def __init__(self, sections, hole, wall, spread):
        self.hole = hole
        self.wall = wall
        self.inset = 0.5 * hole + wall + EXTRA
        self.sep = hole + wall + EXTRA    # least centre distance of two holes
        self.parts: list[list[_Part]] = []
        for k, sec in enumerate(sections):
            self.parts.append([_Part(k, i, poly, robust.buffer(poly, -self.inset, what=f"the room for rod holes in "
                                                                          f"layer {k + 1} part {_letter(i)}"))
                               for i, poly in enumerate(_parts(sec))])
        self.admissible = [robust.union_all([p.admissible for p in layer],
                                            what=f"the room for rod holes in layer {k + 1}") if layer else Polygon()
                           for k, layer in enumerate(self.parts)]
        self.links: list[list[_Link]] = []
        for k in range(len(self.parts) - 1):
            row = []
            for lo in self.parts[k]:
                for up in self.parts[k + 1]:
                    what = f"the rod holes through {_name(lo)} and {_name(up)}"
                    if not lo.poly.intersects(up.poly) or robust.intersection(lo.poly, up.poly, what=what).area <= 0:
                        continue
                    common = robust.intersection(lo.admissible, up.admissible, what=what)
                    if common.is_empty:
                        cap, room = 0, 0.0
                    else:
                        room, _ = _diameter(_vertices(common))
                        cap = 2 if room >= self.sep else 1
                    row.append(_Link(lo, up, cap, max(self.sep, spread * room)))
            self.links.append(row)

    def plan(self, a: int, b: int, region):
        """Hole centres of rods through layers a..b, inside ``region`` (their common
        admissible set), or None with the first joint that fails."""
        pieces = [g for g in shapely.get_parts(region) if isinstance(g, Polygon) and not g.is_empty]
        if not pieces:
            return None, (a, None, "no common room for a rod")
        reps = np.array([shapely.get_coordinates(g.representative_point())[0] for g in pieces])
        # signature of each piece: the part that holds it in every layer of the segment
        sig = np.full((len(pieces), b - a + 1), -1, dtype=int)
        for col, k in enumerate(range(a, b + 1)):
            for part in self.parts[k]:
                inside = shapely.contains_xy(part.poly, reps[:, 0], reps[:, 1])
                sig[inside, col] = part.index
        groups: dict[tuple, list[int]] = {}
        for n, row in enumerate(sig):
            groups.setdefault(tuple(row), []).append(n)
        centres: list[np.ndarray] = []
        for members in sorted(groups.values(), key=lambda m: -sum(pieces[n].area for n in m)):
            pts = np.vstack([_vertices(pieces[n]) for n in members])
            dist, pair = _diameter(pts)
            chosen = pair if dist >= self.sep else reps[members[:1]]
            for c in chosen:
                if all(np.hypot(*(c - o)) >= self.sep for o in centres):
                    centres.append(c)
        centres = np.array(centres)
        for k in range(a, b):
            for link in self.links[k]:
                if link.capacity == 0:
                    continue
                both = (shapely.contains_xy(link.lower.poly, centres[:, 0], centres[:, 1])
                        & shapely.contains_xy(link.upper.poly, centres[:, 0], centres[:, 1]))
                crossing = centres[both]
                if len(crossing) < link.capacity:
                    return None, (k, link, f"{len(crossing)} rod(s) can cross it, {link.capacity} needed")
                if link.capacity == 2:
                    spread, _ = _diameter(crossing)
                    if spread < link.need:
                        return None, (k, link, f"its rods could be only {spread * 1000:.0f} mm apart "
                                               f"({link.need * 1000:.0f} mm wanted)")
        return centres, None

    def joint_plan(self, a: int, keep_out):
        """Rods through layers a and a + 1 only: for each glued pair of parts, the
        farthest pair of centres (or one) their common room leaves, clear of
        ``keep_out`` and of each other."""
        centres: list[np.ndarray] = []
        for link in sorted(self.links[a], key=lambda lk: -lk.capacity):
            if link.capacity == 0:
                continue
            what = f"the rod holes through {_name(link.lower)} and {_name(link.upper)}"
            room = robust.intersection(link.lower.admissible, link.upper.admissible, what=what)
            blocked = [keep_out] if keep_out is not None else []
            blocked += [Point(c).buffer(self.sep + EXTRA, 32) for c in centres]
            if blocked:
                room = robust.difference(room, robust.union_all(blocked, what=what), what=what)
            if room.is_empty:
                continue
            dist, pair = _diameter(_vertices(room))
            if dist >= self.sep:
                centres.extend(pair)
            else:
                centres.append(shapely.get_coordinates(room.representative_point())[0])
        if not centres:
            return None, (a, None, "no common room for a rod")
        return np.array(centres), None

    def crossing(self, link: _Link, centres: np.ndarray) -> int:
        if len(centres) == 0:
            return 0
        return int(np.sum(shapely.contains_xy(link.lower.poly, centres[:, 0], centres[:, 1])
                          & shapely.contains_xy(link.upper.poly, centres[:, 0], centres[:, 1])))


def place_rods(sections, pitch: float, board: float, hole: float, wall: float,
               spread: float = 0.5) -> RodPlan:
    """Plan the alignment rods of a stack of layer outlines (m; layer k's board
    spans z = k pitch .. k pitch + board). See the module docstring."""
    if not (hole > 0 and wall >= 0 and 0 <= spread <= 1):
        raise InputError("rod holes need a positive diameter, a wall >= 0 and a spread in [0, 1]")
    planner = _Planner(sections, hole, wall, spread)
    n = len(sections)
    warnings: list[str] = []
    if n > 1 and all(link.capacity == 0 for row in planner.links for link in row):
        raise InputError(f"a {hole * 1000:.1f} mm rod hole with a {wall * 1000:g} mm wall does not fit through "
                         "any two neighbouring layers: choose a thinner --rod or a smaller --wall")
    for layer in planner.parts:
        for part in layer:
            if part.admissible.is_empty:
                width = 2 * _inradius(part.poly)
                warnings.append(f"{_name(part)} is too small for a {hole * 1000:.1f} mm hole with a "
                                f"{wall * 1000:g} mm wall (about {width * 1000:.0f} mm wide): "
                                "no alignment rod, place it by its outline")

    holes: list[list[np.ndarray]] = [[] for _ in range(n)]
    segments, rods, unaligned = [], [], []
    a = 0
    keep_out = None
    while a < n - 1:
        start = planner.admissible[a] if keep_out is None else robust.difference(
            planner.admissible[a], keep_out, what=f"the room for rod holes in layer {a + 1}")
        best, region, b = None, start, a
        while b + 1 < n:
            cand = robust.intersection(region, planner.admissible[b + 1],
                                       what=f"the common room for rods through layers {a + 1}-{b + 2}")
            centres, failure = planner.plan(a, b + 1, cand)
            if centres is None:
                break
            best, region, b = centres, cand, b + 1
        if best is None:
            # not even one joint under the strict rule: rods through this joint only, as many as fit
            best, failure = planner.joint_plan(a, keep_out)
            b = a + 1
        if best is None:
            k, link, why = failure
            where = f"{_name(link.lower)} on {_name(link.upper)}" if link is not None else f"layers {a + 1}-{a + 2}"
            warnings.append(f"joint {a + 1}/{a + 2} has no alignment rods ({where}: {why})")
            unaligned.append(a)
            a += 1
            keep_out = None
            continue
        segments.append((a, b))
        for k in range(a, b):
            for link in planner.links[k]:
                got = planner.crossing(link, best)
                if link.capacity == 0 or got < link.capacity:
                    if link.capacity == 0:
                        reason = "they share no room for a hole with its walls"
                    elif got == 0:
                        reason = f"no rod crosses it (the holes already in layer {k + 1} leave no room)"
                    else:
                        reason = "one rod crosses it (no room for a second)"
                    warnings.append(f"joint {k + 1}/{k + 2}: {_name(link.lower)} on {_name(link.upper)}: {reason}")
        for x, y in best:
            rods.append(Rod(float(x), float(y), a, b, a * pitch, b * pitch + board))
        for k in range(a, b + 1):
            holes[k].extend(best)
        if b >= n - 1:
            break
        keep_out = robust.union_all([Point(c).buffer(planner.sep + EXTRA, 32) for c in best],
                                    what=f"the rod holes of layer {b + 1}")
        a = b
    hole_arrays = tuple(np.array(h).reshape(-1, 2) for h in holes)
    return RodPlan(rods=tuple(rods), segments=tuple(segments), holes=hole_arrays, hole=hole,
                   unaligned=tuple(unaligned), warnings=tuple(warnings))


def _letter(index: int) -> str:
    return chr(ord("A") + index) if index < 26 else str(index + 1)


def _name(part: _Part) -> str:
    return f"layer {part.layer + 1} part {_letter(part.index)}"


def _inradius(poly: Polygon) -> float:
    from shapely.ops import polylabel

    centre = polylabel(poly, tolerance=1e-5)
    return float(poly.exterior.distance(centre))


def check_holes(sections, plan: RodPlan, wall: float, tol: float = 1e-9) -> list[str]:
    """Problems with the planned holes: a hole not wholly inside a part with ``wall``
    to spare, or two holes closer than ``wall``. Empty when all is well."""
    problems = []
    r = 0.5 * plan.hole
    for k, (sec, centres) in enumerate(zip(sections, plan.holes)):
        for c in centres:
            p = Point(c)
            holder = [poly for poly in sec.geoms if poly.contains(p)]
            if not holder:
                problems.append(f"layer {k + 1}: hole at {c} is outside every part")
                continue
            margin = holder[0].boundary.distance(p) - r
            if margin < wall - tol:
                problems.append(f"layer {k + 1}: hole at {c} leaves a {margin * 1000:.3f} mm wall")
        for i in range(len(centres)):
            for j in range(i + 1, len(centres)):
                gap = np.hypot(*(centres[i] - centres[j])) - 2 * r
                if gap < wall - tol:
                    problems.append(f"layer {k + 1}: holes {i} and {j} leave a {gap * 1000:.3f} mm wall")
    return problems
