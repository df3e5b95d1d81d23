"""Figures of the 2D dynamics (matplotlib Agg, imported only when drawing).

Example
-------
>>> import tempfile, pathlib
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel, simulate
>>> model = RockingModel.housner(RockingParams.rectangular_block(0.0384, 0.2, 1.286), e_L=0.9, e_R=0.9)
>>> r = simulate(model, motions.cosine_pulse(0.3 * 9.81, 2.0), dt_out=0.005)
>>> plot_time_history(r, pathlib.Path(tempfile.mkdtemp()) / "rock.png").exists()
True
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io.files import atomic_write
from .plots import _pyplot

OUTCOME_COLOURS = ["#ffffff", "#c6dbef", "#6baed6", "#fdae6b", "#e6550d", "#a63603"]
EXTRA_COLOURS = {-1: "#969696", -2: "#e5f5e0", -3: "#6a3d9a"}
"""Colours of the negative codes: -1 solver failed (grey), -2 not applicable (pale green),
-3 isolator capacity exceeded (purple: a failure of its own, apart from the overturning reds)."""
CAPACITY_CODE = -3


def _save(fig, path) -> Path:
    plt = _pyplot()
    out = atomic_write(path, lambda p: fig.savefig(p, dpi=120, format="png"))
    plt.close(fig)
    return out


def plot_time_history(result, path) -> Path:
    """theta/delta and the ground acceleration against time, impacts marked."""
    plt = _pyplot()
    h = result.history
    p = result.model.params
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(10, 6), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    th = h["theta"]
    norm = np.where(th >= 0, th / p.delta_R, th / p.delta_L)
    ax1.plot(h["t"], norm, lw=1.0, color="C0")
    ax1.axhline(1, color="C3", lw=0.6, ls="--")
    ax1.axhline(-1, color="C3", lw=0.6, ls="--")
    for ti in result.impact_times[:500]:
        ax1.axvline(ti, color="0.85", lw=0.4, zorder=0)
    ax1.set_ylabel("theta / delta  (+ right pivot)")
    ax1.set_title(f"{result.motion.label}: {result.outcome}, |theta|max/delta = {result.theta_max_over_delta:.3f}, "
                  f"{result.n_impacts} impacts")
    ax2.plot(h["t"], result.motion.acc(h["t"]) / p.g, lw=0.8, color="0.3")
    lim_up, lim_dn = result.model.uplift_limits
    ax2.axhline(lim_up / p.g, color="C1", lw=0.6, ls=":")
    ax2.axhline(-lim_dn / p.g, color="C1", lw=0.6, ls=":")
    ax2.set_ylabel("u_g'' / g")
    ax2.set_xlabel("t [s]")
    fig.tight_layout()
    return _save(fig, path)


def plot_spectrum(sp, path, title: str | None = None) -> Path:
    """Outcome map over (frequency, amplitude/g), thesis Fig. 65-68 style. Negative codes
    (isolator capacity exceeded, not applicable, solver failed) get classes and colours of
    their own; an isolated spectrum with a finite capacity always lists 'isolator capacity
    exceeded' in its legend."""
    plt = _pyplot()
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from ..rocking.batch import OUTCOMES
    from ..rocking.spectrum import label

    g = sp.model.params.g
    codes = np.asarray(sp.codes, dtype=np.int64)
    extra = sorted({int(c) for c in np.unique(codes[codes < 0])}
                   | ({CAPACITY_CODE} if np.isfinite(getattr(sp, "capacity", np.inf)) else set()), reverse=True)
    classes = list(range(len(OUTCOMES))) + extra
    colours = OUTCOME_COLOURS[:len(OUTCOMES)] + [EXTRA_COLOURS.get(c, "#000000") for c in extra]
    index = np.vectorize({c: i for i, c in enumerate(classes)}.__getitem__, otypes=[np.int64])(codes)
    fig, ax = plt.subplots(figsize=(10, 6))
    cmap = ListedColormap(colours)
    norm = BoundaryNorm(np.arange(-0.5, len(classes) + 0.5), cmap.N)
    ax.pcolormesh(sp.freqs, sp.amps / g, index.T, cmap=cmap, norm=norm, shading="nearest")
    lim_up, lim_dn = sp.model.uplift_limits
    ax.axhline(min(lim_up, lim_dn) / g, color="k", lw=0.6, ls=":")
    ax.set_xlabel("pulse frequency [Hz]")
    ax.set_ylabel("pulse amplitude [g]")
    ax.set_title(title or f"stability spectrum, one-{sp.pulse} pulse ({sp.codes.size} runs)")
    names = list(OUTCOMES) + [label(c) for c in extra]
    handles = [Patch(fc=c, ec="0.5", label=n) for c, n in zip(colours, names)]
    handles.append(Line2D([], [], color="k", lw=0.6, ls=":", label="uplift acceleration"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)   # off the data
    fig.tight_layout()
    return _save(fig, path)


def plot_spectrum_not_applicable(sp, path) -> Path:
    """:func:`plot_spectrum` with the points where the model does not apply (``sp.applicable``
    false: the body slides before it rocks) masked, grey (the axes' background)."""
    import dataclasses

    import matplotlib

    shown = dataclasses.replace(sp, codes=np.ma.masked_array(sp.codes, mask=~sp.applicable))
    with matplotlib.rc_context({"axes.facecolor": "0.55"}):
        return plot_spectrum(shown, path, f"stability spectrum, one-{sp.pulse} pulse ({sp.codes.size} runs; grey: "
                                          f"not applicable, slides before it rocks)")


def plot_sweep(sw, path) -> Path:
    """Response against the swept value, and its distribution."""
    plt = _pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5), gridspec_kw={"width_ratios": [2, 1]})
    x = sw.values / sw.model.params.g if sw.name == "pga_m_s2" else sw.values
    ax1.plot(x, sw.theta_max_over_delta, "o-", ms=3, lw=0.8)
    ax1.plot(x[sw.overturned], np.ones(sw.overturned.sum()), "x", color="C3", label="overturned")
    ax1.set_xlabel("PGA / g" if sw.name == "pga_m_s2" else sw.name)
    ax1.set_ylabel("|theta|max / delta")
    ax1.set_ylim(bottom=0)
    if sw.overturned.any():
        ax1.legend()
    ax2.hist(sw.theta_max_over_delta, bins=min(30, max(5, sw.values.size // 3)), color="C0", ec="w")
    ax2.set_xlabel("|theta|max / delta")
    ax2.set_ylabel("count")
    s = sw.summary()
    ax2.set_title(f"mean {s['mean']:.3f}, p95 {s['p95']:.3f}, {s['n_overturned']} overturned", fontsize=9)
    fig.suptitle(f"{sw.motion.label}: sweep of {sw.name} ({sw.values.size} runs)")
    fig.tight_layout()
    return _save(fig, path)


def plot_identification(ident, path) -> Path:
    """Measured e per impact against impact speed, and the fitted lines."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for side, colour in (("L", "C0"), ("R", "C1")):
        sel = ident.side == side
        ax.plot(ident.speed[sel], ident.e[sel], "o", color=colour, label=f"e_{side} (landing on the {side} edge)")
        f = ident.fit[side]
        w = np.linspace(*f["speed_range_rad_s"], 20)
        ax.plot(w, f["c0"] + f["c1"] * w, color=colour, lw=1)
    ax.set_xlabel("|theta'| before impact [rad/s]")
    ax.set_ylabel("e")
    ax.legend()
    fig.tight_layout()
    return _save(fig, path)


def plot_table_motion(t, a, v, u, label, path) -> Path:
    """Acceleration, velocity and displacement of the shake table."""
    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(9, 6), sharex=True)
    for ax, y, name in zip(axes, (a, v, u), ("acc [m/s^2]", "vel [m/s]", "disp [m]")):
        ax.plot(t, y, lw=0.8)
        ax.set_ylabel(name)
    axes[0].set_title(label)
    axes[-1].set_xlabel("t [s]")
    fig.tight_layout()
    return _save(fig, path)
