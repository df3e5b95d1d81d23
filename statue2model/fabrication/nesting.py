"""True-shape nesting of flat CNC parts on rectangular sheets.

The OSB layers of a stacked-board prototype are cut from panels (sheets) of
size W x H; :func:`nest` lays the parts out, all lengths in m. A part is a
shapely Polygon in its own coordinates; its :class:`Placement` rotates it by
``angle_deg`` about its own origin (0, 0), counter-clockwise, then translates it
by (dx, dy) into the sheet's frame, whose corner is (0, 0) and which spans
[0, W] x [0, H].

Method (raster + FFT, bottom-left fill, first-fit decreasing):

* the sheet is a grid of square cells of side ``grid``; each part, at each
  candidate angle, is rasterised to a mask of the cells whose centres lie in
  the part's outline buffered by ``spacing / 2`` plus half a cell diagonal
  (and a little more, to cover the buffer's polygonal arcs). Every cell the
  part's ``spacing / 2`` buffer touches is therefore marked, so two parts whose
  masks share no cell are at least ``spacing`` apart - exactly, not roughly.
  Holes are ignored for collision (nothing is nested inside a ring);
* a part may only sit on lattice positions (translations that move its mask by
  whole cells) for which its outline keeps ``edge_margin`` from the sheet's
  edges; the overlap of the mask with the sheet's occupancy at every lattice
  position at once is one FFT correlation (the sheet's transform is kept until
  a part is added to it, the mask's is computed once per angle), skipped when a
  correlation on blocks of 4 x 4 cells already shows the part cannot fit;
* the parts are taken by decreasing area; each goes to the first sheet where
  it fits, at the free position of least x (then least y) over the candidate
  angles - the sheet fills from its short left edge towards the right; a new
  sheet is opened when none fits. Every chosen position is confirmed cell by
  cell on the boolean grid, and the result is checked exactly with shapely
  (:func:`check_nesting`) before it is returned.

Candidate angles: ``angles``; when these hold all four quarter turns (the
default, orientation free), also each of them applied after turning the part's
minimum rotated rectangle square to the axes - a few % denser for elongated
parts. Any other list (say ``(0,)`` or ``(0, 180)`` to keep the board's grain
direction) is used as it is.

Example
-------
>>> from shapely.geometry import Point, box
>>> parts = [Point(0, 0).buffer(0.2), box(0, 0, 0.5, 0.1), Point(1, 1).buffer(0.1)]
>>> n = nest(parts, sheet_size=(1.0, 0.5), spacing=0.01, grid=0.01,
...          names=["disc", "bar", "small disc"])
>>> n.n_sheets, len(n.placements), [p.part for p in n.placements]
(1, 3, [0, 1, 2])
>>> check_nesting(parts, n)
[]
>>> placed = n.placements[1].apply(parts[1])          # the bar on its sheet
>>> round(placed.area, 3), 0 <= placed.bounds[0] and placed.bounds[2] <= 1.0
(0.05, True)
>>> nest([box(0, 0, 1.2, 0.1)], (1.0, 0.5), spacing=0.01, names=["plank"])
Traceback (most recent call last):
...
statue2model.errors.InputError: plank (1200 x 100 mm) does not fit on a 1000 x 500 mm sheet ...
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise

import numpy as np
import scipy.fft as sfft
import shapely
from shapely import affinity
from shapely.geometry import Polygon

from ..errors import InputError
from . import robust

# Absolute slack (m) by which every guarantee is kept with room to spare, far
# above the rounding of coordinates ~1 m and far below any cutting tolerance.
_EPS = 1e-9
# buffer arcs: segments per quarter circle; the radius is scaled so that the
# polygonal arc lies outside the true circle (see _masks)
_QUAD_SEGS = 8
_MAX_CELLS = 10_000_000    # cells per sheet: memory and time grow with it
# coarse screen: blocks of _C x _C cells (see _Sheet.maybe)
_C = 4


@dataclass(frozen=True)
class Placement:
    """Where one part goes: rotate by ``angle_deg`` (counter-clockwise, about the
    part's own origin), then translate by (dx, dy), onto sheet ``sheet``."""

    part: int
    sheet: int
    angle_deg: float
    dx: float
    dy: float

    def _cos_sin(self) -> tuple[float, float]:
        # the same cosine and sine as shapely.affinity.rotate
        a = math.radians(self.angle_deg)
        c, s = math.cos(a), math.sin(a)
        if abs(c) < 2.5e-16:
            c = 0.0
        if abs(s) < 2.5e-16:
            s = 0.0
        return c, s

    def transform(self, xy: np.ndarray) -> np.ndarray:
        """(n, 2) points in the part's coordinates -> (n, 2) in the sheet's."""
        xy = np.asarray(xy, dtype=float)
        c, s = self._cos_sin()
        x, y = xy[..., 0], xy[..., 1]
        return np.stack([c * x - s * y + self.dx, s * x + c * y + self.dy], axis=-1)

    def apply(self, geom):
        """The shapely geometry ``geom`` (in the part's coordinates) placed on its sheet."""
        return affinity.translate(affinity.rotate(geom, self.angle_deg, origin=(0.0, 0.0)),
                                  self.dx, self.dy)


@dataclass(frozen=True)
class Nesting:
    """The layout: one placement per input part, in input order."""

    placements: tuple[Placement, ...]
    n_sheets: int
    sheet_size: tuple[float, float]
    spacing: float
    utilisation: tuple[float, ...]

    @property
    def material_use(self) -> float:
        """Total part area / total area of the sheets used."""
        if self.n_sheets == 0:
            return 0.0
        return float(np.mean(self.utilisation))

    def parts_on(self, sheet: int) -> list[Placement]:
        """The placements on sheet ``sheet`` (0-based), in input order."""
        return [p for p in self.placements if p.sheet == sheet]


@dataclass
class _Mask:
    """One part at one angle, rasterised on the sheet lattice."""

    angle: float
    cells: np.ndarray        # (mx, my) bool, cell (i, j) centred at origin + ((i, j) + 0.5) grid
    origin: tuple[float, float]   # mask corner in the rotated part's coordinates
    lo: tuple[int, int]      # least lattice offset (cells) keeping the edge margin
    hi: tuple[int, int]      # greatest one
    n: int                   # marked cells
    size: tuple[float, float]  # the rotated outline's width and height, m
    fft: np.ndarray | None = None
    core_fft: np.ndarray | None = None   # see _Sheet.maybe
    core_empty: bool = False


# ----------------------------------------------------------------------------- input


def _check_args(parts, sheet_size, spacing, edge_margin, grid, angles, names):
    try:
        W, H = (float(v) for v in sheet_size)
    except (TypeError, ValueError):
        raise InputError(f"sheet size must be two numbers (width, height) in m, "
                         f"got {sheet_size!r}") from None
    if not (math.isfinite(W) and math.isfinite(H) and W > 0 and H > 0):
        raise InputError(f"sheet size must be positive, got {W} x {H} m")
    for label, v in (("spacing", spacing), ("edge margin", edge_margin)):
        if not (isinstance(v, (int, float, np.number)) and math.isfinite(v) and v >= 0):
            raise InputError(f"{label} must be >= 0 m, got {v!r}")
    if not (isinstance(grid, (int, float, np.number)) and math.isfinite(grid) and grid > 0):
        raise InputError(f"grid must be positive, got {grid!r}")
    cells = (W / grid + 2) * (H / grid + 2)
    if cells > _MAX_CELLS:
        raise InputError(f"grid {grid:g} m gives {cells:.3g} cells per sheet (at most "
                         f"{_MAX_CELLS:.0e}); use a coarser grid")
    try:
        ang = [float(a) % 360.0 for a in angles]
    except (TypeError, ValueError):
        raise InputError(f"angles must be numbers in degrees, got {angles!r}") from None
    if not ang or not all(math.isfinite(a) for a in ang):
        raise InputError(f"angles must be a non-empty list of finite degrees, got {angles!r}")
    parts = list(parts)
    if not parts:
        raise InputError("no parts to nest")
    if names is not None:
        names = [str(s) for s in names]
        if len(names) != len(parts):
            raise InputError(f"{len(names)} names for {len(parts)} parts")
    for i, p in enumerate(parts):
        name = names[i] if names is not None else f"part {i}"
        if not isinstance(p, Polygon):
            raise InputError(f"{name} is a {type(p).__name__}, not a Polygon "
                             "(nest the islands of a MultiPolygon as separate parts)")
        if p.is_empty or not np.all(np.isfinite(shapely.get_coordinates(p))):
            raise InputError(f"{name} is empty or has non-finite coordinates")
        if not p.is_valid or p.area <= 0:
            raise InputError(f"{name} is not a valid polygon of positive area "
                             f"({shapely.is_valid_reason(p)})")
    return parts, (W, H), float(spacing), float(edge_margin), float(grid), ang, names


def _candidate_angles(part: Polygon, angles: list[float]) -> list[float]:
    """``angles``, plus each of them after aligning the part's minimum rotated
    rectangle with the axes when ``angles`` holds all four quarter turns."""
    out = list(angles)
    free = all(any(abs(a - q) < 1e-9 for a in angles) for q in (0.0, 90.0, 180.0, 270.0))
    rect = np.asarray(shapely.minimum_rotated_rectangle(part).exterior.coords) if free else []
    if len(rect) >= 3:
        e = rect[1] - rect[0]
        theta = (-math.degrees(math.atan2(e[1], e[0]))) % 90.0   # turn that aligns an edge with x
        if 1e-6 < theta < 90.0 - 1e-6:
            out += [(a + theta) % 360.0 for a in angles]
    res: list[float] = []
    for a in out:                       # drop duplicates, keep order
        if all(min(abs(a - b), 360 - abs(a - b)) > 1e-9 for b in res):
            res.append(a)
    return res


def _rotate(xy: np.ndarray, angle: float) -> np.ndarray:
    return Placement(0, 0, angle, 0.0, 0.0).transform(xy)


# ----------------------------------------------------------------------------- raster


def _fill(rings: list[np.ndarray], x0: float, y0: float, g: float, mx: int, my: int) -> np.ndarray:
    """(mx, my) bool: cell centres x0 + (i + .5) g, y0 + (j + .5) g inside the closed
    rings (even-odd rule; scanline over the rows of centres each edge crosses)."""
    xy = np.concatenate(rings)
    # row threshold of each vertex: an edge crosses the rows from the lower threshold
    # of its ends to the higher one, exclusive; shared vertices give each row an even count
    t = np.ceil((xy[:, 1] - y0) / g - 0.5).astype(np.int64)
    starts = np.cumsum([0] + [len(r) for r in rings])
    first = np.concatenate([np.arange(a, b - 1) for a, b in pairwise(starts)])
    ta, tb = t[first], t[first + 1]
    lo, n = np.minimum(ta, tb), np.abs(tb - ta)
    if not n.any():
        return np.zeros((mx, my), dtype=bool)
    e = np.repeat(first, n)
    row = np.repeat(lo, n) + (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n))
    (xa, ya), (xb, yb) = xy[e].T, xy[e + 1].T
    x = xa + (y0 + (row + 0.5) * g - ya) * (xb - xa) / (yb - ya)
    k = np.lexsort((x, row))
    row, x = row[k], x[k]
    # cell i is inside from the crossing at which it enters to the one it leaves:
    # centres x0 + (i + .5) g in [x_enter, x_leave)
    i = np.clip(np.ceil((x - x0) / g - 0.5), 0, mx).astype(np.int64)
    sign = np.where(np.arange(len(x)) % 2 == 0, 1.0, -1.0)
    keep = (row >= 0) & (row < my)
    diff = np.bincount(row[keep] * (mx + 1) + i[keep], weights=sign[keep],
                       minlength=my * (mx + 1)).reshape(my, mx + 1)
    return (np.cumsum(diff, axis=1)[:, :mx] > 0.5).T


