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


def _probit_ll(u, z, n):
    """The log-likelihood terms z ln Phi(u) + (n - z) ln Phi(-u) alone (those of :func:`_probit_terms`,
    without its derivatives: the line searches ask for the likelihood only)."""
    from scipy.special import log_ndtr

    return z * log_ndtr(u) + (n - z) * log_ndtr(-u)


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
        return -_probit_ll(c_[:, None] * xc - d_[:, None], Zr, Nr).sum(axis=1)

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
        f = np.stack([-_probit_ll(u, zr, nr).sum(-1) for zr, nr in zip(Zf, Nf)])  # (Bf, 25, 13)
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
    prof = -_probit_ll(c[:, None] * xc - d[:, None], Zr, Nr).sum(1)
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
    for one fitted on exact thresholds (EXACT: its median is their geometric mean, not a fit's; EMPIRICAL:
    their median)."""
    if not cv.fitted or cv.status in (EXACT, EMPIRICAL):
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
    if not cv.fitted or cv.status in (EXACT, EMPIRICAL):   # exact thresholds: beta their log std, or no beta
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
    computed from the counts when asked), ``beta_profile_note`` why an end is nan. ``thresholds``: the
    exact thresholds the curve stands on (fixed-base uplift only, :func:`distinct_thresholds`; None
    elsewhere), ``choice``: which curve :func:`choose_uplift_curve` kept and why (None elsewhere). A
    curve of status EMPIRICAL is the step CDF of ``thresholds`` (beta nan: it has none)."""

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
    thresholds: np.ndarray | None = None
    choice: dict | None = None

    @property
    def fitted(self) -> bool:
        """Whether the curve is defined (status "ok", "step", EXACT, or EMPIRICAL: no beta there)."""
        return self.status in ("ok", "step", EXACT, EMPIRICAL)

    @property
    def reason(self) -> str | None:
        """Why the fit is undefined (REASONS), None when it is defined."""
        return None if self.fitted else REASONS.get(self.status, self.status)

    @property
    def fraction(self) -> np.ndarray:
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.n_trials > 0, self.n_fail / np.maximum(self.n_trials, 1), np.nan)

    def probability(self, x) -> np.ndarray:
        """P(failure | IM = x) of the curve reported: the lognormal fit, or for an EMPIRICAL curve the
        share of its thresholds at or below x (:func:`empirical_cdf`)."""
        if self.status == EMPIRICAL:
            return empirical_cdf(self.thresholds, x)
        return lognormal_cdf(x, self.median, self.beta)

    def count_at(self, x) -> dict | None:
        """The count behind P at IM = x of a curve on exact thresholds (None for the others):
        {"k": thresholds <= x, "n", "p": k / n, "ci": its Wilson interval (COUNT_CONFIDENCE),
        "method"} (:func:`threshold_count`)."""
        if self.thresholds is None:
            return None
        return threshold_count(self.thresholds, float(x))

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
        choice = d.get("choice")
        if choice is not None and not isinstance(choice, dict):
            raise InputError(f"fragility curve {key}: choice must be a table")
        status = str(d.get("status") or "")
        thresholds = arr("thresholds")
        if status == EMPIRICAL and (thresholds is None or not thresholds.size):
            raise InputError(f"fragility curve {key}: an empirical curve needs its thresholds")
        return cls(key, levels, n_fail, n_trials, num(d.get("median"), "median"), num(d.get("beta"), "beta"),
                   status, tuple(num(x, "median_ci") for x in d.get("median_ci") or (None, None)),
                   tuple(num(x, "beta_ci") for x in d.get("beta_ci") or (None, None)), arr("band_lo"), arr("band_hi"),
                   d.get("median_ci_note"), d.get("beta_ci_note"), dict(d.get("bootstrap_undefined") or {}),
                   profile, prof_note, thresholds, None if choice is None else dict(choice))

    def to_dict(self) -> dict:
        """JSON-ready; an undefined number is None with its reason beside it (``reason`` for the
        fit, its fitted P and bands; ``median_ci_note``, ``beta_ci_note`` for a band end;
        ``spread_reason`` when the median or beta is not identified (``identified`` False): then
        ``fitted`` is None too). A curve on exact thresholds adds ``thresholds`` and ``choice`` (which curve
        is reported and why: :func:`choose_uplift_curve`); the others have them None."""
        spread = self.spread
        prof = (float("nan"),) * 2 if self.beta_profile is None else self.beta_profile
        extra = {"thresholds": None if self.thresholds is None else [float(v) for v in self.thresholds],
                 "choice": self.choice}
        return {**extra, "outcome": self.outcome, "label": LABELS[self.outcome], "median": _finite(self.median),
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
EMPIRICAL = "empirical"
"""Status of the fixed-base uplift curve when the lognormal is not kept (:func:`choose_uplift_curve`):
the step CDF of the exact thresholds."""
COUNT_CONFIDENCE = 0.95
"""The two-sided confidence of the binomial (Wilson score) interval of a threshold count."""
TIE_RTOL = 1e-9
"""Thresholds equal to this relative tolerance are tied."""
UPLIFT_RULE = (
    "fixed-base uplift: with the exact thresholds x* of the n runs (a record's runs that share one x*, "
    "samples that do not move its uplift limit, count once) and k = #(x* <= x), the empirical P = k / n "
    "and its 95 % Wilson score interval are always computed; the lognormal fit (median exp(mean ln x*), "
    "beta std ln x*) is the curve reported only where (a) no threshold is tied (the largest number of equal "
    "thresholds, to a relative 1e-9, is 1) and (b) its P lies inside the Wilson interval of k / n at the "
    "design PGA and at every level run; otherwise the curve reported is the empirical one (the step CDF of "
    "x*, status 'empirical'), with the reason")
"""The rule of :func:`choose_uplift_curve`, in words (docs/fragility.md, the report's text)."""


def wilson_interval(k: float, n: float, confidence: float = COUNT_CONFIDENCE) -> tuple[float, float]:
    """The Wilson score interval (lo, hi) of ``k`` successes in ``n`` trials at two-sided
    ``confidence`` (full precision; (nan, nan) for n = 0). It always holds k / n; (0, ...) at k = 0.

    >>> [round(v, 4) for v in wilson_interval(6, 7)]
    [0.4869, 0.9743]
    >>> wilson_interval(0, 7)[0], round(wilson_interval(7, 7)[1], 12)
    (0.0, 1.0)
    """
    from scipy.stats import norm

    if n <= 0:
        return float("nan"), float("nan")
    z = float(norm.ppf(0.5 + confidence / 2))
    p = k / n
    den = 1 + z * z / n
    mid = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(max(p * (1 - p), 0.0) / n + z * z / (4 * n * n)) / den
    lo, hi = max(0.0, mid - half), min(1.0, mid + half)
    return min(lo, p), max(hi, p)          # rounding never leaves k / n outside


def empirical_cdf(thresholds, x) -> np.ndarray:
    """The share of ``thresholds`` at or below each x (the step CDF; right-continuous)."""
    t = np.sort(np.asarray(thresholds, dtype=float))
    x = np.asarray(x, dtype=float)
    if not t.size:
        return np.full(x.shape, np.nan)
    return np.searchsorted(t, x, side="right") / t.size


def threshold_count(thresholds, x: float, confidence: float = COUNT_CONFIDENCE) -> dict:
    """{"k", "n", "p", "ci", "method"}: how many of ``thresholds`` lie at or below ``x``, of how many,
    the share and its Wilson interval.

    >>> c = threshold_count([1.0, 2.0, 2.0, 2.0, 3.0], 2.0)
    >>> c["k"], c["n"], c["p"], c["method"]
    (4, 5, 0.8, 'Wilson score, 95 %')
    """
    t = np.asarray(thresholds, dtype=float)
    k, n = int(np.sum(t <= x)), int(t.size)
    lo, hi = wilson_interval(k, n, confidence)
    return {"k": k, "n": n, "p": k / n if n else None, "ci": [_finite(lo), _finite(hi)],
            "method": f"Wilson score, {confidence:.0%}".replace("%", " %")}


def distinct_thresholds(x) -> np.ndarray:
    """The thresholds the empirical curve counts, sorted, of the (records, samples) array ``x`` of exact
    thresholds (nan: a run not counted; inf: a record that never lifts it): each record's finite
    thresholds, those equal to TIE_RTOL (samples that do not move its uplift limit) counted once; the
    same value in two records counts twice (that is a tie).

    >>> distinct_thresholds(np.array([[2.0, 2.0, 2.0], [3.0, 3.5, np.nan]])).tolist()
    [2.0, 3.0, 3.5]
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    out = []
    for row in x:
        v = np.sort(row[np.isfinite(row)])
        keep = [float(a) for i, a in enumerate(v) if i == 0 or not math.isclose(a, v[i - 1], rel_tol=TIE_RTOL)]
        out.extend(keep)
    return np.sort(np.array(out, dtype=float))


def max_tie(thresholds) -> tuple[int, float]:
    """(the largest number of equal values to TIE_RTOL, that value) of ``thresholds`` ((0, nan) if none).

    >>> max_tie([2.7, 2.7, 2.9, 2.7 * (1 + 1e-12), 3.1])
    (3, 2.7)
    """
    t = np.sort(np.asarray(thresholds, dtype=float))
    best, value, run = 0, float("nan"), 0
    for i, a in enumerate(t):
        run = run + 1 if i and math.isclose(a, t[i - 1], rel_tol=TIE_RTOL) else 1
        if run > best:
            best, value = run, float(t[i - run + 1])
    return best, value


def _median_band(t: np.ndarray, confidence: float) -> tuple[tuple, str | None]:
    """The distribution-free band of the median of sorted ``t``: [t_(j), t_(n+1-j)] with the largest j
    such that P(Binomial(n, 1/2) < j) <= (1 - confidence) / 2 (coverage at least ``confidence``)."""
    from scipy.stats import binom

    n = t.size
    j = 0
    while j + 1 <= n // 2 and binom.cdf(j, n, 0.5) <= (1 - confidence) / 2:
        j += 1
    if j == 0:
        return (float("nan"),) * 2, (f"no band: {n} thresholds are too few for a {confidence:.0%} band of the "
                                     "median (order statistics)")
    return (float(t[j - 1]), float(t[n - j])), f"order statistics {j} and {n + 1 - j} of {n} thresholds"


def empirical_curve(cv: FragilityCurve, reason: str, choice: dict) -> FragilityCurve:
    """The EMPIRICAL curve of ``cv``'s thresholds: P the step CDF, the median the smallest threshold
    with P >= 1/2 (lower median), its band from the order statistics (:func:`_median_band`, at the
    study's confidence kept in ``choice``), the band at each level the Wilson interval of the count
    there; beta nan (none). ``reason``: why the lognormal was not kept."""
    t = np.sort(np.asarray(cv.thresholds, dtype=float))
    n = t.size
    med = float(t[(n + 1) // 2 - 1])
    mci, note = _median_band(t, float(choice.get("confidence", 0.90)))
    k = np.searchsorted(t, np.asarray(cv.levels, dtype=float), side="right")
    band = np.array([wilson_interval(int(kk), n) for kk in k]).reshape(-1, 2).T
    return FragilityCurve(cv.outcome, cv.levels, cv.n_fail, cv.n_trials, med, float("nan"), EMPIRICAL,
                          median_ci=mci, beta_ci=(float("nan"), float("nan")), band_lo=band[0], band_hi=band[1],
                          median_ci_note=note, beta_ci_note="an empirical curve has no beta",
                          beta_profile=None, beta_profile_note="an empirical curve has no beta",
                          thresholds=t, choice={**choice, "curve": EMPIRICAL, "reason": reason})


def choose_uplift_curve(cv: FragilityCurve, check=()) -> FragilityCurve:
    """The curve the fixed-base uplift reports (:data:`UPLIFT_RULE`): ``cv`` (status EXACT, with its
    ``thresholds``) when no threshold is tied and its lognormal P lies inside the Wilson interval of the
    count at every level of ``cv.levels`` and of ``check`` (the design PGA), else :func:`empirical_curve`
    with the reason. An EMPIRICAL curve, or one without thresholds, is returned as it is; an EXACT curve
    already checked at every level asked is too (a reader can call this with its own design level).

    >>> lv = np.array([2.0, 3.0])
    >>> t = np.array([2.717] * 4 + [2.6, 2.75, 3.0])
    >>> cv = FragilityCurve("full_contact_fixed", lv, np.zeros(2, int), np.full(2, 7), 2.78, 0.05, EXACT,
    ...                     thresholds=np.sort(t), choice={"checked_at": []})
    >>> c = choose_uplift_curve(cv, [2.8194])
    >>> c.status, c.choice["reason"].split(":")[0], float(c.probability(2.8194))
    ('empirical', '4 of 7 thresholds are tied at 2.717 m/s^2 (0.277 g)', 0.8571428571428571)
    """
    if cv.status != EXACT or cv.thresholds is None or not len(cv.thresholds):
        return cv
    choice = dict(cv.choice or {})
    t = np.asarray(cv.thresholds, dtype=float)
    at = sorted({float(v) for v in [*np.asarray(cv.levels, dtype=float), *np.atleast_1d(check)]
                 if v is not None and math.isfinite(float(v)) and float(v) > 0})
    done = set(choice.get("checked_at") or [])
    if choice.get("curve") == EXACT and all(v in done for v in at):
        return cv
    tie, tied = max_tie(t)
    choice.update(rule=UPLIFT_RULE, n=int(t.size), max_tie=tie, tied_value=_finite(tied) if tie > 1 else None,
                  lognormal={"median": _finite(cv.median), "beta": _finite(cv.beta)})
    if tie > 1:
        where = f"{tied:.4g} m/s^2 ({tied / G:.3f} g)"
        return empirical_curve(cv, (f"all {tie} thresholds are equal, {where}: a deterministic step" if tie == t.size
                                    else f"{tie} of {t.size} thresholds are tied at {where}: a lognormal has no "
                                    "point mass to hold them"), choice)
    bad = []
    for v in at:
        c = threshold_count(t, v)
        p = float(lognormal_cdf(v, cv.median, cv.beta))
        if not (c["ci"][0] <= p <= c["ci"][1]):
            bad.append((v, p, c))
    if bad:
        v, p, c = bad[0]
        return empirical_curve(cv, f"the lognormal gives P {p:.3f} at {v:.4g} m/s^2 ({v / G:.3f} g), outside the "
                               f"95 % Wilson interval {c['ci'][0]:.3f}-{c['ci'][1]:.3f} of the count there, "
                               f"{c['k']} of {c['n']} thresholds" + (f" ({len(bad)} levels so)" if len(bad) > 1 else ""),
                               choice)
    from dataclasses import replace

    return replace(cv, choice={**choice, "curve": EXACT, "reason": None, "checked_at": at})


def _finite(v):
    """v as a float, or None when it is not finite (JSON: inf has no spelling; null)."""
    return float(v) if v is not None and np.isfinite(v) else None
