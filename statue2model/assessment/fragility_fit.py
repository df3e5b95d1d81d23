"""The statistics of a fragility study: the lognormal fit of failure counts, its bands, and the curve.

Fit (Baker 2015, Earthquake Spectra 31(1)): at level x_j, z_j of n_j runs fail; P(fail | x) =
Phi(ln(x / theta) / beta); theta (median) and beta (dispersion) maximise the binomial likelihood
(:func:`fit_lognormal`, :func:`fit_lognormal_many` for the bootstrap's replicates), the
profile-likelihood band of beta (:func:`beta_profile_band`), whether the median and the spread are
identified (:func:`median_reason`, :func:`spread_reason`, :func:`identified_reason`), and
:class:`FragilityCurve` (counts, fit, bands; to_dict / from_dict). The runs, the adaptive levels
and the study are assessment/fragility.py's, which re-exports these names.

>>> import numpy as np
>>> m, b, st = fit_lognormal(np.array([1.0, 2.0, 3.0, 4.0]), np.array([0, 2, 5, 7]), np.full(4, 7))
>>> st, bool(1.5 < m < 3.0)
('ok', True)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..quantities import G  # m/s^2: the g every report prints
from ..errors import InputError
from .states import CURVE_LABELS as LABELS

BETA_MIN, BETA_MAX = 1e-3, 5.0
MIN_PARTIAL = 2
"""Levels with a partial fraction of failures a curve needs for its spread to count as identified."""
REASONS = {"no runs": "no run counted at any level", "no failures": "no failure at any level",
           "all failed": "failure at every level", "one level": "one level: spread not identified"}
"""Why a fit's median and beta are undefined, by status (the text written beside a null)."""


# --- the lognormal fit ----------------------------------------------------------------
def _nll(ln_theta, ln_beta, lnx, z, n):
    """Negative binomial log-likelihood; ln_theta, ln_beta broadcast against (..., 1)."""
    from scipy.special import log_ndtr

    u = (lnx - ln_theta) / np.exp(ln_beta)
    return -(z * log_ndtr(u) + (n - z) * log_ndtr(-u)).sum(axis=-1)


def _nll_grad(q, lnx, z, n):
    """The negative log-likelihood at q = (ln theta, ln beta) and its gradient."""
    from scipy.special import log_ndtr

    beta = math.exp(q[1])
    u = (lnx - q[0]) / beta
    lp, lm = log_ndtr(u), log_ndtr(-u)
    lphi = -0.5 * u * u - 0.5 * math.log(2 * math.pi)
    dll = z * np.exp(lphi - lp) - (n - z) * np.exp(lphi - lm)      # d(log-likelihood)/du
    f = -(z * lp + (n - z) * lm).sum()
    return f, np.array([(dll / beta).sum(), (dll * u).sum()])


def fit_lognormal(levels, n_fail, n_trials) -> tuple[float, float, str]:
    """(median, beta, status) of the maximum-likelihood lognormal curve through the binomial
    counts (see the module docstring); median and beta are nan unless status is "ok" or "step"
    (the others' reasons: REASONS). Identified only with runs at two levels or more, at least
    one failure and one survival.

    >>> fit_lognormal([5.0], [3], [7])           # one point: any beta passes through it
    (nan, nan, 'one level')
    >>> fit_lognormal([1.0, 2.0, 4.0], [0, 0, 0], [7, 7, 7])[2], REASONS["no failures"]
    ('no failures', 'no failure at any level')
    """
    from scipy.optimize import minimize

    x = np.asarray(levels, dtype=float)
    z = np.asarray(n_fail, dtype=float)
    n = np.asarray(n_trials, dtype=float)
    keep = n > 0
    x, z, n = x[keep], z[keep], n[keep]
    nan = float("nan")
    if x.size == 0:
        return nan, nan, "no runs"
    if z.sum() == 0:
        return nan, nan, "no failures"
    if z.sum() == n.sum():
        return nan, nan, "all failed"
    if np.unique(x).size < 2:
        return nan, nan, "one level"
    lnx = np.log(x)
    lo, hi = lnx.min() - 3.0, lnx.max() + 3.0
    bl, bh = math.log(BETA_MIN), math.log(BETA_MAX)
    gt = np.linspace(lo, hi, 61)[:, None, None]
    gb = np.linspace(bl, bh, 31)[None, :, None]
    f = _nll(gt, gb, lnx, z, n)
    i, j = np.unravel_index(np.argmin(f), f.shape)
    start = np.array([gt[i, 0, 0], gb[0, j, 0]])
    res = minimize(_nll_grad, start, args=(lnx, z, n), jac=True, method="TNC",
                   bounds=[(lo, hi), (bl, bh)], options={"ftol": 1e-14, "gtol": 1e-10})
    q = res.x if res.fun <= f[i, j] else start
    beta = float(np.exp(q[1]))
    return float(np.exp(q[0])), beta, ("step" if beta <= BETA_MIN * 1.0001 else "ok")


