"""Previews of nested sheets: parts, rod holes and engraving, in mm, as PNG and SVG."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

from ..io.files import atomic_write
from .plots import _pyplot


def plot_sheet(res, sheet: int, drawings, stem: Path) -> tuple[Path, Path]:
    """Draw sheet ``sheet`` (0-based) of a SliceResult; write STEM.png and STEM.svg."""
    plt = _pyplot()
    W, H = (s * 1000 for s in res.spec.sheet)
    fig, ax = plt.subplots(figsize=(12, 12 * H / W + 0.8))
    try:
        from matplotlib.collections import (
            EllipseCollection,
            LineCollection,
            PathCollection,
        )
        from matplotlib.path import Path as MplPath

        ax.add_patch(plt.Rectangle((0, 0), W, H, fill=True, fc="#f3e6c8", ec="k", lw=1.0))
        paths, centres, strokes = [], [], []
        hole = 0.0
        for d in drawings:
            for poly in shapely.get_parts(d.outline):
                if isinstance(poly, Polygon) and not poly.is_empty:
                    paths.append(_compound_path(poly, MplPath))
            centres.extend(np.asarray(d.holes).reshape(-1, 2) * 1000)
            hole = d.hole * 1000 or hole
            strokes.extend(np.asarray(s) * 1000 for s in d.engrave)
        ax.add_collection(PathCollection(paths, facecolors="#c98f4a", edgecolors="#8a1c1c", linewidths=0.6))
        if centres:
            ax.add_collection(EllipseCollection(hole, hole, 0.0, units="xy", offsets=np.array(centres),
                                                offset_transform=ax.transData, facecolors="white",
                                                edgecolors="#1c7a1c", linewidths=0.5))
        if strokes:
            ax.add_collection(LineCollection(strokes, colors="#4a3200", linewidths=0.5))
        n = len(drawings)
        ax.set_title(f"sheet {sheet + 1} of {res.nesting.n_sheets}: {n} parts, material use "
                     f"{res.nesting.utilisation[sheet] * 100:.1f} %  ({W:.0f} x {H:.0f} mm)")
        ax.set_xlim(-20, W + 20)
        ax.set_ylim(-20, H + 20)
        ax.set_aspect("equal")
        ax.set_xlabel("x, mm")
        ax.set_ylabel("y, mm")
        fig.tight_layout()
        out = []
        for fmt, dpi in (("png", 110), ("svg", None)):
            path = Path(f"{stem}.{fmt}")

            def write(tmp, fmt=fmt, dpi=dpi):
                fig.savefig(tmp, format=fmt, dpi=dpi)

            out.append(atomic_write(path, write))
        return tuple(out)
    finally:
        plt.close(fig)


def _compound_path(poly: Polygon, MplPath):
    """A matplotlib Path of a polygon with its holes (even-odd filled)."""
    rings = [np.asarray(poly.exterior.coords) * 1000] + [np.asarray(r.coords) * 1000 for r in poly.interiors]
    verts = np.vstack(rings)
    codes = np.concatenate([[MplPath.MOVETO] + [MplPath.LINETO] * (len(r) - 2) + [MplPath.CLOSEPOLY] for r in rings])
    return MplPath(verts, codes)
