"""Part labels for the CNC: layer number and front arrow as single-stroke paths.

Each part of a layer is engraved with its label, e.g. ``37`` or ``37B`` (layer
37, part B), followed by an arrow that points toward the statue's front. The
label is cuttable geometry, not font text: open polylines (in m) that an
engraving tool follows, drawn from the stroke table :data:`GLYPHS` (no font
files, no DXF TEXT entities).

Layout, in the label's own frame: the text reads along +x with its baseline at
y = 0 and character height h (cell 0.6 h wide, advance 0.8 h); after a gap of
0.3 h comes the arrow, 1.5 h long, on the text's mid-line y = h/2, pointing
along +x. :func:`place_label` rotates the whole label so that the arrow points
to ``front_deg`` (degrees from +x toward +y, in the part's plan) and moves it
into the part.

Chirality: the arrow fixes the label's direction, so the only reflection that
could map the label onto itself is the one across the arrow's axis (the text's
mid-line). Every digit glyph is asymmetric about that line (the ``0`` is
slashed, the upper bowls of ``3`` and ``8`` are smaller than the lower ones), so
every label holding a digit reads wrong on a board turned over: the assembler
sees mirrored digits and knows the board is flipped.

Fit: the label's bounding rectangle, grown by ``margin + tool_diameter / 2`` on
every side, must lie inside the part minus the keep-out region. For a given
centre the largest height at which that rectangle still fits is computed
exactly, in closed form (the growing rectangle's first contact with a boundary
segment), so no bisection on the height is needed; only the centre is searched.
It starts at the pole of inaccessibility (GEOS polylabel, as
``shapely.maximum_inscribed_circle``), which is enough for most parts; when the
label does not reach ``max_height`` there, compass searches run from the pole
and from the best points of a coarse grid, on the outline simplified within 1 %
of the inscribed radius, and the best end is polished on the true outline.
Because the strokes lie inside the rectangle, the engraved grooves (the strokes
buffered by the clearance) lie inside the part; the rectangle is checked with
shapely's exact ``contains`` before the label is returned.

Example
-------
>>> from shapely.geometry import Point, box
>>> part = box(0.0, 0.0, 0.2, 0.1)                 # a 200 x 100 mm part, m
>>> holes = Point(0.1, 0.05).buffer(0.006)         # an alignment hole at its centre
>>> lab = place_label(part, "37B", front_deg=90.0, keep_out=holes, margin=0.002)
>>> lab.text, lab.height                           # the largest height fits
('37B', 0.012)
>>> part.difference(holes).contains(lab.bounds_polygon(0.002))
True
>>> tail, tip = lab.strokes[-2][0], lab.strokes[-2][-1]   # arrow shaft: tail -> tip
>>> [round(float(v), 6) for v in (tip - tail) / np.hypot(*(tip - tail))]   # toward +y
[0.0, 1.0]
>>> round(lab.length() * 1000)                     # engraving path, mm
125
>>> place_label(box(0, 0, 0.2, 0.004), "37B", 0.0) is None   # a 4 mm sliver: no room
True
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiLineString, Polygon

from ..errors import InputError
from . import robust

CELL_WIDTH = 0.6          # glyph cell width / height
ADVANCE = 0.8             # character advance / height
ARROW_GAP = 0.3           # gap between the text's last cell and the arrow / height
ARROW_LENGTH = 1.5        # arrow length / height
ARROW_HEAD = 0.3          # head length / arrow length
ARROW_BARB = 0.2          # head half-width / arrow length
_GRID = 14                # seed grid per side when the pole is not enough
_STARTS = 2               # compass searches from the best grid points
_CHUNK = 4096             # centre-segment pairs per block in _touch_height

_Stroke = tuple[tuple[float, float], ...]


def _arc(cx: float, cy: float, rx: float, ry: float, a0: float, a1: float) -> list[tuple[float, float]]:
    """Points of an elliptic arc from angle a0 to a1 (degrees, either sense), <= 20 deg apart."""
    n = max(2, math.ceil(abs(a1 - a0) / 20.0))
    a = np.radians(np.linspace(a0, a1, n + 1))
    return list(zip(cx + rx * np.cos(a), cy + ry * np.sin(a)))


def _glyph(*strokes) -> tuple[_Stroke, ...]:
    """Round to 1e-4 and clip to the cell [0, 0.6] x [0, 1]."""
    out = []
    for s in strokes:
        p = np.clip(np.round(np.asarray(s, dtype=float), 4), [0.0, 0.0], [CELL_WIDTH, 1.0])
        keep = np.r_[True, np.any(np.diff(p, axis=0) != 0, axis=1)]     # drop repeated points
        out.append(tuple((float(x), float(y)) for x, y in p[keep]))
    return tuple(out)


def _stroke_table() -> dict[str, tuple[_Stroke, ...]]:
    ring = _arc(0.3, 0.5, 0.3, 0.5, 90, 450)
    p_bowl = [(0, 0), (0, 1), (0.35, 1)] + _arc(0.35, 0.75, 0.25, 0.25, 90, -90) + [(0, 0.5)]
    six = _arc(0.3, 0.5, 0.3, 0.5, 45, 180) + _arc(0.3, 0.3, 0.3, 0.3, 180, 540)
    g = {
        "0": (ring, [(0.12, 0.2), (0.48, 0.8)]),                                   # slashed
        "1": ([(0.12, 0.78), (0.3, 1), (0.3, 0)], [(0.1, 0), (0.5, 0)]),
        "2": (_arc(0.3, 0.72, 0.28, 0.28, 165, -30) + [(0, 0), (0.6, 0)],),
        "3": (_arc(0.3, 0.765, 0.25, 0.235, 150, -90) + _arc(0.3, 0.265, 0.29, 0.265, 90, -150)[1:],),
        "4": ([(0.45, 0), (0.45, 1), (0, 0.32), (0.6, 0.32)],),
        "5": ([(0.56, 1), (0.1, 1), (0.07, 0.58)] + _arc(0.3, 0.3, 0.3, 0.3, 125, -140),),
        "6": (six,),
        "7": ([(0, 1), (0.6, 1), (0.2, 0)],),
        "8": (_arc(0.3, 0.77, 0.24, 0.23, -90, 270), _arc(0.3, 0.27, 0.3, 0.27, 90, 450)),
        "9": ([(0.6 - x, 1 - y) for x, y in six],),                               # 6 turned
        "A": ([(0, 0), (0.3, 1), (0.6, 0)], [(0.105, 0.35), (0.495, 0.35)]),
        "B": ([(0, 0), (0, 1), (0.38, 1)] + _arc(0.38, 0.77, 0.2, 0.23, 90, -90) + [(0, 0.54)],
              [(0, 0.54), (0.38, 0.54)] + _arc(0.38, 0.27, 0.22, 0.27, 90, -90) + [(0, 0)]),
        "C": (_arc(0.3, 0.5, 0.3, 0.5, 45, 315),),
        "D": ([(0, 0), (0, 1), (0.25, 1)] + _arc(0.25, 0.5, 0.35, 0.5, 90, -90) + [(0, 0)],),
        "E": ([(0.6, 1), (0, 1), (0, 0), (0.6, 0)], [(0, 0.5), (0.45, 0.5)]),
        "F": ([(0.6, 1), (0, 1), (0, 0)], [(0, 0.5), (0.45, 0.5)]),
        "G": (_arc(0.3, 0.5, 0.3, 0.5, 45, 360) + [(0.32, 0.5)],),
        "H": ([(0, 0), (0, 1)], [(0.6, 0), (0.6, 1)], [(0, 0.5), (0.6, 0.5)]),
        "I": ([(0.3, 0), (0.3, 1)], [(0.1, 1), (0.5, 1)], [(0.1, 0), (0.5, 0)]),
        "J": ([(0.6, 1)] + _arc(0.3, 0.3, 0.3, 0.3, 0, -180),),
        "K": ([(0, 0), (0, 1)], [(0.6, 1), (0, 0.35)], [(0.2, 0.5667), (0.6, 0)]),
        "L": ([(0, 1), (0, 0), (0.6, 0)],),
        "M": ([(0, 0), (0, 1), (0.3, 0.4), (0.6, 1), (0.6, 0)],),
        "N": ([(0, 0), (0, 1), (0.6, 0), (0.6, 1)],),
        "O": (ring,),
        "P": (p_bowl,),
        "Q": (ring, [(0.35, 0.25), (0.6, 0)]),
        "R": (p_bowl, [(0.3, 0.5), (0.6, 0)]),
        "S": (_arc(0.3, 0.75, 0.28, 0.25, 20, 270) + _arc(0.3, 0.25, 0.3, 0.25, 90, -160)[1:],),
        "T": ([(0, 1), (0.6, 1)], [(0.3, 1), (0.3, 0)]),
        "U": ([(0, 1)] + _arc(0.3, 0.3, 0.3, 0.3, 180, 360) + [(0.6, 1)],),
        "V": ([(0, 1), (0.3, 0), (0.6, 1)],),
        "W": ([(0, 1), (0.15, 0), (0.3, 0.6), (0.45, 0), (0.6, 1)],),
        "X": ([(0, 0), (0.6, 1)], [(0, 1), (0.6, 0)]),
        "Y": ([(0, 1), (0.3, 0.5), (0.6, 1)], [(0.3, 0.5), (0.3, 0)]),
        "Z": ([(0, 1), (0.6, 1), (0, 0), (0.6, 0)],),
        "-": ([(0.1, 0.5), (0.5, 0.5)],),
    }
    return {c: _glyph(*s) for c, s in g.items()}


GLYPHS: dict[str, tuple[tuple[tuple[float, float], ...], ...]] = _stroke_table()
"""Single-stroke glyphs on the unit cell x in [0, 0.6], y in [0, 1] (baseline y = 0):
each glyph is a tuple of strokes, each stroke an open polyline (a closed loop
repeats its first point)."""


def text_strokes(text: str, height: float) -> list[np.ndarray]:
    """Open polylines (k, 2), m, of ``text`` at character ``height``: baseline at
    y = 0, first cell at x = 0, advance 0.8 height. A space advances without
    strokes; any character without a glyph raises :class:`InputError`."""
    try:
        ok = math.isfinite(height) and height > 0
    except TypeError:
        ok = False
    if not ok:
        raise InputError(f"label text height must be a positive length in m, got {height!r}")
    bad = sorted({c for c in text if c != " " and c not in GLYPHS})
    if bad:
        raise InputError(f"label text {text!r}: no engraving glyph for {''.join(bad)!r}; "
                         "use 0-9, A-Z, '-' and spaces")
    out = []
    for i, c in enumerate(text):
        for s in GLYPHS.get(c, ()):
            out.append((np.asarray(s) + [i * ADVANCE, 0.0]) * height)
    return out


def arrow_strokes(length: float) -> list[np.ndarray]:
    """An arrow from (0, 0) to (length, 0): the shaft (tail -> tip) and the head
    (one barb -> tip -> other barb), open polylines in m."""
    if not (math.isfinite(length) and length > 0):
        raise InputError(f"arrow length must be a positive length in m, got {length!r}")
    a, b = ARROW_HEAD * length, ARROW_BARB * length
    return [np.array([[0.0, 0.0], [length, 0.0]]),
            np.array([[length - a, b], [length, 0.0], [length - a, -b]])]


@dataclass(frozen=True, eq=False)
class Label:
    """A placed label. ``strokes`` are the text's polylines followed by the
    arrow's two (shaft tail -> tip, then head), in the part's coordinates (m);
    ``anchor`` is the centre of the label's bounding rectangle."""
    text: str
    height: float
    strokes: tuple[np.ndarray, ...]
    anchor: tuple[float, float]

    def length(self) -> float:
        """Total engraving path length, m (tool moves between strokes excluded)."""
        return float(sum(np.hypot(*np.diff(s, axis=0).T).sum() for s in self.strokes))

    def bounds_polygon(self, pad: float = 0.0) -> shapely.Polygon | shapely.MultiPolygon:
        """The strokes buffered by ``pad`` (m): the area the grooves of a tool of
        diameter 2 pad remove. A Polygon, or a MultiPolygon when the glyphs stay
        apart; empty for pad = 0 (lines have no area)."""
        return robust.buffer(MultiLineString(list(self.strokes)), pad, what=f"the grooves of label {self.text}")