def lognormal_cdf(x, median: float, beta: float) -> np.ndarray:
    """Phi(ln(x / median) / beta); nan if the curve is undefined."""
    from scipy.stats import norm

    x = np.asarray(x, dtype=float)
    if not (math.isfinite(median) and math.isfinite(beta)):
        return np.full(x.shape, np.nan)
    return norm.cdf(np.log(x / median) / beta)


def _probit_terms(u, z, n):
    """(log-likelihood terms, d/du, d2/du2) of the binomial probit terms z ln Phi(u) + (n - z) ln Phi(-u)."""
    from scipy.special import log_ndtr

    lp, lm = log_ndtr(u), log_ndtr(-u)
    lphi = -0.5 * u * u - 0.5 * math.log(2 * math.pi)
    lam_p, lam_m = np.exp(lphi - lp), np.exp(lphi - lm)          # phi / Phi(u), phi / Phi(-u)
    d1 = z * lam_p - (n - z) * lam_m
    d2 = -z * lam_p * (u + lam_p) - (n - z) * lam_m * (lam_m - u)
    return z * lp + (n - z) * lm, d1, d2


def _newton_rows(xc, Z, N, c0, d0, iters: int = 60):
    """Maximum likelihood of P = Phi(c x - d) for every row of counts Z, N (B, L) on centred
    ln levels ``xc`` (L,): damped Newton on the convex negative log-likelihood in (c, d), c kept in
    [1 / BETA_MAX, 1 / BETA_MIN], from (c0, d0) (B,); each iteration a joint step, then a step in
    d alone (the slope may sit on its bound), each with a backtracking line search; a row stops
    once an iteration improves its likelihood by less than 1e-12 (relative). Returns (c, d)."""
    cmin, cmax = 1.0 / BETA_MAX, 1.0 / BETA_MIN
    c, d = np.clip(np.asarray(c0, float), cmin, cmax), np.asarray(d0, float).copy()

    def nll(c_, d_, Zr, Nr):
        return -_probit_terms(c_[:, None] * xc - d_[:, None], Zr, Nr)[0].sum(axis=1)

    def search(c, d, f, sc, sd, Zr, Nr):
        cn, dn, fn = c.copy(), d.copy(), f.copy()
        todo = np.flatnonzero((sc != 0) | (sd != 0))
        step = 1.0
        for _ in range(40):                                    # backtracking on the rows still searching
            if not todo.size:
                break
            ct = np.clip(c[todo] + step * sc[todo], cmin, cmax)
            dt = d[todo] + step * sd[todo]
            ft = nll(ct, dt, Zr[todo], Nr[todo])
            better = ft < f[todo]
            k = todo[better]
            cn[k], dn[k], fn[k] = ct[better], dt[better], ft[better]
            todo = todo[~better]
            step *= 0.5
        return cn, dn, fn

    f = nll(c, d, Z, N)
    act = np.arange(c.size)
    for _ in range(iters):
        if not act.size:
            break
        ca, da, fa, Za, Na = c[act], d[act], f[act], Z[act], N[act]
        _, d1, d2 = _probit_terms(ca[:, None] * xc - da[:, None], Za, Na)
        gc, gd = -(d1 * xc).sum(1), (d1).sum(1)                 # gradient of the nll
        hcc, hcd, hdd = -(d2 * xc * xc).sum(1), (d2 * xc).sum(1), -(d2).sum(1)
        det = hcc * hdd - hcd * hcd
        ok = det > 1e-14 * np.maximum(hcc * hdd, 1e-300)
        sc = np.where(ok, -(hdd * gc - hcd * gd) / np.where(ok, det, 1.0), 0.0)
        sd = np.where(ok, -(hcc * gd - hcd * gc) / np.where(ok, det, 1.0), 0.0)
        c1, d1_, f1 = search(ca, da, fa, sc, sd, Za, Na)
        _, e1, e2 = _probit_terms(c1[:, None] * xc - d1_[:, None], Za, Na)
        g2, h2 = e1.sum(1), -e2.sum(1)
        c2, d2_, f2 = search(c1, d1_, f1, np.zeros_like(c1), np.where(h2 > 0, -g2 / np.maximum(h2, 1e-300), 0.0),
                             Za, Na)
        c[act], d[act], f[act] = c2, d2_, f2
        act = act[fa - f2 > 1e-12 * np.maximum(np.abs(fa), 1.0)]
    return c, d


