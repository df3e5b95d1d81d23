"""Figures of a ``statue2model run``: the prototype's layers, and the statue on a fixed
base beside the statue on the isolator (matplotlib Agg, imported only when drawing).

Example
-------
>>> import tempfile, pathlib, numpy as np
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel
>>> from statue2model.rocking.sweeps import variability
>>> model = RockingModel.housner(RockingParams.rectangular_block(0.0384, 0.2, 1.286))
>>> sw = variability(model, motions.sine_pulse(0.3 * 9.81, 2.0), np.linspace(0.1, 0.6, 6) * 9.81)
>>> plot_variability_pair(sw, None, None, pathlib.Path(tempfile.mkdtemp()) / "v.png").exists()
True
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .dynamics_plots import _save
from .plots import _pyplot


def plot_layers(res, path) -> Path:
    """A SliceResult's boards: every part's outline in plan, coloured by height, with
    the rod holes; and the stack in elevation along the excitation direction (x)."""
    plt = _pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 6), gridspec_kw={"width_ratios": [1, 1]})
    n = max(res.n_layers, 1)
    cmap = plt.get_cmap("viridis")
    for part in res.parts:
        colour = cmap(part.layer / max(n - 1, 1))
        for ring in [part.outline.exterior, *part.outline.interiors]:
            x, y = np.asarray(ring.coords).T * 1000
            ax1.plot(x, y, lw=0.5, color=colour)
        if len(part.holes):
            h = np.asarray(part.holes) * 1000
            ax1.plot(h[:, 0], h[:, 1], ".", ms=2, color="k")
    ax1.set_aspect("equal")
    ax1.set_xlabel("x [mm]")
    ax1.set_ylabel("y [mm]")
    ax1.set_title(f"{len(res.parts)} parts in plan (colour: layer 1 to {res.n_layers})", fontsize=10)
    pitch = res.spec.pitch * 1000
    for part in res.parts:
        x0, _, x1, _ = part.outline.bounds
        z = res.bottoms[part.layer] * 1000
        ax2.add_patch(plt.Rectangle((x0 * 1000, z), (x1 - x0) * 1000, res.spec.board * 1000,
                                    fc=cmap(part.layer / max(n - 1, 1)), ec="none"))
    xs = [v * 1000 for p in res.parts for v in (p.outline.bounds[0], p.outline.bounds[2])]
    if xs:
        ax2.set_xlim(min(xs) - 20, max(xs) + 20)
    ax2.set_ylim(0, (res.bottoms[-1] * 1000 + pitch) if res.n_layers else 1)
    ax2.set_aspect("equal")
    ax2.set_xlabel("x [mm]")
    ax2.set_ylabel("z [mm]")
    ax2.set_title(f"elevation: {res.n_layers} layers, pitch {pitch:g} mm", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def plot_variability_pair(fixed, isolated, acc_isolated, path) -> Path:
    """|theta|max/delta against PGA on a fixed base and on the isolator (two SweepResults
    over the same PGAs; ``isolated`` may be None); the plate's peak absolute
    acceleration beside it when given."""
    plt = _pyplot()
    g = fixed.model.params.g
    ncol = 2 if acc_isolated is not None else 1
    fig, axes = plt.subplots(1, ncol, figsize=(6 * ncol, 4.5), squeeze=False)
    ax = axes[0, 0]
    for sw, label, colour in ((fixed, "fixed base", "C3"), (isolated, "on the isolator", "C0")):
        if sw is None:
            continue
        x = sw.values / g
        y = np.where(sw.overturned, 1.0, sw.theta_max_over_delta)
        ax.plot(x, y, "o-", ms=3, lw=0.9, color=colour, label=label)
        if sw.overturned.any():
            ax.plot(x[sw.overturned], np.ones(sw.overturned.sum()), "x", color=colour, ms=7)
    peak = max(float(np.nanmax(np.where(sw.overturned, 1.0, sw.theta_max_over_delta))) if sw is not None else 0.0
               for sw in (fixed, isolated))
    if peak >= 0.3:
        ax.axhline(1, color="0.5", lw=0.6, ls="--")
        ax.set_ylim(0, 1.1)
    else:
        ax.set_ylim(0, max(peak, 1e-6) * 1.25)
        ax.text(0.01, 0.97, "overturning at 1 (off the scale)", transform=ax.transAxes, fontsize=7, va="top",
                color="0.4")
    ax.set_xlabel("PGA [g]")
    ax.set_ylabel("|theta|max / delta [-]  (x: overturned)")
    ax.legend(loc="upper left", bbox_to_anchor=(0.0, -0.15), ncol=2, fontsize=8)
    ax.set_title(f"{fixed.motion.label}", fontsize=9)
    if acc_isolated is not None:
        ax = axes[0, 1]
        ax.plot(fixed.values / g, np.asarray(acc_isolated) / g, "o-", ms=3, color="C0", label="plate |a_abs| max")
        ax.plot(fixed.values / g, fixed.values / g, color="0.6", lw=0.8, label="ground (PGA)")
        up, dn = isolated.model.uplift_limits if isolated is not None else fixed.model.uplift_limits
        ax.axhline(min(up, dn) / g, color="C1", ls=":", lw=0.8, label="statue uplift limit")
        ax.set_xlabel("PGA [g]")
        ax.set_ylabel("peak acceleration [g]")
        ax.legend(loc="upper left", bbox_to_anchor=(0.0, -0.15), ncol=3, fontsize=8)
        ax.set_title("what the statue feels on the isolator", fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def _response_axis(ax, peak: float, label: str) -> None:
    """theta/delta axis that shows the response: the overturning lines at +-1 only when
    the response comes within 30 % of them, otherwise an axis scaled to the response
    and a note that +-1 is off the scale."""
    if peak >= 0.3:
        for y in (1, -1):
            ax.axhline(y, color="0.5", lw=0.6, ls="--")
        ax.set_ylim(-1.15, 1.15)
    else:
        top = max(peak, 1e-6) * 1.25
        ax.set_ylim(-top, top)
        ax.text(0.01, 0.97, "overturning at +-1 (off the scale)", transform=ax.transAxes, fontsize=7,
                va="top", color="0.4")
    ax.set_ylabel(label)


def plot_history_pair(fixed, plate, coupled, path) -> Path:
    """One time history on a fixed base (RockingResult with history) and on the
    isolator (IsolatorResult of the plate and the CoupledResult of plate + statue; both
    may be None): theta/delta, the ground and plate accelerations, and the plate's
    displacement against the isolator's capacity. Legends sit outside the axes; each
    axis is scaled to what it shows."""
    plt = _pyplot()
    p = fixed.model.params
    rows = 3 if plate is not None else 2
    fig, axes = plt.subplots(rows, 1, figsize=(11, 2.6 * rows + 1), sharex=True,
                             gridspec_kw={"height_ratios": [3, 2, 2][:rows]})
    ax1, ax2 = axes[0], axes[1]
    h = fixed.history
    th = h["theta"]
    rel = np.where(th >= 0, th / p.delta_R, th / p.delta_L)
    peak = float(np.abs(rel).max()) if len(rel) else 0.0
    ax1.plot(h["t"], rel, lw=0.9, color="C3", label=f"fixed base: {fixed.outcome}")
    if coupled is not None and coupled.uplift:
        tc = coupled.theta
        rc = np.where(tc >= 0, tc / p.delta_R, tc / p.delta_L)
        peak = max(peak, float(np.abs(rc).max()))
        ax1.plot(coupled.t, rc, lw=0.9, color="C0", label=f"on the isolator: {coupled.outcome}")
    elif coupled is not None:
        ax1.plot([h["t"][0], h["t"][-1]], [0, 0], lw=0.9, color="C0",
                 label=f"on the isolator: {coupled.outcome}")
    _response_axis(ax1, peak, "theta / delta [-]  (+ right pivot)")
    ax1.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax1.set_title(fixed.motion.label, fontsize=9)
    t = h["t"]
    ax2.plot(t, fixed.motion.acc(t) / p.g, lw=0.6, color="0.4", label="ground u_g''")
    if plate is not None:
        ax2.plot(plate.t, plate.acc_abs / p.g, lw=0.8, color="C0", label="plate (absolute)")
    lim_up, lim_dn = fixed.model.uplift_limits
    ax2.axhline(lim_up / p.g, color="C1", lw=0.6, ls=":")
    ax2.axhline(-lim_dn / p.g, color="C1", lw=0.6, ls=":", label="statue uplift limits")
    ax2.set_ylabel("acceleration [g]")
    ax2.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    if plate is not None:
        ax3 = axes[2]
        ax3.plot(plate.t, plate.u * 1000, lw=0.8, color="C0", label="plate displacement u_o")
        cap = getattr(plate.isolator, "capacity", float("inf"))
        if np.isfinite(cap):
            for sgn in (1, -1):
                ax3.axhline(sgn * cap * 1000, color="C3", lw=0.8, ls="--",
                            label="isolator capacity" if sgn > 0 else None)
        ax3.set_ylabel("u_o [mm]")
        ax3.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    axes[-1].set_xlabel("t [s]")
    fig.tight_layout()
    return _save(fig, path)
