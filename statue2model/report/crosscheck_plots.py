"""Figures of the 3D cross-check: one overlay plot per time history, 2D (line) and 3D (dashed).

:func:`plot_histories` draws a cross-check's overlay PNGs (file names from
statue2model.crosscheck.output.plot_files), atomically; the data file, crosscheck.json, is
statue2model.crosscheck.output.write_report's (the report draws, it writes no data).

Example
-------
>>> from statue2model.crosscheck.case import Case, Comparison
>>> import tempfile, numpy as np, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> c = Comparison(cases=(Case.relative("q", "s", 1.0, 1.001, 0.01),),
...                histories={"q": {"t2": np.arange(3.0), "y2": np.zeros(3), "t3": np.arange(3.0),
...                                 "y3": np.zeros(3), "label": "theta (rad)"}})
>>> paths = plot_histories(c.histories, d)
>>> sorted(p.name for p in paths.values())
['q.png']
"""
from __future__ import annotations

from pathlib import Path

from ..crosscheck.output import plot_files
from ..io.files import atomic_write, prepare_dir
from .plots import _pyplot


def plot_overlay(title: str, h: dict, path: Path) -> Path:
    """One time history ``h`` ({'t2', 'y2', 't3', 'y3', 'label'}: times in s and the plotted
    quantity) of the 2D model and the 3D scene, overlaid, as a PNG at ``path``."""
    plt = _pyplot()

    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.plot(h["t2"], h["y2"], lw=1.4, label="2D model")
    ax.plot(h["t3"], h["y3"], lw=1.1, ls="--", label="3D PyBullet")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(h.get("label", ""))
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(loc="best")
    fig.tight_layout()

    def save(p):
        fig.savefig(p, dpi=110, format="png")

    try:
        return atomic_write(path, save)
    finally:
        plt.close(fig)


def plot_histories(histories: dict, out_dir) -> dict[str, Path]:
    """One overlay PNG per time history into ``out_dir``: {history name: path}."""
    out = prepare_dir(out_dir)
    return {name: plot_overlay(name, histories[name], out / file) for name, file in plot_files(histories).items()}