def fit_lognormal_many(levels, n_fail, n_trials, start: tuple | None = None) -> tuple[np.ndarray, np.ndarray, list]:
    """(median, beta, status) of :func:`fit_lognormal` for every row of the counts ``n_fail``,
    ``n_trials`` (B, L) at the common ``levels`` (L,), all rows at once (bootstrap replicates):
    the same statuses, and for a fitted row the same maximum (measured on 300 random count sets:
    never a lower likelihood than fit_lognormal's by more than 1e-13; the probit likelihood is convex
    in the slope 1/beta and the intercept ln(median)/beta: damped Newton from a coarse
    grid, the slope bounded to [1 / BETA_MAX, 1 / BETA_MIN], the median to the fit's bounds). Where
    the counts are separable (no partial level, every failure above every survival) the row is a
    "step" at once: beta BETA_MIN, the median the geometric middle of the gap. With one partial
    level the likelihood has a ridge toward beta -> 0 and the two fitters may stop at different
    points of it (same likelihood to 1e-5): such a spread is not identified (:func:`spread_reason`).
    ``start``: (median, beta) every row starts from (the full data's fit, for bootstrap replicates;
    the likelihood being convex, the start changes the path, not the maximum), else a coarse grid.

    >>> lv, n = [1.0, 1.5, 2.0, 3.0, 4.0], [50] * 5
    >>> med, beta, st = fit_lognormal_many(lv, [[0, 10, 25, 40, 50], [0] * 5], [n, n])
    >>> m1, b1, _ = fit_lognormal(lv, [0, 10, 25, 40, 50], n)
    >>> st, bool(abs(med[0] / m1 - 1) < 1e-6 and abs(beta[0] / b1 - 1) < 1e-5)
    (['ok', 'no failures'], True)
    """
    x = np.asarray(levels, dtype=float)
    Z = np.atleast_2d(np.asarray(n_fail, dtype=float))
    N = np.atleast_2d(np.asarray(n_trials, dtype=float))
    B = Z.shape[0]
    med, beta = np.full(B, np.nan), np.full(B, np.nan)
    status = []
    has = N > 0
    zt, nt = (Z * has).sum(1), (N * has).sum(1)
    fit = np.zeros(B, dtype=bool)
    for b in range(B):
        if nt[b] == 0:
            status.append("no runs")
        elif zt[b] == 0:
            status.append("no failures")
        elif zt[b] == nt[b]:
            status.append("all failed")
        elif np.unique(x[has[b]]).size < 2:
            status.append("one level")
        else:
            none, all_ = has[b] & (Z[b] == 0), has[b] & (Z[b] == N[b])
            if not np.any(has[b] & ~none & ~all_) and x[none].max() < x[all_].min():
                status.append("step")              # separable: the likelihood's sup is at beta -> 0
                med[b], beta[b] = math.sqrt(x[none].max() * x[all_].min()), BETA_MIN
            else:
                status.append("ok")
                fit[b] = True
    if not fit.any():
        return med, beta, status
    lnx = np.log(x)
    used = has.any(axis=0)
    lo, hi = lnx[used].min() - 3.0, lnx[used].max() + 3.0
    mean = float(lnx[used].mean())
    xc = np.where(used, lnx - mean, 0.0)
    Zf, Nf = np.where(has, Z, 0.0)[fit], np.where(has, N, 0.0)[fit]    # the separable rows are set
    if start is not None and all(math.isfinite(v) and v > 0 for v in start):
        c0 = np.full(Zf.shape[0], 1.0 / min(max(float(start[1]), BETA_MIN), BETA_MAX))
        d0 = c0 * (min(max(math.log(float(start[0])), lo), hi) - mean)
    else:   # a coarse grid for the start (as fit_lognormal's, coarser): ln median x ln beta
        gt = np.linspace(lo, hi, 25) - mean
        gb = np.exp(np.linspace(math.log(BETA_MIN), math.log(BETA_MAX), 13))
        u = (xc[None, None, :] - gt[:, None, None]) / gb[None, :, None]              # (25, 13, L)
        f = np.stack([-_probit_terms(u, zr, nr)[0].sum(-1) for zr, nr in zip(Zf, Nf)])  # (Bf, 25, 13)
        i, j = np.unravel_index(f.reshape(f.shape[0], -1).argmin(1), f.shape[1:])
        c0 = 1.0 / gb[j]
        d0 = gt[i] * c0
    c, d = _newton_rows(xc, Zf, Nf, c0, d0)
    a = np.clip(d / c + mean, lo, hi)
    bt = 1.0 / c
    med[fit], beta[fit] = np.exp(a), bt
    k = 0
    for b in range(B):
        if fit[b]:
            if bt[k] <= BETA_MIN * 1.0001:
                status[b] = "step"
            k += 1
    return med, beta, status


