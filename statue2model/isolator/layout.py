"""Where the balls (and so the grooves) sit on the plates: rings and grids of 3 to 16 balls.

A layout is a set of unit points, neighbouring centres one unit apart, the plate centre at the
origin; a device scales it by its groove spacing s (m, the least distance between two groove
centres: at least 2 a + GAP, a the grooves' opening radius). What the design reads of it:

    centres(s)    the groove centres (m)
    L_cr(s)       distance from the plate centre to the nearest edge of the convex hull of the
                  centres (m): the top plate tips about that edge (eqs. 47-49 with L_cr)
    extent(s)     the largest |x| or |y| of a centre (m): the square plate's side is
                  2 (extent + a + EDGE)
    spread(s)     min over horizontal directions of sum (x_i . e)^2 / max_i |x_i . e| (m): the
                  lever of the balls against an overturning moment (the most loaded ball carries
                  M / spread more than W / n)

Rings put n balls on a circle (3 to 8; ring4 is the 2 x 2 grid), grids fill a square (3 x 3,
3 x 4, 4 x 4). The thesis built ring3 and ring4 (ch. 5.1, 5.3).

>>> lay = LAYOUTS["ring4"]
>>> lay.n, round(lay.L_cr(0.2), 4), round(lay.extent(0.2), 4)       # a square of side 0.2 m
(4, 0.1, 0.1)
>>> round(LAYOUTS["ring3"].L_cr(0.2), 4)                            # the triangle's inradius
0.0577
>>> LAYOUTS["grid3x4"].n, round(LAYOUTS["grid3x4"].L_cr(0.1), 3)
(12, 0.1)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Layout:
    """A ball layout: ``key``, ``n`` balls, ``unit`` points (neighbours one unit apart)."""

    key: str
    name: str
    unit: tuple
    n: int = field(init=False)
    unit_extent: float = field(init=False)
    unit_L_cr: float = field(init=False)
    unit_spread: float = field(init=False)

    def __post_init__(self):
        p = np.asarray(self.unit, dtype=float)
        ang = np.linspace(0.0, math.pi, 73)
        x = p @ np.column_stack([np.cos(ang), np.sin(ang)]).T
        object.__setattr__(self, "n", len(self.unit))
        object.__setattr__(self, "unit_extent", float(np.abs(p).max()))
        object.__setattr__(self, "unit_L_cr", _hull_inradius(p))
        object.__setattr__(self, "unit_spread", float(((x ** 2).sum(axis=0) / np.abs(x).max(axis=0)).min()))

    def centres(self, s: float) -> tuple:
        return tuple((float(x * s), float(y * s)) for x, y in self.unit)

    def L_cr(self, s: float) -> float:
        return s * self.unit_L_cr

    def extent(self, s: float) -> float:
        return s * self.unit_extent

    def spread(self, s: float) -> float:
        return s * self.unit_spread


def _hull_inradius(p: np.ndarray) -> float:
    from scipy.spatial import ConvexHull

    hull = ConvexHull(p)
    # each facet: n . x + d <= 0 inside; distance of the origin = -d
    return float((-hull.equations[:, 2]).min())


def _ring(n: int) -> tuple:
    rho = 1.0 / (2.0 * math.sin(math.pi / n))
    start = math.pi / 2 if n % 2 else math.pi / 2 + math.pi / n     # a flat side at the bottom
    return tuple((rho * math.cos(start + 2 * math.pi * k / n), rho * math.sin(start + 2 * math.pi * k / n))
                 for k in range(n))


def _grid(nx: int, ny: int) -> tuple:
    xs = np.arange(nx) - (nx - 1) / 2
    ys = np.arange(ny) - (ny - 1) / 2
    return tuple((float(x), float(y)) for y in ys for x in xs)


LAYOUTS = {
    "ring3": Layout("ring3", "3 balls on a triangle", _ring(3)),
    "ring4": Layout("ring4", "4 balls on a square", _grid(2, 2)),
    "ring5": Layout("ring5", "5 balls on a ring", _ring(5)),
    "ring6": Layout("ring6", "6 balls on a ring", _ring(6)),
    "ring8": Layout("ring8", "8 balls on a ring", _ring(8)),
    "grid3x3": Layout("grid3x3", "9 balls on a 3 x 3 grid", _grid(3, 3)),
    "grid3x4": Layout("grid3x4", "12 balls on a 3 x 4 grid", _grid(4, 3)),
    "grid4x4": Layout("grid4x4", "16 balls on a 4 x 4 grid", _grid(4, 4)),
}
"""Ball layouts (registry)."""


def layouts_with(n: int | None) -> tuple:
    """The layouts of ``n`` balls (None: all)."""
    out = tuple(lay for lay in LAYOUTS.values() if n is None or lay.n == n)
    if not out:
        counts = sorted({lay.n for lay in LAYOUTS.values()})
        from ..errors import InputError

        raise InputError(f"no ball layout has {n} balls (layouts: {', '.join(map(str, counts))} balls)")
    return out