def _masks(part: Polygon, angles: list[float], sheet: tuple[float, float], spacing: float,
           margin: float, g: float, name: str = "a part") -> list[_Mask]:
    """The part's masks at the candidate angles at which it fits on an empty sheet
    (``name``: the part, in an error)."""
    W, H = sheet
    shell = Polygon(part.exterior)
    # the cells to mark are those whose centre is within r of the part's outline; the
    # buffer polygon's arcs are chords of a circle, so the radius is raised to put the
    # chords outside the circle of radius r, and by 2 % more for the input
    # simplification GEOS does (1 % of the distance)
    r = spacing / 2 + g * math.sqrt(0.5) + 2 * _EPS
    rb = 1.02 * r / math.cos(math.pi / (4 * _QUAD_SEGS)) + _EPS
    halo = robust.buffer(shell, rb, quad_segs=_QUAD_SEGS, what=f"the spacing band around {name} (nesting)")
    halo_rings = [np.asarray(rr.coords) for poly in getattr(halo, "geoms", [halo])
                  for rr in [poly.exterior, *poly.interiors]]
    body = np.asarray(part.exterior.coords)
    out = []
    for a in angles:
        xy = _rotate(body, a)
        bx0, by0 = xy.min(axis=0)
        bx1, by1 = xy.max(axis=0)
        rings = [_rotate(rr, a) for rr in halo_rings]
        allxy = np.concatenate(rings)
        hx0, hy0 = allxy.min(axis=0)
        hx1, hy1 = allxy.max(axis=0)
        # mask corner on the lattice that puts the outline exactly margin + eps from
        # the sheet's low edges at offset lo, and lies at or below the halo's corner
        kx = math.floor((hx0 - bx0 + margin + _EPS) / g)
        ky = math.floor((hy0 - by0 + margin + _EPS) / g)
        x0 = bx0 - margin - _EPS + kx * g
        y0 = by0 - margin - _EPS + ky * g
        nx_ = math.floor((W - 2 * margin - 2 * _EPS - (bx1 - bx0)) / g)
        ny_ = math.floor((H - 2 * margin - 2 * _EPS - (by1 - by0)) / g)
        if nx_ < 0 or ny_ < 0:
            continue
        mx = math.ceil((hx1 - x0) / g) + 1
        my = math.ceil((hy1 - y0) / g) + 1
        cells = _fill(rings, x0, y0, g, mx, my)
        out.append(_Mask(a, cells, (x0, y0), (kx, ky), (kx + nx_, ky + ny_), int(cells.sum()),
                         (bx1 - bx0, by1 - by0)))
    return out