def beta_profile_band(levels, n_fail, n_trials, confidence: float = 0.90) -> tuple[tuple, str | None]:
    """((lo, hi), note): the profile-likelihood band of beta at ``confidence`` (two-sided): the betas
    whose log-likelihood, maximised over the median, is within chi2_1(confidence) / 2 of the
    maximum (on a grid of 241 betas, log-spaced over [BETA_MIN, BETA_MAX], interpolated). An end
    that reaches BETA_MIN (a step fits the counts: the spread is not bounded below) or BETA_MAX is
    not identified: nan, and the note says which. (nan, nan) with a note when the counts have no fit.

    >>> (lo, hi), note = beta_profile_band([1.0, 2.0, 4.0], [0, 0, 7], [7, 7, 7])
    >>> bool(lo != lo), note.startswith("lower end not identified")
    (True, True)
    >>> (lo, hi), note = beta_profile_band([1.0, 1.5, 2.0, 3.0, 4.0], [0, 10, 25, 40, 50], [50] * 5)
    >>> round(lo, 3), round(hi, 3), note            # brute force (scipy, fine beta): 0.2832, 0.3999
    (0.283, 0.4, None)
    """
    from scipy.stats import chi2

    x = np.asarray(levels, dtype=float)
    z = np.asarray(n_fail, dtype=float)
    n = np.asarray(n_trials, dtype=float)
    keep = n > 0
    x, z, n = x[keep], z[keep], n[keep]
    med, beta, st = fit_lognormal(x, z, n)
    nan = float("nan")
    if st not in ("ok", "step"):
        return (nan, nan), f"no band: the fit is undefined ({REASONS.get(st, st)})"
    lnx = np.log(x)
    mean = float(lnx.mean())
    xc = lnx - mean
    betas = np.exp(np.linspace(math.log(BETA_MIN), math.log(BETA_MAX), 241))
    c = 1.0 / betas
    # for each beta the best median: bisection on the intercept's derivative (the nll is convex in it)
    lo_a, hi_a = lnx.min() - 3.0 - mean, lnx.max() + 3.0 - mean
    dl, dh = c * lo_a, c * hi_a
    Zr, Nr = np.broadcast_to(z, (c.size, z.size)), np.broadcast_to(n, (c.size, n.size))
    for _ in range(64):
        d = 0.5 * (dl + dh)
        g = _probit_terms(c[:, None] * xc - d[:, None], Zr, Nr)[1].sum(1)     # d nll / d d
        dl, dh = np.where(g < 0, d, dl), np.where(g < 0, dh, d)
    d = 0.5 * (dl + dh)
    prof = -_probit_terms(c[:, None] * xc - d[:, None], Zr, Nr)[0].sum(1)
    best = min(float(prof.min()), float(_nll(math.log(med), math.log(beta), lnx, z, n)))
    inside = prof - best <= 0.5 * float(chi2.ppf(confidence, 1))
    notes = []
    idx = np.flatnonzero(inside)
    if not idx.size:
        return (nan, nan), "no band: the profile has no point within the threshold"
    thr = best + 0.5 * float(chi2.ppf(confidence, 1))
    lb = np.log(betas)

    def cross(i_in, i_out):
        p_in, p_out = prof[i_in], prof[i_out]
        w = (thr - p_in) / (p_out - p_in) if p_out != p_in else 0.0
        return float(np.exp(lb[i_in] + w * (lb[i_out] - lb[i_in])))

    i0, i1 = int(idx[0]), int(idx[-1])
    lo = nan if i0 == 0 else cross(i0, i0 - 1)
    hi = nan if i1 == betas.size - 1 else cross(i1, i1 + 1)
    if i0 == 0:
        notes.append(f"lower end not identified: a step (beta -> {BETA_MIN:g}) fits the counts")
    if i1 == betas.size - 1:
        notes.append(f"upper end not identified: beta up to {BETA_MAX:g} fits the counts")
    return (lo, hi), ("; ".join(notes) or None)


