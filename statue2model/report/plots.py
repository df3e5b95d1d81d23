"""Figures (matplotlib, Agg backend, imported only when a figure is drawn).

Example
-------
>>> from statue2model.geometry.body import load_body
>>> from statue2model.io.paths import default_scan
>>> from statue2model.report.plots import plot_footprint_and_rose
>>> import tempfile, pathlib
>>> body = load_body(default_scan())
>>> out = pathlib.Path(tempfile.mkdtemp()) / "props.png"
>>> plot_footprint_and_rose(body, body.rocking(), body.rose(), out).exists()
True
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io.files import atomic_write
from ..geometry.rocking_params import RockingParams, Rose, unit_vectors


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_footprint_and_rose(body, params: RockingParams, rose: Rose, path: str | Path) -> Path:
    """Footprint (contact faces, the points taken as contact, the contact hull at the
    tolerance used and at half and double it, centre of mass, pivots) beside the
    vulnerability rose."""
    plt = _pyplot()
    fig = plt.figure(figsize=(11, 5))
    ax = fig.add_subplot(1, 2, 1)
    mm = 1000.0
    for ext, holes in body.footprint.polygons:
        ax.fill(ext[:, 0] * mm, ext[:, 1] * mm, color="0.8", lw=0.5, ec="0.4")
        for h in holes:
            ax.fill(h[:, 0] * mm, h[:, 1] * mm, color="white", lw=0.5, ec="0.4")
    hull = np.vstack([body.footprint.hull, body.footprint.hull[:1]])
    tol = body.footprint.tol
    ax.plot(hull[:, 0] * mm, hull[:, 1] * mm, "k--", lw=1, label=f"contact hull, tolerance {tol * mm:.2f} mm")
    base = getattr(body, "base", None)
    if base is not None:
        touch = body.vertices[body.vertices[:, 2] <= tol, :2]
        ax.plot(touch[:, 0] * mm, touch[:, 1] * mm, ".", ms=1.5, color="0.3", label="points taken as contact")
        for case, style in ((base.cases[0], ":"), (base.cases[2], "-.")):
            if len(case.hull) >= 3:
                ring = np.vstack([case.hull, case.hull[:1]]) * mm
                ax.plot(ring[:, 0], ring[:, 1], style, lw=1, color="tab:orange" if style == ":" else "tab:green",
                        label=f"hull at {case.tol * mm:.2f} mm ({case.a_min / params.g:.3f} g)")
    c = body.mass.com[:2]
    ax.plot(c[0] * mm, c[1] * mm, "ro", label="centre of mass (projection)")
    x, _ = unit_vectors(params.direction_deg)
    pr = c + params.b_R * x[:2]
    pl = c - params.b_L * x[:2]
    ax.annotate("", xy=pr * mm, xytext=pl * mm, arrowprops=dict(arrowstyle="->", color="tab:blue"))
    ax.plot([pl[0] * mm, pr[0] * mm], [pl[1] * mm, pr[1] * mm], "s", color="tab:blue", label="pivots L, R")
    ax.text(*(pl * mm), "  L", color="tab:blue", va="center")
    ax.text(*(pr * mm), "  R", color="tab:blue", va="center")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(
        f"Footprint, direction {params.direction_deg:.1f} deg\n"
        f"b_L = {params.b_L * mm:.1f} mm, b_R = {params.b_R * mm:.1f} mm, h = {params.h * mm:.1f} mm"
        + ("\nUNCERTAIN BASE CONTACT: a_min moves {:.0%} at half / double tolerance".format(base.spread)
           if base is not None and base.uncertain else "")
    )
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3, fontsize=8)

    ax2 = fig.add_subplot(1, 2, 2, projection="polar")
    psi = np.radians(np.r_[rose.direction_deg, rose.direction_deg[:1]])
    a = np.r_[rose.a_tip, rose.a_tip[:1]] / params.g
    ax2.plot(psi, a, "k-")
    ax2.fill(psi, a, color="tab:red", alpha=0.15)
    ax2.plot([np.radians(rose.weakest_deg)], [rose.a_min / params.g], "ro")
    ax2.set_title(
        f"Uplift acceleration to tip toward each direction [g]\n"
        f"weakest {rose.weakest_deg:.1f} deg: {rose.a_min / params.g:.3f} g"
    )
    fig.tight_layout()

    def write(tmp: Path) -> None:
        fig.savefig(tmp, dpi=110, format=Path(path).suffix.lstrip(".") or "png")

    try:
        return atomic_write(path, write)
    finally:
        plt.close(fig)
