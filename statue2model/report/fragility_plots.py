"""Figure of a fragility study: fractions failed, fitted lognormal curves and their bootstrap
bands, one colour per outcome (matplotlib Agg, imported only when drawing).

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
>>> plot_fragility(res, pathlib.Path(tempfile.mkdtemp()) / "f.png").exists()
True
"""
from __future__ import annotations

import numpy as np

from ..assessment.fragility import LABELS
from ..quantities import G
from .dynamics_plots import _save
from .plots import _pyplot

COLOURS = {"overturn": "#d62728", "overturn_isolated": "#1f77b4", "capacity_exceeded": "#6a3d9a",
           "failure_isolated": "#2ca02c"}


def plot_fragility(res, path, design_im: float | None = None):
    """The curves of a FragilityResult ``res`` as a PNG at ``path``: fractions (markers), fitted
    curves (lines) and their bands (shaded), one colour per outcome; ``design_im``: the design
    level (PGA m/s^2, or PGV m/s) as a vertical line."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    scale = G if res.im == "pga" else 1.0
    xs = np.geomspace(res.levels[0], res.levels[-1], 200)
    for k, c in res.curves.items():
        col = COLOURS[k]
        ax.plot(c.levels / scale, c.fraction, "o", ms=3.5, color=col, alpha=0.7)
        if c.status in ("ok", "step"):
            ax.plot(xs / scale, c.probability(xs), "-", color=col,
                    label=f"{LABELS[k]} (median {c.median / scale:.3g}{' g' if res.im == 'pga' else ' m/s'}, "
                          f"beta {c.beta:.2f})")
        else:
            ax.plot([], [], "o", color=col, label=f"{LABELS[k]} (not fitted: {c.reason})")
        if c.band_lo is not None and np.all(np.isfinite(c.band_lo)):
            ax.fill_between(c.levels / scale, c.band_lo, c.band_hi, color=col, alpha=0.15, lw=0)
    if design_im is not None and np.isfinite(design_im) and design_im > 0:
        ax.axvline(design_im / scale, color="k", ls="--", lw=1.2,
                   label=f"design {'PGA' if res.im == 'pga' else 'PGV'} {design_im / scale:.3f}"
                         f"{' g' if res.im == 'pga' else ' m/s'}")
    ax.set_xlabel("PGA (g)" if res.im == "pga" else "PGV (m/s)")
    ax.set_ylabel("probability")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3)
    ax.set_title(f"fragility: {len(res.record_labels)} records x {res.levels.size} levels x {res.samples.n} "
                 f"samples; bands {res.study.confidence:.0%} ({res.bootstrap_unit} bootstrap)", fontsize=9)
    ax.legend(fontsize=7.5, loc="lower right")
    fig.tight_layout()
    return _save(fig, path)