def partial_levels(n_fail, n_trials) -> int:
    """How many levels have a partial fraction of failures, 0 < z < n."""
    z, n = np.asarray(n_fail), np.asarray(n_trials)
    return int(np.sum((z > 0) & (z < n)))


def median_reason(cv) -> str | None:
    """None when the fitted median of curve ``cv`` lies within the levels it ran (else the median is
    an extrapolation of the fit: not identified, and why); None too for a curve without a fit, and
    for one fitted on exact thresholds (EXACT: its median is their geometric mean, not a fit's)."""
    if not cv.fitted or cv.status == EXACT:
        return None
    lv = np.asarray(cv.levels, dtype=float)[np.asarray(cv.n_trials) > 0]
    if cv.median < lv.min():
        return (f"median not identified: the fit puts it at {cv.median / G:.3f} g, below the lowest level run "
                f"({lv.min() / G:.3f} g)")
    if cv.median > lv.max():
        return (f"median not identified: the fit puts it at {cv.median / G:.3f} g, above the highest level run "
                f"({lv.max() / G:.3f} g)")
    return None


def identified_reason(cv, confidence: float = 0.90) -> str | None:
    """None when curve ``cv`` is identified: its median within the levels run (:func:`median_reason`)
    and its spread identified (:func:`spread_reason`); else the first reason. A probability from a
    curve that is not identified is not stored (None with this reason). None for a curve without a fit."""
    return median_reason(cv) or spread_reason(cv, confidence)


