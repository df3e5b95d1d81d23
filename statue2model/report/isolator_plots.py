"""Figure of the isolator's plates: the dimensioned section through a groove (matplotlib Agg,
imported only when drawing), and the plates' files with that section, as ``isolator plates`` and
the isolator stage write them.

Example
-------
>>> import tempfile, pathlib
>>> from statue2model.isolator.plates import PlateGeometry
>>> geom = PlateGeometry(side=0.40, thickness=0.03, R=0.30, depth=0.012,
...                      groove_centres=((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)),
...                      ball_radius=0.0183)
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> [p.name for p in plot_plates_section(geom, d / "s.png", d / "s.svg")]
['s.png', 's.svg']
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..fabrication.dxf import MM
from ..io.files import atomic_write
from ..isolator.plates import PlateGeometry, section_shapes, write_plates
from .plots import _pyplot

SECTION_FILES = ("plates_section.png", "plates_section.svg")
"""The section's files, written beside the plates' (after them)."""


def write_plates_with_section(geom: PlateGeometry, out_dir, segments: int = 256) -> dict[str, Path]:
    """The plates' files (:func:`statue2model.isolator.plates.write_plates`, its keys) and then
    their section (keys ``section_png``, ``section_svg``: plates_section.png / .svg) in ``out_dir``."""
    paths = write_plates(geom, out_dir, segments=segments)
    out = Path(out_dir)
    paths["section_png"], paths["section_svg"] = plot_plates_section(geom, *(out / n for n in SECTION_FILES))
    return paths


def plot_plates_section(geom: PlateGeometry, png: Path, svg: Path) -> tuple[Path, Path]:
    """Section of both plates with the balls in place, through the first groove's
    centre along x; the lower panel details that groove with its dimensions (``png``, ``svg``)."""
    import shapely

    plt = _pyplot()
    x0, y0 = geom.groove_centres[0]
    bottom, top, balls, fuse = section_shapes(geom, y0)
    t, d, a, R, r, gap = geom.thickness, geom.depth, geom.opening_radius, geom.R, geom.ball_radius, geom.gap
    fig, axes = plt.subplots(2, 1, figsize=(12, 9), gridspec_kw={"height_ratios": [1, 1.6]})

    def draw(ax):
        for geom_, fc in ((bottom, "burlywood"), (top, "tan")):
            for poly in shapely.get_parts(geom_):
                xy = np.asarray(poly.exterior.coords) * MM
                ax.fill(xy[:, 0], xy[:, 1], fc=fc, ec="k", lw=0.8)
        for disc, fc in [(b, "0.6") for b in balls] + [(f, "steelblue") for f in fuse]:
            xy = np.asarray(disc.exterior.coords) * MM
            ax.fill(xy[:, 0], xy[:, 1], fc=fc, ec="k", lw=0.6, alpha=0.7)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("z (mm)")

    ax = axes[0]
    draw(ax)
    ax.set_title(f"Section y = {y0 * MM:.1f} mm through groove 1: bottom plate, balls (r = {r * MM:.1f} mm), "
                 f"top plate; side {geom.side * MM:.0f} mm, gap {gap * MM:.1f} mm", fontsize=10)

    ax = axes[1]
    draw(ax)
    pad = 0.02
    sd = 1.0 if x0 <= 0 else -1.0                   # towards the plate centre: the side with wood
    lo, hi = sorted(((x0 - sd * (a + pad)) * MM, (x0 + sd * (a + 3 * pad)) * MM))
    ax.set_xlim(lo, hi)
    ax.set_ylim(-0.008 * MM, (2 * t + gap + 0.008) * MM)
    arrow = {"arrowstyle": "<->", "color": "darkred", "lw": 1.0, "shrinkA": 0, "shrinkB": 0}
    text = {"color": "darkred", "fontsize": 9, "bbox": {"fc": "white", "ec": "none", "alpha": 0.8, "pad": 1.0}}
    ha = "left" if sd > 0 else "right"
    # depth, beside the groove, with an extension line from its deepest point
    xd = (x0 + sd * (a + 0.5 * pad)) * MM
    ax.plot([x0 * MM, xd + 2 * sd], [(t - d) * MM] * 2, color="darkred", lw=0.6, ls="--")
    ax.annotate("", xy=(xd, (t - d) * MM), xytext=(xd, t * MM), arrowprops=arrow)
    ax.text(xd + sd, (t - 0.5 * d) * MM, f"depth = {d * MM:.1f} mm", ha=ha, va="center", **text)
    # thickness, just beyond it
    xt = xd + 22 * sd
    ax.annotate("", xy=(xt, 0), xytext=(xt, t * MM), arrowprops=arrow)
    ax.text(xt + sd, 0.35 * t * MM, f"t = {t * MM:.1f} mm", ha=ha, va="center", rotation=90, **text)
    # opening radius, in the gap above the bottom plate
    za = (t + 0.35 * gap) * MM
    ax.annotate("", xy=(x0 * MM, za), xytext=((x0 + sd * a) * MM, za), arrowprops=arrow)
    ax.plot([x0 * MM] * 2, [(t - d) * MM, za], color="darkred", lw=0.6, ls=":")
    ax.text((x0 + 0.5 * sd * a) * MM, za + 0.8, f"a = {a * MM:.1f} mm", ha="center", va="bottom", **text)
    # R: a leader along the radius to a point of the groove's surface, on the other side
    th = -sd * 0.55 * math.asin(a / R)
    px, pz = x0 + R * math.sin(th), t - d + R - R * math.cos(th)
    ux, uz = -math.sin(th), math.cos(th)           # towards the sphere centre (far above)
    L = 0.6 * (t + gap)
    ax.annotate("", xy=(px * MM, pz * MM), xytext=((px + L * ux) * MM, (pz + L * uz) * MM),
                arrowprops={"arrowstyle": "->", "color": "darkred", "lw": 1.0})
    ax.text((px + L * ux) * MM, (pz + L * uz) * MM + 0.8,
            f"R = {R * MM:.0f} mm\n(centre {(R - d) * MM:.0f} mm above the face)", ha="center", va="bottom", **text)
    ax.set_title(f"Groove 1 at ({x0 * MM:.1f}, {y0 * MM:.1f}) mm: t = {t * MM:.1f} mm, R = {R * MM:.0f} mm, "
                 f"depth = {d * MM:.1f} mm, a = {a * MM:.1f} mm, ball r = {r * MM:.1f} mm "
                 "(top plate: the mirror)", fontsize=10)
    fig.tight_layout()
    try:
        atomic_write(png, lambda p: fig.savefig(p, format="png", dpi=150))
        atomic_write(svg, lambda p: fig.savefig(p, format="svg"))
    finally:
        plt.close(fig)
    return png, svg
