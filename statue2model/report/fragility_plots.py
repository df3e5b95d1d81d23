"""Figure of a fragility study: one panel per limit state (full contact, overturning, and on the
isolator its capacity), the fixed-base and the isolated curve in each (matplotlib Agg, imported
only when drawing). In a panel: the fraction failed at each level a base ran (markers), the
fitted lognormal curve and its bootstrap band where the spread is identified
(assessment.fragility.spread_reason), only the median with its band (a horizontal bar at
P = 0.5) where it is not: a probability from such a fit is not known and is not drawn; the
design level (PGA or PGV) as a vertical dashed line in every panel.

Example
-------
>>> import numpy as np, tempfile, pathlib
>>> from statue2model.assessment.fragility import FragilityStudy, run_fragility
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel
>>> from statue2model.rocking.sampling import nominal
>>> model = RockingModel.housner(RockingParams.rectangular_block(0.0384, 0.2, 1.286), e_L=0.9, e_R=0.9)
>>> recs = [motions.synthetic_record(6.0, 0.01, 1.0, seed=s) for s in range(3)]
>>> res = run_fragility(model, recs, np.linspace(1.0, 12.0, 5), nominal(1), FragilityStudy(n_boot=10))
>>> plot_fragility(res, pathlib.Path(tempfile.mkdtemp()) / "f.png", design_im=3.0).exists()
True
"""
from __future__ import annotations

import math

from ..assessment import states
import numpy as np

from ..assessment.fragility import LIMIT_STATE_CURVES
from ..quantities import G
from .dynamics_plots import _save
from .plots import _pyplot

COLOURS = {"fixed": "#d62728", "isolated": "#1f77b4"}
TITLES = {s.id: s.title for s in states.REGISTRY}
BASE_WORDS = {"fixed": "fixed base", "isolated": "isolated"}


def panels(res) -> list[tuple[str, dict]]:
    """[(limit state, {base: curve name})] of a FragilityResult ``res``: the limit states of
    assessment.fragility.LIMIT_STATE_CURVES whose curves it has."""
    out = []
    for ls, bases in LIMIT_STATE_CURVES.items():
        have = {b: k for b, k in bases.items() if k in res.curves}
        if have:
            out.append((ls, have))
    return out


def _draw_curve(ax, c, base, scale, unit, xs):
    col = COLOURS[base]
    ax.plot(c.levels / scale, c.fraction, "o", ms=3.5, color=col, alpha=0.75)
    word = BASE_WORDS[base]
    if not c.fitted:
        ax.plot([], [], "o", color=col, label=f"{word}: not fitted ({c.reason})")
        return
    spread = c.spread
    lo, hi = (float(x) for x in c.median_ci)
    if c.status == "empirical":     # the step CDF of the exact thresholds, the Wilson band of the count
        t = np.sort(np.asarray(c.thresholds, dtype=float))
        xe = np.concatenate([[min(xs[0], t[0])], t, [max(xs[-1], t[-1])]])
        ax.step(xe / scale, c.probability(xe), where="post", color=col,
                label=f"{word}: empirical, {t.size} thresholds, median {c.median / scale:.3g}{unit}")
        from ..assessment.fragility import wilson_interval

        band = np.array([wilson_interval(int(k), t.size) for k in np.searchsorted(t, xe, side="right")])
        ax.fill_between(xe / scale, band[:, 0], band[:, 1], color=col, alpha=0.15, lw=0, step="post")
        return
    if spread is None:
        ax.plot(xs / scale, c.probability(xs), "-", color=col,
                label=f"{word}: median {c.median / scale:.3g}{unit}, beta {c.beta:.2f}")
        if c.band_lo is not None and np.all(np.isfinite(c.band_lo)):
            ax.fill_between(c.levels / scale, c.band_lo, c.band_hi, color=col, alpha=0.15, lw=0)
        return
    # the spread is not identified: the fractions joined, the median and its band, no curve
    ax.plot(c.levels / scale, c.fraction, "-", lw=0.6, color=col, alpha=0.5)
    xerr = None
    if math.isfinite(lo) and math.isfinite(hi):
        xerr = [[max(c.median - lo, 0.0) / scale], [max(hi - c.median, 0.0) / scale]]
    ax.errorbar([c.median / scale], [0.5], xerr=xerr, fmt="D", ms=5, color=col, capsize=3,
                label=f"{word}: median {c.median / scale:.3g}{unit}; not identified")


def plot_fragility(res, path, design_im: float | None = None, slc_im: float | None = None):
    """The curves of a FragilityResult ``res`` as a PNG at ``path``: one panel per limit state
    (module docstring), fixed base and isolated in each (the overturning panel holds the fixed base's
    overturning and the isolator's failure: the device must lie at or right of it); ``design_im``: the
    design level (PGA m/s^2, or PGV m/s), ``slc_im``: the collapse level (SLC) the device is checked at,
    vertical lines in every panel."""
    plt = _pyplot()
    rows = panels(res)
    fig, axes = plt.subplots(1, len(rows), figsize=(4.1 * len(rows) + 0.4, 4.6), squeeze=False, sharey=True)
    pga = res.im == "pga"
    scale, unit = (G, " g") if pga else (1.0, " m/s")
    lo_all = min(float(np.min(c.levels)) for c in res.curves.values())
    hi_all = max(float(np.max(c.levels)) for c in res.curves.values())
    xs = np.geomspace(lo_all, hi_all, 200)
    show_design = design_im is not None and np.isfinite(design_im) and design_im > 0
    for ax, (ls, bases) in zip(axes[0], rows):
        for base, k in bases.items():
            _draw_curve(ax, res.curves[k], base, scale, unit, xs)
        if show_design:
            ax.axvline(design_im / scale, color="k", ls="--", lw=1.1,
                       label=f"design {'PGA' if pga else 'PGV'} {design_im / scale:.3f}{unit}")
        if pga and slc_im is not None and np.isfinite(slc_im) and slc_im > 0:
            ax.axvline(slc_im / scale, color="firebrick", ls=":", lw=1.3,
                       label=f"collapse level (SLC) PGA {slc_im / scale:.3f}{unit}")
        ax.set_title(TITLES.get(ls, ls), fontsize=9.5)
        ax.set_xlabel("PGA (g)" if pga else "PGV (m/s)")
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6.8, loc="upper left")
    axes[0][0].set_ylabel("probability of exceeding the limit state")
    fig.suptitle(f"fragility per limit state: {len(res.record_labels)} records x {res.samples.n} samples, "
                 f"levels {res.levels[0] / scale:.3g}-{res.levels[-1] / scale:.3g}{unit}; bands "
                 f"{res.study.confidence:.0%} ({res.bootstrap_unit} bootstrap)", fontsize=9)
    fig.tight_layout()
    return _save(fig, path)