def spread_reason(cv, confidence: float = 0.90) -> str | None:
    """None when the dispersion beta of curve ``cv`` (a FragilityCurve) is identified by its counts
    (module docstring), else why not: a step (failures from none to all between two adjacent
    levels: any beta up to the gap fits), fewer than MIN_PARTIAL levels with a partial fraction of
    failures, a profile-likelihood band of beta with an end not identified, or a bootstrap band with
    an end not identified. None too for a curve without a fit (its ``reason`` says why). A
    probability from a fit whose spread is not identified is not known and is not stored."""
    if not cv.fitted or cv.status == EXACT:     # exact thresholds: beta is their log standard deviation
        return None
    lv = np.asarray(cv.levels, dtype=float)
    zf, nt = np.asarray(cv.n_fail), np.asarray(cv.n_trials)
    partial = partial_levels(zf, nt)
    if partial == 0:
        with np.errstate(invalid="ignore", divide="ignore"):
            frac = np.where(nt > 0, zf / np.maximum(nt, 1), np.nan)
        below, above = lv[frac == 0], lv[frac >= 1]
        gap = (f" (from none at {below.max() / G:.3f} g to all at {above.min() / G:.3f} g)"
               if below.size and above.size else "")
        return f"spread not identified: the failures jump between adjacent levels{gap}; beta is not known"
    if partial < MIN_PARTIAL:
        at = lv[(zf > 0) & (zf < nt)]
        return (f"spread not identified: {partial} level with a partial fraction of failures (at "
                f"{at[0] / G:.3f} g), {MIN_PARTIAL} are needed (with one, a step through it fits "
                "best); beta is not known")
    if cv.status == "step":
        return "spread not identified: the best fit is a step (beta at its floor); beta is not known"
    prof = getattr(cv, "beta_profile", None)
    note = getattr(cv, "beta_profile_note", None)
    if prof is None:
        prof, note = beta_profile_band(lv, zf, nt, confidence)
    if not all(math.isfinite(x) for x in prof):
        return f"spread not identified: its profile-likelihood band has an end not identified ({note})"
    lo, hi = (float(x) for x in cv.beta_ci)
    boot = getattr(cv, "boot_undefined", None)
    if boot and not (math.isfinite(lo) and math.isfinite(hi)):
        return f"spread not identified: its band has an end not identified ({cv.beta_ci_note or 'bootstrap'})"
    if boot and lo <= BETA_MIN * 1.0001:
        return (f"spread not identified: its bootstrap band of beta reaches a step ({boot.get('steps', 0)} of "
                f"{boot.get('replicates', 0)} replicates over the records or samples fit one: the levels do not "
                "separate their thresholds)")
    if boot and hi >= BETA_MAX * 0.9999:
        return f"spread not identified: its bootstrap band of beta reaches {BETA_MAX:g}"
    return None


