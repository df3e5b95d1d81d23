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
from ..isolator.plates import PlateGeometry, section_shapes
from .plots import _pyplot

SECTION_FILES = ("plates_section.png", "plates_section.svg")
"""The section's files, written beside the plates' (after them)."""


def plot_plates_figures(geom: PlateGeometry, out_dir, design: dict | None = None) -> dict[str, Path]:
    """The plates' figures in ``out_dir`` (the plates' CNC files are
    :func:`statue2model.isolator.plates.write_plates`'s, written first by the caller): their section
    (keys ``section_png``, ``section_svg``: plates_section.png / .svg) and, with the ``design``
    (design.json's dict), the carpenter's dimensioned drawing (``drawing_svg``, ``drawing_png``:
    drawing.svg / .png, :func:`plot_plates_drawing`)."""
    paths = {}
    out = Path(out_dir)
    paths["section_png"], paths["section_svg"] = plot_plates_section(geom, *(out / n for n in SECTION_FILES))
    if design is not None:
        paths["drawing_svg"], paths["drawing_png"] = plot_plates_drawing(geom, design, out / "drawing.svg",
                                                                         out / "drawing.png")
    return paths


def plot_plates_drawing(geom: PlateGeometry, design: dict, svg: Path, png: Path) -> tuple[Path, Path]:
    """The carpenter's drawing (mm): the plate in plan with its outline and overall dimensions, every groove
    centre numbered and dimensioned from the plate centre, the opening circles, the fuse seats and drop
    holes; beside it a table of the groove centres, and the notes: groove radius R and depth (the carved
    ones with a liner), board stack, balls, liner, cost."""
    plt = _pyplot()
    fig, (ax, tx) = plt.subplots(1, 2, figsize=(16, 9), gridspec_kw={"width_ratios": [1.25, 1]})
    h = 0.5 * geom.side * MM
    ax.plot([-h, h, h, -h, -h], [-h, -h, h, h, -h], "k-", lw=1.5)
    circles = geom.circles("bottom")
    for k, (kind, x, y, r) in enumerate(circles):
        style = {"groove": ("saddlebrown", "-"), "seat": ("steelblue", "-"), "hole": ("steelblue", "--")}[kind]
        ax.add_patch(plt.Circle((x * MM, y * MM), r * MM, fill=False, color=style[0], ls=style[1], lw=1))
    for k, (x, y) in enumerate(geom.groove_centres):
        ax.plot(x * MM, y * MM, "k+", ms=10)
        ax.annotate(f"G{k + 1}", (x * MM, y * MM), xytext=(6, 6), textcoords="offset points", fontsize=9)
    # overall dimensions
    off = 0.06 * h
    ax.annotate("", (-h, -h - off), (h, -h - off), arrowprops={"arrowstyle": "<->", "lw": 0.8})
    ax.text(0, -h - 2 * off, f"{geom.side * MM:.0f}", ha="center", va="top", fontsize=10)
    ax.annotate("", (-h - off, -h), (-h - off, h), arrowprops={"arrowstyle": "<->", "lw": 0.8})
    ax.text(-h - 2 * off, 0, f"{geom.side * MM:.0f}", ha="right", va="center", rotation=90, fontsize=10)
    # one opening radius dimensioned
    x0, y0 = geom.groove_centres[0]
    a = geom.opening_radius * MM
    ax.annotate("", (x0 * MM, y0 * MM), (x0 * MM + a, y0 * MM), arrowprops={"arrowstyle": "<-", "lw": 0.8})
    ax.text(x0 * MM + a / 2, y0 * MM + 4, f"a {a:.1f}", ha="center", va="bottom", fontsize=8)
    ax.plot(0, 0, "kx")
    ax.set_aspect("equal")
    ax.set_xlim(-h - 4 * off, h + off)
    ax.set_ylim(-h - 4 * off, h + off)
    ax.set_title("bottom plate, carved face up (mm; the top plate is its mirror, grooves facing down)", fontsize=10)
    ax.set_xlabel("x, mm (origin: plate centre)")
    ax.set_ylabel("y, mm")
    tx.axis("off")
    layers = design.get("layers") or [[geom.thickness, 1]]
    lines = [f"Rolling-ball isolator: {design.get('n_balls', len(geom.groove_centres))} balls, "
             f"{design.get('layout', '')}",
             f"plate {geom.side * MM:.0f} x {geom.side * MM:.0f} x {geom.thickness * MM:.0f} mm: "
             + " + ".join(f"{int(k)} x {t * MM:g} mm" for t, k in layers) + f" {design.get('surface_name') or ''}",
             f"grooves: sphere R {geom.R * MM:.1f} mm, depth {geom.depth * MM:.2f} mm, opening radius "
             f"{cap_open(geom) * MM:.1f} mm (rolling surface)"]
    if geom.liner > 0:
        lines.append(f"  liner {geom.liner * MM:g} mm: carve R {geom.cut_R * MM:.1f} mm, depth "
                     f"{geom.cut_depth * MM:.2f} mm, opening radius {geom.opening_radius * MM:.1f} mm")
    lines.append(f"balls: {design.get('ball_material', '')} {2 * geom.ball_radius * MM:g} mm diameter; gap between "
                 f"the plates {geom.gap * MM:.1f} mm")
    if geom.fuse_centres:
        lines.append(f"fuse: {len(geom.fuse_centres)} balls of {2 * geom.fuse_ball_radius * MM:.1f} mm in seats "
                     f"{geom.fuse_seat_depth * MM:.2f} mm deep; drop holes {geom.fuse_hole_diameter * MM:.1f} mm x "
                     f"{geom.fuse_hole_depth * MM:.1f} mm (bottom plate)")
    if design.get("cost"):
        lines.append(f"cost {design['cost']:.0f} EUR (bom.csv)")
    lines += ["", "groove centres (mm from the plate centre):"]
    lines += [f"  G{k + 1:<3d} x {x * MM:9.1f}   y {y * MM:9.1f}" for k, (x, y) in enumerate(geom.groove_centres)]
    if geom.fuse_centres:
        lines += ["fuse seats:"] + [f"  F{k + 1:<3d} x {x * MM:9.1f}   y {y * MM:9.1f}"
                                    for k, (x, y) in enumerate(geom.fuse_centres)]
    tx.text(0.0, 1.0, "\n".join(lines), va="top", ha="left", family="monospace", fontsize=8.5,
            transform=tx.transAxes)
    fig.tight_layout()
    from ..io.files import atomic_write

    for path in (svg, png):
        atomic_write(path, lambda p, f=fig: f.savefig(p, format=Path(path).suffix[1:], dpi=120))
    plt.close(fig)
    return svg, png


def cap_open(geom: PlateGeometry) -> float:
    """The rolling surface's opening radius, m."""
    from ..isolator.plates import cap_opening_radius

    return cap_opening_radius(geom.R, geom.depth)


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
