"""Figure of a spectrum-compatible record set (matplotlib Agg, imported only when drawing).

Example
-------
>>> import tempfile, pathlib
>>> from statue2model.hazard.code_spectra import parse_spectrum
>>> from statue2model.hazard.matching import match_set
>>> rs = match_set(parse_spectrum("ec8:ag=0.2g"), n=2, duration=5, band=(0.15, 1.0))
>>> plot_spectra(rs, pathlib.Path(tempfile.mkdtemp()) / "spectra.png").exists()
True
"""
from __future__ import annotations

from ..io.files import atomic_write
from ..quantities import G_STANDARD


def plot_spectra(rs, path, title: str = "spectrum-compatible set"):
    """Each record's spectrum of a RecordSet ``rs``, the mean, the target and the tolerance
    band (PNG at ``path``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    g = G_STANDARD
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for k, sp in enumerate(rs.spectra):
        ax.plot(rs.periods, sp / g, color="0.7", lw=0.8, label="records" if k == 0 else None)
    lo, hi = rs.tolerance
    band = rs.in_band
    if hi is None:      # artificial records: a floor, no ceiling
        ax.plot(rs.periods[band], (1 + lo) * rs.target[band] / g, color="tab:green", lw=1.2, ls=":",
                label=f"{(1 + lo) * 100:.0f} % of the target (no upper bound: artificial records)")
    else:
        ax.fill_between(rs.periods[band], (1 + lo) * rs.target[band] / g, (1 + hi) * rs.target[band] / g,
                        color="tab:green", alpha=0.15, label=f"tolerance {lo * 100:+.0f} % / {hi * 100:+.0f} %")
    ax.plot(rs.periods, rs.target / g, "k--", lw=1.5, label="target")
    ax.plot(rs.periods, rs.mean / g, color="tab:red", lw=1.8, label=f"mean of {len(rs.records)}")
    c = rs.check()
    ax.set_xscale("log")
    ax.set_xlabel("period T (s)")
    ax.set_ylabel(f"PSA (g), {rs.xi * 100:g} % damping")
    ax.set_title(f"{title}: code rules {'met' if c['met'] else 'NOT met'}, lowest mean/target "
                 f"{c['min_ratio']:.3f} at {c['period_of_min_s']:.3g} s", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    try:
        return atomic_write(path, lambda p: fig.savefig(p, format="png", dpi=110))
    finally:
        plt.close(fig)