# ----------------------------------------------------------------------------- sheets


def _core(cells: np.ndarray) -> np.ndarray:
    """core[k, l] = all of cells[_C k - _C + 1 .. _C k + _C - 1, same in l] (outside: False)."""
    w = 2 * _C - 1
    c = np.pad(cells, _C - 1).astype(np.int32)
    for axis in (0, 1):
        cs = np.cumsum(c, axis=axis)
        cs = np.concatenate([np.zeros_like(np.take(cs, [0], axis=axis)), cs], axis=axis)
        s = np.arange(0, c.shape[axis] - w + 1, _C)          # window starts
        c = (np.take(cs, s + w, axis=axis) - np.take(cs, s, axis=axis) == w).astype(np.int32)
    return c.astype(bool)


class _Sheet:
    """Occupancy of one sheet: cell (a, b) of ``occ`` is lattice cell (a - pad[0],
    b - pad[1]), centred at ((a - pad[0] + .5) grid, (b - pad[1] + .5) grid)."""

    def __init__(self, shape: tuple[int, int], fshape: tuple[int, int], cshape: tuple[int, int],
                 cfshape: tuple[int, int]):
        self.occ = np.zeros(shape, dtype=bool)
        self.fshape, self.cshape, self.cfshape = fshape, cshape, cfshape
        self.free = int(self.occ.size)
        self._fft = None
        self._cfft = None

    def fft(self) -> np.ndarray:
        if self._fft is None:
            self._fft = sfft.rfft2(self.occ.astype(np.float32), s=self.fshape)
        return self._fft

    def cfft(self) -> np.ndarray:
        """Transform of the coarse occupancy: block (A, B) of _C x _C cells is 1
        when any of its cells is occupied."""
        if self._cfft is None:
            (cx, cy), (nx, ny) = self.cshape, self.occ.shape
            occ = np.zeros((cx * _C, cy * _C), dtype=bool)
            occ[:nx, :ny] = self.occ
            blocks = occ.reshape(cx, _C, cy, _C).any(axis=(1, 3))
            self._cfft = sfft.rfft2(blocks.astype(np.float32), s=self.cfshape)
        return self._cfft

    def maybe(self, m: _Mask, a0: int, a1: int, b0: int, b1: int) -> bool:
        """False when mask m has no free offset in [a0, a1] x [b0, b1], by a coarse
        necessary condition: at offset a = _C A + p (0 <= p < _C) the cells
        _C k - p .. _C k - p + _C - 1 of the mask lie on block A + k of the sheet, so
        if the mask's cells _C k - _C + 1 .. _C k + _C - 1 are all marked (its
        "core" block k, the same for every p) that block must be wholly free."""
        if m.core_fft is None:
            core = _core(m.cells)
            m.core_empty = not core.any()
            if not m.core_empty:
                m.core_fft = np.conj(sfft.rfft2(core.astype(np.float32), s=self.cfshape))
        if m.core_empty:
            return True
        corr = sfft.irfft2(self.cfft() * m.core_fft, s=self.cfshape)
        return bool(np.any(corr[a0 // _C:a1 // _C + 1, b0 // _C:b1 // _C + 1] < 0.5))

    def best(self, m: _Mask, pad: tuple[int, int]) -> tuple[int, int] | None:
        """Least (x, then y) free lattice offset of mask m, confirmed cell by cell."""
        if m.n > self.free:
            return None
        a0, b0 = m.lo[0] + pad[0], m.lo[1] + pad[1]
        a1, b1 = m.hi[0] + pad[0], m.hi[1] + pad[1]
        if self.free < self.occ.size and not self.maybe(m, a0, a1, b0, b1):
            return None
        fx, fy = self.fshape
        if m.fft is None:
            # 2-D transform of the zero-padded mask, the row pass on its own rows only
            m.fft = np.conj(sfft.fft(sfft.rfft(m.cells.astype(np.float32), n=fy, axis=1),
                                     n=fx, axis=0))
        # corr[a, b] = cells of the mask at offset (a, b) that are occupied; the
        # transforms are circular, but no offset read here wraps around
        corr = sfft.irfft(sfft.ifft(self.fft() * m.fft, axis=0)[a0:a1 + 1], n=fy, axis=1)
        free = corr[:, b0:b1 + 1] < 0.5
        mx, my = m.cells.shape
        for k in np.flatnonzero(free.ravel()):     # C order: least x, then least y
            a, b = divmod(int(k), free.shape[1])
            a += a0
            b += b0
            if not np.any(self.occ[a:a + mx, b:b + my] & m.cells):
                return a, b
        return None

    def add(self, m: _Mask, a: int, b: int) -> None:
        mx, my = m.cells.shape
        self.occ[a:a + mx, b:b + my] |= m.cells
        self.free -= m.n
        self._fft = self._cfft = None


# ----------------------------------------------------------------------------- nesting


def nest(parts: Sequence[Polygon], sheet_size: tuple[float, float], spacing: float,
         edge_margin: float = 0.0, grid: float = 0.005,
         angles: Sequence[float] = (0, 90, 180, 270),
         names: Sequence[str] | None = None) -> Nesting:
    """Lay ``parts`` out on as few sheets of ``sheet_size`` (W, H) as the greedy
    allows, each part at least ``spacing`` from every other part on its sheet and
    ``edge_margin`` from the sheet's edges (m).

    ``grid`` is the raster cell (m): the gaps between neighbouring parts come out
    between ``spacing`` and about ``spacing + 2.5 grid``, and the time grows as
    1 / grid^2. ``angles`` (degrees,
    counter-clockwise) are the allowed turns (see the module notes on the minimum
    rotated rectangle); ``names`` label the parts in error messages.

    Raises InputError for bad arguments or a part that fits no empty sheet at any
    allowed angle (checked before any nesting); a part exactly as large as the
    usable sheet (within 2 nm) counts as not fitting."""
    parts, (W, H), spacing, margin, g, angles, names = _check_args(
        parts, sheet_size, spacing, edge_margin, grid, angles, names)

    # every part must fit an empty sheet at some allowed angle
    cand = [_candidate_angles(p, angles) for p in parts]
    usable_w, usable_h = W - 2 * margin - 2 * _EPS, H - 2 * margin - 2 * _EPS
    for i, p in enumerate(parts):
        body = np.asarray(p.exterior.coords)
        sizes = [np.ptp(_rotate(body, a), axis=0) for a in cand[i]]
        if not any(w <= usable_w and h <= usable_h for w, h in sizes):
            # name the part by its size at the angle closest to fitting
            w, h = min(sizes, key=lambda wh: max(wh[0] / W, wh[1] / H))
            name = names[i] if names is not None else f"part {i}"
            raise InputError(f"{name} ({w * 1000:.0f} x {h * 1000:.0f} mm) does not fit on a "
                             f"{W * 1000:.0f} x {H * 1000:.0f} mm sheet with {margin * 1000:g} mm "
                             "margins at any allowed angle")

    masks = [_masks(p, cand[i], (W, H), spacing, margin, g, names[i] if names is not None else f"part {i}")
             for i, p in enumerate(parts)]
    flat = [m for ms in masks for m in ms]
    pad = (max(0, -min(m.lo[0] for m in flat)), max(0, -min(m.lo[1] for m in flat)))
    shape = (max(math.ceil(W / g) + pad[0], max(m.hi[0] + pad[0] + m.cells.shape[0] for m in flat)),
             max(math.ceil(H / g) + pad[1], max(m.hi[1] + pad[1] + m.cells.shape[1] for m in flat)))
    fshape = (sfft.next_fast_len(shape[0], real=True), sfft.next_fast_len(shape[1], real=True))
    cshape = (-(-shape[0] // _C), -(-shape[1] // _C))
    cfshape = (sfft.next_fast_len(cshape[0], real=True), sfft.next_fast_len(cshape[1], real=True))
    del flat

    order = sorted(range(len(parts)), key=lambda i: -Polygon(parts[i].exterior).area)
    sheets: list[_Sheet] = []
    placed: dict[int, Placement] = {}
    for i in order:
        spot = None
        for s, sheet in enumerate([*sheets, None]):
            if sheet is None:
                sheet = _Sheet(shape, fshape, cshape, cfshape)
                sheets.append(sheet)
            best = None
            for m in masks[i]:
                ab = sheet.best(m, pad)
                if ab is not None:
                    key = _key(m, ab)
                    if best is None or key < best[0]:
                        best = (key, m, ab)
            if best is not None:
                spot = (s, *best[1:])
                break
        if spot is None:
            raise AssertionError(f"part {i} fits an empty sheet but found no place on one")
        s, m, (a, b) = spot
        sheets[s].add(m, a, b)
        masks[i] = []                   # done with this part: free its transforms
        # mask cell (0, 0) sits on grid cell (a, b): centre ((a - pad + .5) g, ...)
        dx = (a - pad[0]) * g - m.origin[0]
        dy = (b - pad[1]) * g - m.origin[1]
        placed[i] = Placement(i, s, float(m.angle), float(dx), float(dy))

    area = W * H
    used = [0.0] * len(sheets)
    for i, p in placed.items():
        used[p.sheet] += parts[i].area
    result = Nesting(tuple(placed[i] for i in range(len(parts))), len(sheets), (W, H), spacing,
                     tuple(u / area for u in used))
    problems = check_nesting(parts, result, edge_margin=margin)
    if problems:
        raise AssertionError("nesting failed its own check: " + "; ".join(problems[:5]))
    return result


def _key(m: _Mask, ab: tuple[int, int]) -> tuple[int, int]:
    """Rank of a position across angles: the outline's left edge, then its bottom
    (in cells from the least allowed offset, where the edge is at the margin)."""
    return (ab[0] - m.lo[0], ab[1] - m.lo[1])


# ----------------------------------------------------------------------------- check


def check_nesting(parts: Sequence[Polygon], nesting: Nesting,
                  edge_margin: float = 0.0) -> list[str]:
    """Exact check with shapely: every part placed once, in order, inside its sheet
    at >= ``edge_margin`` from the edges, >= ``nesting.spacing`` from the other parts
    on its sheet (and never overlapping them). Returns the problems, [] when fine."""
    problems: list[str] = []
    parts = list(parts)
    W, H = nesting.sheet_size
    if len(nesting.placements) != len(parts):
        problems.append(f"{len(nesting.placements)} placements for {len(parts)} parts")
        return problems
    placed = []
    for i, (p, pl) in enumerate(zip(parts, nesting.placements)):
        if pl.part != i:
            problems.append(f"placement {i} is for part {pl.part}")
        if not 0 <= pl.sheet < nesting.n_sheets:
            problems.append(f"part {i} is on sheet {pl.sheet} of {nesting.n_sheets}")
        g = pl.apply(p)
        x0, y0, x1, y1 = g.bounds
        # inside [0, W] x [0, H], so its distance to each edge is that of its bounds
        gap = min(x0, y0, W - x1, H - y1)
        if gap < edge_margin:
            problems.append(f"part {i} is {gap * 1000:.4g} mm from the edge of sheet {pl.sheet} "
                            f"(margin {edge_margin * 1000:g} mm)")
        placed.append(g)
    sheet = np.array([pl.sheet for pl in nesting.placements])
    geoms = np.array(placed, dtype=object)
    tree = shapely.STRtree(geoms)
    pairs = tree.query(geoms, predicate="dwithin", distance=nesting.spacing)
    for a, b in pairs.T:
        if a >= b or sheet[a] != sheet[b]:
            continue
        d = shapely.distance(geoms[a], geoms[b])
        if d < nesting.spacing or shapely.relate_pattern(geoms[a], geoms[b], "T********"):
            problems.append(f"parts {a} and {b} on sheet {sheet[a]} are {d * 1000:.4g} mm apart "
                            f"(spacing {nesting.spacing * 1000:g} mm)")
    area = W * H
    for s in range(nesting.n_sheets):
        u = sum(parts[i].area for i in np.flatnonzero(sheet == s)) / area
        if s >= len(nesting.utilisation) or not math.isclose(u, nesting.utilisation[s],
                                                             rel_tol=1e-9):
            problems.append(f"utilisation of sheet {s} is {u:.6f}, not as reported")
    return problems