def _unit_layout(text: str) -> tuple[list[np.ndarray], np.ndarray, np.ndarray]:
    """Strokes of the label at height 1 in its own frame, the centre and the
    half-extents of their bounding rectangle."""
    strokes = text_strokes(text, 1.0)
    x0 = (len(text) - 1) * ADVANCE + CELL_WIDTH + ARROW_GAP if text else 0.0
    strokes += [s + [x0, 0.5] for s in arrow_strokes(ARROW_LENGTH)]
    pts = np.vstack(strokes)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    return strokes, (lo + hi) / 2, (hi - lo) / 2


def _segments(geom) -> np.ndarray:
    """All boundary segments (n, 2, 2) of a polygonal geometry."""
    segs = []
    for ring in shapely.get_parts(shapely.boundary(geom)):
        for part in shapely.get_parts(ring):
            c = shapely.get_coordinates(part)
            segs.append(np.stack([c[:-1], c[1:]], axis=1))
    return np.concatenate(segs) if segs else np.zeros((0, 2, 2))


def _touch_height(segs: np.ndarray, centres: np.ndarray, half: np.ndarray, r: float) -> np.ndarray:
    """For each centre (m, 2), in the label's frame: the height h at which the
    rectangle of half-extents half * h + r first touches a segment (n, 2, 2).

    In coordinates scaled by 1 / half, a point p is in the rectangle of height h
    when g(p) = max(|X| - r / ax, |Y| - r / ay) <= h. Along a segment g is convex
    and piecewise linear, so its minimum is at an end or at a kink: X = 0, Y = 0
    or |X| - |Y| = r / ax - r / ay, all of which are tried."""
    if not len(segs):
        return np.full(len(centres), np.inf)
    inv = 1.0 / np.asarray(half, dtype=float)
    rho = r * inv
    delta = rho[0] - rho[1]
    s = segs * inv
    p0 = s[None, :, 0, :] - (centres * inv)[:, None, :]      # (m, n, 2)
    d = s[:, 1, :] - s[:, 0, :]                               # (n, 2)
    x0, y0, dx, dy = p0[..., 0], p0[..., 1], d[:, 0], d[:, 1]

    def g(x, y):
        return np.maximum(np.abs(x) - rho[0], np.abs(y) - rho[1])

    with np.errstate(divide="ignore", invalid="ignore"):
        a0, b0 = x0 - y0, x0 + y0
        ia, ib, ix, iy = 1.0 / (dx - dy), 1.0 / (dx + dy), 1.0 / dx, 1.0 / dy
        t = np.stack([-x0 * ix, -y0 * iy, (delta - a0) * ia, (-delta - a0) * ia,
                      (delta - b0) * ib, (-delta - b0) * ib], axis=-1)
    t = np.fmax(np.fmin(t, 1.0), 0.0)                         # into [0, 1]; fmin/fmax drop NaN
    kinks = g(x0[..., None] + t * dx[:, None], y0[..., None] + t * dy[:, None]).min(axis=2)
    ends = np.minimum(g(x0, y0), g(x0 + dx, y0 + dy))
    return np.minimum(kinks, ends).min(axis=1)


