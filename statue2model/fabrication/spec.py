"""What the workshop builds: the frozen parameters of a stacked-board prototype.

All lengths in metres, densities in kg/m^3, feed in m/s (SI, like the rest of the
package; the command line takes '9mm', '2500x1250mm' and converts).

    scale      lambda: every length of the prototype = real length / lambda (1:2 -> 2)
    board      board (OSB panel) thickness; the thesis used 9 mm
    glue       glue film between boards; pitch = board + glue
    tool       cutter diameter (3 mm in the thesis)
    rod        alignment rod (vertical bar) diameter; holes are rod + clearance
    wall       least wood left between a rod hole and a part's edge (or another hole)
    sheet      (W, H) of the panels the parts are nested on
    margin     gap added to the tool diameter between nested parts
    edge       keep-out band along the sheet edges
    policy     section of each board: 'mid' (mid-plane), 'envelope' (union of the
               slab's sections: never smaller than the statue), 'core' (intersection)
    compensate write the cutter-centre path (outline offset by tool/2) instead of the
               true outline; off by default because CAM software compensates
    tolerance  chordal tolerance of the outlines (simplification), m

Example
-------
>>> spec = SliceSpec(scale=2.0)
>>> round(spec.pitch * 1000, 3), round(spec.hole * 1000, 3), round(spec.spacing * 1000, 3)
(9.5, 8.2, 5.0)
>>> SliceSpec(board=0.0002)
Traceback (most recent call last):
...
statue2model.errors.InputError: board thickness 0.2 mm is out of range (1 to 100 mm)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError

POLICIES = ("mid", "envelope", "core")

OSB_DENSITY = 620.0
"""OSB/3 panel, kg/m^3 (typical 600-650)."""
GLUE_DENSITY = 1100.0
"""Cured PVA wood glue, kg/m^3."""
STEEL_DENSITY = 7850.0
"""Steel alignment bars, kg/m^3 (0 if the bars are pulled out after gluing)."""


def _check_mm(name: str, value: float, lo_mm: float, hi_mm: float) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value)):
        raise InputError(f"{name} must be a finite length, got {value!r}")
    mm = value * 1000.0
    if not (lo_mm <= mm <= hi_mm):
        raise InputError(f"{name} {mm:g} mm is out of range ({lo_mm:g} to {hi_mm:g} mm)")


@dataclass(frozen=True)
class SliceSpec:
    scale: float = 2.0
    board: float = 0.009
    glue: float = 0.0005
    tool: float = 0.003
    rod: float = 0.008
    clearance: float = 0.0002
    wall: float = 0.005
    sheet: tuple[float, float] = (2.5, 1.25)
    margin: float = 0.002
    edge: float = 0.01
    policy: str = "mid"
    compensate: bool = False
    tolerance: float = 5e-5
    feed: float = 2.0 / 60.0
    pass_depth: float | None = None
    drill_time: float = 4.0
    osb_density: float = OSB_DENSITY
    glue_density: float = GLUE_DENSITY
    rod_density: float = STEEL_DENSITY

    def __post_init__(self):
        if not (isinstance(self.scale, (int, float)) and math.isfinite(self.scale) and 1.0 <= self.scale <= 100.0):
            raise InputError(f"scale 1:{self.scale:g} is out of range (1:1 to 1:100; the prototype is not enlarged)")
        _check_mm("board thickness", self.board, 1, 100)
        _check_mm("glue thickness", self.glue, 0, 5)
        _check_mm("tool diameter", self.tool, 0.1, 50)
        _check_mm("rod diameter", self.rod, 0.5, 100)
        _check_mm("hole clearance", self.clearance, 0, 5)
        _check_mm("minimum wall", self.wall, 0, 100)
        _check_mm("nesting margin", self.margin, 0, 100)
        _check_mm("sheet edge margin", self.edge, 0, 200)
        _check_mm("outline tolerance", self.tolerance, 0, 1)
        if len(self.sheet) != 2:
            raise InputError(f"sheet must be (width, height), got {self.sheet!r}")
        for side in self.sheet:
            _check_mm("sheet side", side, 50, 10000)
        if min(self.sheet) <= 2 * self.edge:
            raise InputError(f"sheet edge margin {self.edge * 1000:g} mm leaves no room on the sheet")
        if self.policy not in POLICIES:
            raise InputError(f"section policy {self.policy!r} is not one of {', '.join(POLICIES)}")
        if not (math.isfinite(self.feed) and self.feed > 0):
            raise InputError(f"feed must be a positive speed, got {self.feed!r}")
        if self.pass_depth is not None:
            _check_mm("depth per pass", self.pass_depth, 0.1, 100)
        if not (math.isfinite(self.drill_time) and self.drill_time >= 0):
            raise InputError(f"drill time must be >= 0 s, got {self.drill_time!r}")
        for name in ("osb_density", "glue_density", "rod_density"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0) or (name == "osb_density" and value == 0):
                raise InputError(f"{name.replace('_', ' ')} must be a positive number of kg/m^3, got {value!r}")

    @property
    def pitch(self) -> float:
        """Height of one layer: board + glue, m."""
        return self.board + self.glue

    @property
    def hole(self) -> float:
        """Diameter of the alignment holes: rod + clearance, m."""
        return self.rod + self.clearance

    @property
    def spacing(self) -> float:
        """Least distance between nested parts: tool diameter + margin, m."""
        return self.tool + self.margin

    @property
    def passes(self) -> int:
        """Depth passes per cut through one board (default depth per pass: one tool diameter)."""
        depth = self.pass_depth or self.tool
        return max(1, math.ceil(self.board / depth - 1e-9))

    def to_dict(self) -> dict:
        return {
            "scale": self.scale, "board": self.board, "glue": self.glue, "pitch": self.pitch,
            "tool": self.tool, "rod": self.rod, "hole": self.hole, "wall": self.wall,
            "sheet": list(self.sheet), "spacing": self.spacing, "edge": self.edge,
            "policy": self.policy, "compensate": self.compensate, "tolerance": self.tolerance,
            "feed": self.feed, "passes": self.passes, "drill_time": self.drill_time,
            "osb_density": self.osb_density, "glue_density": self.glue_density, "rod_density": self.rod_density,
        }