@dataclass(frozen=True, eq=False)
class FragilityCurve:
    """One outcome: counts per level, the fit, its bootstrap bands (``confidence`` level).
    levels (L,) in the IM's unit; n_fail, n_trials (L,) int; median (IM unit), beta; status
    (``reason``: why median and beta are nan, None when fitted); median_ci, beta_ci: (lo, hi),
    an end nan when not identified, ``median_ci_note`` / ``beta_ci_note`` saying why (or
    what the band was computed on); band_lo, band_hi (L,): P at each level (nan when the
    curve is undefined); ``boot_undefined``: replicates per undefined status; ``beta_profile``:
    the profile-likelihood band of beta (:func:`beta_profile_band`; None: not computed, then
    computed from the counts when asked), ``beta_profile_note`` why an end is nan."""

    outcome: str
    levels: np.ndarray
    n_fail: np.ndarray
    n_trials: np.ndarray
    median: float
    beta: float
    status: str
    median_ci: tuple = (float("nan"), float("nan"))
    beta_ci: tuple = (float("nan"), float("nan"))
    band_lo: np.ndarray = None
    band_hi: np.ndarray = None
    median_ci_note: str | None = None
    beta_ci_note: str | None = None
    boot_undefined: dict = field(default_factory=dict)
    beta_profile: tuple | None = None
    beta_profile_note: str | None = None

    @property
    def fitted(self) -> bool:
        """Whether median and beta are defined (status "ok" or "step")."""
        return self.status in ("ok", "step", EXACT)

    @property
    def reason(self) -> str | None:
        """Why the fit is undefined (REASONS), None when it is defined."""
        return None if self.fitted else REASONS.get(self.status, self.status)

    @property
    def fraction(self) -> np.ndarray:
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.n_trials > 0, self.n_fail / np.maximum(self.n_trials, 1), np.nan)

    def probability(self, x) -> np.ndarray:
        """The fitted P(failure | IM = x)."""
        return lognormal_cdf(x, self.median, self.beta)

    @property
    def partial(self) -> int:
        """Levels with a partial fraction of failures."""
        return partial_levels(self.n_fail, self.n_trials)

    @property
    def spread(self) -> str | None:
        """:func:`identified_reason` of this curve: None when its median and beta are identified (or
        there is no fit: see ``reason``), else why not."""
        return identified_reason(self)

    @classmethod
    def from_dict(cls, d: dict) -> FragilityCurve:
        """The curve of :meth:`to_dict` (fragility.json's ``curves[key]``): a None number back as nan;
        ``FragilityCurve.from_dict(c.to_dict()).to_dict() == c.to_dict()``. A key outside the registry
        (assessment/states.py), counts that do not match the levels or a non-number is an InputError
        naming it."""
        if not isinstance(d, dict):
            raise InputError(f"fragility curve: expected a table, got {type(d).__name__}")
        key = d.get("outcome")
        if key not in LABELS:
            raise InputError(f"fragility curve: unknown outcome {key!r:.40} (one of {', '.join(LABELS)})")

        def num(x, what):
            if x is None:
                return math.nan
            if isinstance(x, bool) or not isinstance(x, (int, float)):
                raise InputError(f"fragility curve {key}: {what} must be a number, got {x!r:.40}")
            return float(x)

        def arr(name, kind=float):
            v = d.get(name)
            if v is None:
                return None
            if not isinstance(v, list):
                raise InputError(f"fragility curve {key}: {name} must be a list")
            out = np.array([num(x, name) for x in v], dtype=float)
            return out.astype(int) if kind is int else out

        levels, n_fail, n_trials = arr("levels"), arr("n_fail", int), arr("n_trials", int)
        if levels is None or n_fail is None or n_trials is None or not (levels.shape == n_fail.shape == n_trials.shape):
            raise InputError(f"fragility curve {key}: levels, n_fail and n_trials must be lists of one length")
        prof, prof_note = d.get("beta_profile"), d.get("beta_profile_note")
        profile = (None if prof is None or (all(x is None for x in prof) and prof_note is None)
                   else tuple(num(x, "beta_profile") for x in prof))
        return cls(key, levels, n_fail, n_trials, num(d.get("median"), "median"), num(d.get("beta"), "beta"),
                   str(d.get("status") or ""), tuple(num(x, "median_ci") for x in d.get("median_ci") or (None, None)),
                   tuple(num(x, "beta_ci") for x in d.get("beta_ci") or (None, None)), arr("band_lo"), arr("band_hi"),
                   d.get("median_ci_note"), d.get("beta_ci_note"), dict(d.get("bootstrap_undefined") or {}),
                   profile, prof_note)

    def to_dict(self) -> dict:
        """JSON-ready; an undefined number is None with its reason beside it (``reason`` for the
        fit, its fitted P and bands; ``median_ci_note``, ``beta_ci_note`` for a band end;
        ``spread_reason`` when the median or beta is not identified (``identified`` False): then
        ``fitted`` is None too)."""
        spread = self.spread
        prof = (float("nan"),) * 2 if self.beta_profile is None else self.beta_profile
        return {"outcome": self.outcome, "label": LABELS[self.outcome], "median": _finite(self.median),
                "beta": _finite(self.beta), "status": self.status, "reason": self.reason,
                "identified": bool(self.fitted and spread is None), "spread_reason": spread,
                "partial_levels": self.partial,
                "median_ci": [_finite(x) for x in self.median_ci], "median_ci_note": self.median_ci_note,
                "beta_ci": [_finite(x) for x in self.beta_ci], "beta_ci_note": self.beta_ci_note,
                "beta_profile": [_finite(x) for x in prof], "beta_profile_note": self.beta_profile_note,
                "bootstrap_undefined": dict(self.boot_undefined),
                "levels": self.levels, "n_fail": self.n_fail, "n_trials": self.n_trials,
                "fraction": self.fraction,
                "fitted": None if spread is not None else self.probability(self.levels),
                "band_lo": self.band_lo, "band_hi": self.band_hi}


EXACT = "exact"
"""Status of the fixed-base uplift curve: fitted to each run's exact uplift PGA, not to counts."""


def _finite(v):
    """v as a float, or None when it is not finite (JSON: inf has no spelling; null)."""
    return float(v) if v is not None and np.isfinite(v) else None