def _polygons(geom) -> list[Polygon]:
    return robust.polygons(geom)


def place_label(part: Polygon, text: str, front_deg: float, *, keep_out=None,
                max_height: float = 0.012, min_height: float = 0.003, margin: float = 0.002,
                tool_diameter: float = 0.0) -> Label | None:
    """Place ``text`` and a front arrow pointing to ``front_deg`` (degrees from +x
    toward +y) inside ``part`` (m) minus ``keep_out`` (any shapely geometry, e.g.
    alignment-hole disks, or None), as large as fits with max_height as the cap.

    The label's bounding rectangle grown by margin + tool_diameter / 2 lies in
    the allowed region, so ``allowed.contains(label.bounds_polygon(margin +
    tool_diameter / 2))`` holds; None when no height >= min_height fits (or the
    allowed region is empty). ``part`` may also be a MultiPolygon."""
    for name, v in (("max_height", max_height), ("min_height", min_height)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"label {name} must be a positive length in m, got {v!r}")
    if min_height > max_height:
        raise InputError(f"label min_height {min_height} m exceeds max_height {max_height} m")
    for name, v in (("margin", margin), ("tool_diameter", tool_diameter)):
        if not (math.isfinite(v) and v >= 0):
            raise InputError(f"label {name} must be a length >= 0 in m, got {v!r}")
    if not math.isfinite(front_deg):
        raise InputError(f"label front direction must be finite degrees, got {front_deg!r}")
    unit, centre, half = _unit_layout(text)
    r = margin + tool_diameter / 2

    what = f"the room for label {text}"
    allowed = part if part.is_valid else robust.as_multipolygon(part)
    if keep_out is not None and not keep_out.is_empty:
        allowed = robust.difference(allowed, keep_out if keep_out.is_valid else robust.as_multipolygon(keep_out),
                                    what=what)
    comps = sorted(_polygons(allowed), key=lambda p: -p.area)
    if not comps:
        return None
    allowed = shapely.MultiPolygon(comps) if len(comps) > 1 else comps[0]
    shapely.prepare(allowed)

    th = math.radians(front_deg)
    cos, sin = math.cos(th), math.sin(th)
    to_frame = np.array([[cos, sin], [-sin, cos]])           # world -> label frame (rotate by -th)
    reach = half * max_height + r                              # the largest rectangle's half-extents

    def fit(geom):
        """The largest height at centres c (m, 2, label frame) against the boundary of geom."""
        segs = _segments(geom) @ to_frame.T
        seg_lo, seg_hi = segs.min(axis=1), segs.max(axis=1)

        def height_at(c: np.ndarray) -> np.ndarray:
            w = c @ to_frame                                   # back to the world
            h = np.full(len(c), -np.inf)
            inside = shapely.contains_xy(allowed, w[:, 0], w[:, 1])
            if inside.any():
                ci = c[inside]
                # only segments that the largest rectangle around some centre can reach
                near = np.all((seg_hi >= ci.min(axis=0) - reach) & (seg_lo <= ci.max(axis=0) + reach), axis=1)
                sn = segs[near]
                m = max(1, _CHUNK // max(1, len(sn)))          # centres per block: arrays stay in cache
                h[inside] = np.concatenate([_touch_height(sn, ci[i:i + m], half, r)
                                            for i in range(0, len(ci), m)])
            return h
        return height_at, segs

    moves = np.array([(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)], float)
    moves[4:] /= math.sqrt(2)

    def climb(height_at, c: np.ndarray, h: np.ndarray, step: np.ndarray, stop: float):
        """Compass searches from the centres c (s, 2), all at once: each moves to its
        best neighbour at distance step when that fits larger, else halves the step."""
        c, h, step = c.copy(), h.copy(), step.copy()
        for _ in range(80):
            run = np.flatnonzero((step >= stop) & (h < max_height))
            if not len(run):
                break
            trial = c[run, None, :] + step[run, None, None] * moves          # (s, 8, 2)
            ht = height_at(trial.reshape(-1, 2)).reshape(len(run), len(moves))
            j = np.argmax(ht, axis=1)
            better = ht[np.arange(len(run)), j] > h[run]
            up = run[better]
            c[up], h[up] = trial[better, j[better]], ht[better, j[better]]
            step[run[~better]] *= 0.5
        return c, h

    # the pole of inaccessibility of the largest pieces and their centroids: enough
    # for most parts
    exact, _ = fit(allowed)
    seeds, radius = [], 0.0
    for p in comps[:3]:
        tol = max(1e-7, 0.05 * p.area / p.length)
        mic = shapely.get_coordinates(robust.safe_op(shapely.maximum_inscribed_circle, p, tol, what=what))
        seeds += [mic[0], shapely.get_coordinates(p.centroid)[0]]
        radius = max(radius, float(np.hypot(*(mic[1] - mic[0]))), tol)
    c = np.asarray(seeds) @ to_frame.T
    h = exact(c)
    k = int(np.argmax(h))
    best_c, best_h = c[k], float(h[k])
    if best_h < max_height:
        # search on the outline simplified within eps, from the best seed and from the
        # best points of a grid over the region; then the best end exactly
        eps = 0.01 * radius
        approx, segs = fit(robust.simplify(allowed, eps, what=what))
        lo, hi = segs.reshape(-1, 2).min(axis=0), segs.reshape(-1, 2).max(axis=0)
        spacing = (hi - lo) / (_GRID + 1)
        u = [np.linspace(lo[i], hi[i], _GRID + 2)[1:-1] for i in (0, 1)]
        grid = np.stack(np.meshgrid(*u), axis=-1).reshape(-1, 2)
        hg = approx(grid)
        starts, steps = [best_c], [0.5 * radius]
        for k in np.argsort(-hg):
            if len(starts) > _STARTS or not np.isfinite(hg[k]):
                break
            if not any(np.all(np.abs(grid[k] - e) <= 1.5 * spacing) for e in starts):
                starts.append(grid[k])                         # not next to a start already
                steps.append(0.5 * float(spacing.max()))
        starts = np.asarray(starts)
        ends, _ = climb(approx, starts, approx(starts), np.asarray(steps),
                        max(1e-3 * radius, 2e-3 * max_height))
        h = exact(ends)
        k = int(np.argmax(h))
        if h[k] > best_h:
            best_c, best_h = ends[k], float(h[k])
        if np.isfinite(best_h):                                # polish on the true outline
            c, h = climb(exact, best_c[None], np.array([best_h]), np.array([2 * eps]), eps / 8)
            best_c, best_h = c[0], float(h[0])

    height = min(max_height, float(best_h) * (1 - 1e-6))
    if not height >= min_height:
        return None
    anchor = best_c @ to_frame                                 # the label's centre, world
    corners = np.array([(-1, -1), (1, -1), (1, 1), (-1, 1)], float)
    for _ in range(3):
        # exact check of the grown rectangle, which holds every groove (the strokes
        # buffered by r, shapely's buffer polygon being inscribed in the true one);
        # shrink a little if a rounding tie fails it
        rect = Polygon((corners * (half * height + r)) @ to_frame + anchor)
        if allowed.contains(rect):
            strokes = tuple(_frozen(((s - centre) * height) @ to_frame + anchor) for s in unit)
            return Label(text, height, strokes, (float(anchor[0]), float(anchor[1])))
        height *= 0.999
        if height < min_height:
            break
    return None


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=float)
    a.setflags(write=False)
    return a
