"""The isolator design verified by time histories, on several record sets, at two levels, with a reserve
(MODEL.md sections 4, 7, 8, 9). SI units throughout.

The spectral search (design.search) sizes and prices every candidate; here the candidates are taken
cheapest first and each is run, the top plate alone (time_history.simulate, Coulomb: exact while the
statue stays in full contact, which a passing device must ensure), every record at the friction bounds
mu_low and mu_high (EN 15129 / ASCE 7-16 17.2.8.4 bound analyses: the lower bound normally gives the
travel, the upper the force; each demand takes the bound that governs it), on:

    the design set        the run's >= 7 records matched to the design target
    further sets          ``extra_sets``: independent code-compliant sets of other seeds (at least three
                          in the pipeline): the device is chosen on the design set and must hold on every
                          set; where a set asks more travel the opening is cut for it (the margin is
                          raised until every set holds), so no set's records decide alone
    the collapse level    the design set scaled by Se_SLC(T) / Se(T) at the device's period (the SLC
                          spectrum over the design one, hazard/levels.py; x gamma_x 1.2 on EC8 sites)
    the reserve           every design record scaled to the PGA where half of them overturn the fixed-base
                          statue (the geometric mean of each record's lowest overturning PGA, reserve.py;
                          capped at RESERVE_LEVEL x the design PGA): at most half may pass the capacity
                          there, so the device's failure median lies at or right of the fixed base's
                          overturning median (it never makes the statue worse than no device)

The demand of a set is the MEAN over its records with at least N_MIN = 7 (NTC 2018 7.3.5, EN 1998-1
4.3.3.4.3), else the most unfavourable record; the larger of the two bounds. The travel the grooves
must give is the largest of (checks.py):

    design      1.5 u_set + mu_high R_hat, over every set
    SLC         1.25 u_SLC + mu_high R_hat
    reserve     1.05 x the median over the records of u_i(at the fixed base's overturning median) + mu_high R_hat

and each candidate's opening is re-cut for it (design.resized): its plate, mass and price grow, and
every spectral check is evaluated again. Time-history checks (required): the felt acceleration (the
statistic of the peak |absolute plate acceleration| on every set, against the statue's uplift limit:
replaces the spectral Se(T) <= a_lim, which stays advisory), the three travels against the capacity,
and the most loaded ball at SLC with the records' felt acceleration. The cheapest candidate that passes
is chosen (ties within design.COST_TOLERANCE: the larger least margin). The candidates are taken in the order
of their price re-cut for the screen's estimate of the travel (_Screen), and the search stops once every
candidate left has a spectral price (a lower bound: the verified cut can only be larger) above the best
verified one, or an estimated price more than SCREEN_SLACK above it, or after MAX_VERIFIED. Friction bounds are rounded outward to a grid of MU_STEP (mu_low down, mu_high up) so that devices
of one period share their runs.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard.code_spectra import ec8
>>> from statue2model.hazard import motions
>>> statue = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
>>> recs = [motions.synthetic_record(duration=10.0, pga=0.5, seed=s) for s in (1, 2)]
>>> d = verify(statue, records=recs, mu=0.0073, spectrum=ec8(0.05 * 9.80665, "A"), thickness=0.03,
...            R_grid=(0.4, 0.8), balls=(0.02,), surfaces="beech", layouts="ring4")
>>> d.passed, d.verification["statistic"], sorted(d.th_margins)[:3]
(True, 'max', ['acceleration', 'bearing', 'bearing_slc'])
>>> all(m >= 1 for m in d.th_margins.values() if m is not None), d.what_would_pass is None
(True, True)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..compute.collector import collector_paused
from ..errors import InputError
from ..hazard.matching import N_MIN
from ..hazard.motions import GroundMotion
from . import checks as C
from .checks import DISPLACEMENT_MARGIN, RESERVE_LEVEL, SLC_MARGIN, Check, travel_need
from .design import BALLS, COST_TOLERANCE, CRITERION, R_GRID, SHOWN_FAILING, SHOWN_PASSING, Candidate, \
    _design_from, failure_text, resized, search, what_would_pass
from .device import G, Isolator

REPLACED = ("acceleration",)
"""Spectral checks the time histories replace (the felt acceleration; it stays advisory)."""
TH_KEYS = ("th_acceleration", "th_travel", "th_travel_slc", "reserve", "th_ball_load_slc")
TOL = 1e-9
DT_OUT = 1.0
"""s, the plate runs' output step: only their exact peaks are used."""
MU_STEP = 1.05
"""Friction bounds are rounded outward to powers of 1.05."""
MAX_VERIFIED = 36
"""Candidates verified at most (cheapest first) before the nearest is reported."""
BATCH = 6
SCREEN_CLEARANCE = 0.02
"""The screen's travel estimate is raised 2 % before the candidates are re-cut and priced."""
SCREEN_SLACK = 0.10
"""The screen's price may overstate the verified one (the screen's travel is estimated): the search goes on
while a candidate's estimated price is within COST_TOLERANCE + SCREEN_SLACK of the best verified one and its
spectral price (a true lower bound) within COST_TOLERANCE."""
SCREEN_PERIODS = 10
SCREEN_MUS = 9
DEFINITIONS = {
    "travel": f"capacity / max over the sets of ({DISPLACEMENT_MARGIN:g} x u + mu_high R_hat), u the set's statistic "
              "of the plate's peak travel relative to the ground (the larger of the two friction bounds)",
    "acceleration": "a_lim / max over the sets of the statistic of the peak absolute plate acceleration (what the "
                    "statue feels)",
    "bearing": "the surface's long-term capacity per ball / W / n",
    "travel_slc": f"capacity / ({SLC_MARGIN:g} x u_SLC + mu_high R_hat), u_SLC the statistic over the design set "
                  "scaled to the collapse level",
    "bearing_slc": "the short-term capacity per ball / the most loaded ball at SLC (W / n + M a l / spread)",
    "reserve": f"capacity / ({C.RESERVE_MARGIN:g} x the median over the design records of the travel at the fixed "
               "base's overturning median PGA + mu_high R_hat)",
}


def friction_bounds(mu: float) -> tuple[float, float]:
    """(mu_low, mu_high) by default: ``mu`` times Table 25's spread (isolator/friction.py friction_bounds).

    >>> [round(x, 4) for x in friction_bounds(0.0073)]
    [0.0039, 0.0108]
    """
    from .friction import friction_bounds as bounds

    lo, hi, _ = bounds(mu)
    return lo, hi


def _outward(lo: float, hi: float) -> tuple[float, float]:
    k = math.log(MU_STEP)
    q_lo = MU_STEP ** math.floor(math.log(lo) / k + 1e-9) if lo > 0 else 0.0
    q_hi = MU_STEP ** math.ceil(math.log(hi) / k - 1e-9) if hi > 0 else 0.0
    return float(f"{q_lo:.6g}"), float(f"{q_hi:.6g}")


@dataclass(frozen=True)
class RecordSet:
    """One set the device is verified on: ``name``, its ``records`` (GroundMotion), ``seeds`` and what the set
    is (``info``: rules_met, band, band_reason, ...)."""

    name: str
    records: tuple
    seeds: str = ""
    info: dict | None = None


@dataclass(frozen=True)
class Peaks:
    """Peaks of the top plate of one period at one friction pair, per motion: travel (m) and felt (m/s^2)
    at mu_low and mu_high."""

    travel_low: np.ndarray
    travel_high: np.ndarray
    felt_low: np.ndarray
    felt_high: np.ndarray

    def take(self, sl) -> "Peaks":
        return Peaks(self.travel_low[sl], self.travel_high[sl], self.felt_low[sl], self.felt_high[sl])

    def stat(self, statistic: str) -> tuple[float, float]:
        f = np.mean if statistic == "mean" else np.max
        return (max(float(f(self.travel_low)), float(f(self.travel_high))),
                max(float(f(self.felt_low)), float(f(self.felt_high))))

    @property
    def per_record_travel(self) -> np.ndarray:
        return np.maximum(self.travel_low, self.travel_high)


def _peaks(task) -> list:
    from .time_history import simulate

    items, g = task
    out = []
    for R_hat, lo, hi, motions in items:
        res = []
        for mu in ((lo,) if lo == hi else (lo, hi)):
            iso = Isolator(R=R_hat / 2 + 0.01, r=0.01, M=1.0, mu=mu, g=g)
            runs = [simulate(iso, m, dt_out=DT_OUT) for m in motions]
            res.append((np.array([x.u_max for x in runs]), np.array([x.acc_abs_max for x in runs])))
        res = res * (3 - len(res))
        out.append(Peaks(res[0][0], res[1][0], res[0][1], res[1][1]))
    return out


def _statistic(n: int) -> str:
    return "mean" if n >= N_MIN else "max"


@dataclass(frozen=True)
class Demands:
    """Everything the time histories say of one (R_hat, mu_low, mu_high)."""

    sets: tuple          # ((name, travel, felt), ...)
    slc_travel: float
    slc_felt: float
    reserve_travel: float
    per_record_reserve: tuple


class _Runner:
    """Plate runs, cached by (R_hat, mu_low, mu_high), run in batches on the executor."""

    def __init__(self, sets, reserve_scales, slc_ratio, g, executor):
        self.sets, self.reserve_scales, self.slc_ratio, self.g, self.ex = sets, reserve_scales, slc_ratio, g, executor
        self.cache: dict = {}
        self.runs = 0

    def motions(self, R_hat):
        T = 2 * math.pi * math.sqrt(R_hat / self.g)
        design = list(self.sets[0].records)
        out = [m for s in self.sets for m in s.records]
        s_slc = self.slc_ratio(T)
        out += [m.scaled(s_slc) for m in design]
        if self.reserve_scales is not None:
            out += [m.scaled(s) for m, s in zip(design, self.reserve_scales)]
        return out

    def fill(self, keys) -> None:
        todo = [k for k in dict.fromkeys(keys) if k not in self.cache]
        if not todo:
            return
        items = [(R_hat, lo, hi, self.motions(R_hat)) for R_hat, lo, hi in todo]
        self.runs += 2 * sum(len(it[3]) for it in items)
        if self.ex is None or getattr(self.ex, "workers", 1) < 2 or len(items) < 2:
            peaks = _peaks((items, self.g))
        else:
            peaks = [p for part in self.ex.map(_peaks, [([it], self.g) for it in items],
                                               desc="isolator: time histories") for p in part]
        for k, p in zip(todo, peaks):
            self.cache[k] = self._demands(p)

    def _demands(self, p: Peaks) -> Demands:
        i = 0
        sets = []
        for s in self.sets:
            n = len(s.records)
            u, a = p.take(slice(i, i + n)).stat(_statistic(n))
            sets.append((s.name, u, a))
            i += n
        n0 = len(self.sets[0].records)
        u_slc, a_slc = p.take(slice(i, i + n0)).stat(_statistic(n0))
        i += n0
        res, per = 0.0, ()
        if self.reserve_scales is not None:
            r = p.take(slice(i, i + n0)).per_record_travel
            res, per = float(np.median(r)), tuple(float(x) for x in r)
        return Demands(tuple(sets), u_slc, a_slc, res, per)

    def get(self, key) -> Demands:
        self.fill([key])
        return self.cache[key]


def _key(c: Candidate) -> tuple:
    lo, hi = _outward(c.mu_low, c.mu_high)
    return (round(c.R_hat, 10), lo, hi)


def _th(c: Candidate, dem: Demands, key, reserve_on: bool, a_lim: float, why_lim: str, stat: str) -> tuple:
    """(checks, margins, floor) of one candidate under its demands."""
    R_hat, lo, hi = key
    need_sets = [(name, travel_need(u, hi, R_hat), u, a) for name, u, a in dem.sets]
    need_d = max(n for _, n, _, _ in need_sets)
    felt = max(a for *_, a in need_sets)
    need_slc = travel_need(dem.slc_travel, hi, R_hat, SLC_MARGIN)
    need_res = travel_need(dem.reserve_travel, hi, R_hat, C.RESERVE_MARGIN) if reserve_on else 0.0
    floor = max(need_d, need_slc, need_res)
    return need_sets, need_d, felt, need_slc, need_res, floor


def _th_checks(c: Candidate, dem: Demands, key, reserve_on, a_lim, why_lim, stat) -> tuple[tuple, dict]:
    R_hat, lo, hi = key
    need_sets, need_d, felt, need_slc, need_res, _ = _th(c, dem, key, reserve_on, a_lim, why_lim, stat)
    cap = c.capacity
    worst = max(need_sets, key=lambda x: x[1])
    dev = c.device
    from .layout import LAYOUTS

    spread = LAYOUTS[dev.layout].spread(dev.spacing)
    P = c.W / dev.n
    P_dyn = C.dynamic_ball_load(c.W, dev.n, c.M, dem.slc_felt, c.lever, spread)
    checks = [
        C.acceleration_check(felt, a_lim, f"peak absolute plate acceleration {felt:.4f} m/s^2 (the {stat} over each "
                             f"set's records, the largest of {len(need_sets)} sets, mu {lo:g}/{hi:g}) vs {why_lim}",
                             key="th_acceleration",
                             name="time-history felt acceleration below the uplift limit"),
        Check("time-history travel within the capacity (every set)", need_d <= cap * (1 + TOL), need_d, cap,
              f"{DISPLACEMENT_MARGIN:g} x {worst[2]:.4f} m (set {worst[0]}) + mu_high R_hat {hi * R_hat:.4f} m = "
              f"{need_d:.4f} m vs capacity {cap:.4f} m", unit="m", key="th_travel"),
        Check("time-history travel at the collapse level (SLC)", need_slc <= cap * (1 + TOL), need_slc, cap,
              f"{SLC_MARGIN:g} x {dem.slc_travel:.4f} m + mu_high R_hat = {need_slc:.4f} m vs capacity {cap:.4f} m",
              unit="m", key="th_travel_slc", level="SLC"),
        C.ball_load_check(P_dyn, c.ball_capacity_short, f"W / n + M a l / spread = {P:.0f} + {P_dyn - P:.0f} N (felt "
                          f"{dem.slc_felt:.3f} m/s^2 at SLC) vs the short-term {c.ball_capacity_short:.0f} N",
                          level="SLC", key="th_ball_load_slc"),
    ]
    if reserve_on:
        checks.append(Check("travel reserve up to where the statue overturns without the device",
                            need_res <= cap * (1 + TOL), need_res, cap,
                            f"{C.RESERVE_MARGIN:g} x the median over the design records of the travel at the PGA "
                            f"where half of them overturn the fixed-base statue {dem.reserve_travel:.4f} m + mu_high "
                            f"R_hat = {need_res:.4f} m vs capacity {cap:.4f} m",
                            unit="m", key="reserve", level="reserve"))
    inf = math.inf
    margins = {"travel": cap / need_d if need_d > 0 else inf, "acceleration": a_lim / felt if felt > 0 else inf,
               "bearing": c.ball_capacity.load / P if P > 0 else inf,
               "travel_slc": cap / need_slc if need_slc > 0 else inf,
               "bearing_slc": c.ball_capacity_short / P_dyn if P_dyn > 0 else inf,
               "reserve": (cap / need_res if need_res > 0 else inf) if reserve_on else None}
    return tuple(checks), margins


@dataclass(frozen=True)
class Verified:
    candidate: Candidate
    checks: tuple
    margins: dict
    key: tuple

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks if c.required)

    @property
    def cost(self) -> float:
        return self.candidate.cost


def _verify_one(c: Candidate, runner: _Runner, reserve_on, stat) -> Verified:
    cx = c.cx
    c2, key = c, _key(c)
    for _ in range(3):                 # the plate's mass, so its friction, follows the travel: until it settles
        dem = runner.get(key)
        *_, floor = _th(c, dem, key, reserve_on, cx.a_lim, cx.why_lim, stat)
        c2 = resized(c, floor)
        if _key(c2) == key:
            break
        key = _key(c2)
    th, margins = _th_checks(c2, dem, key, reserve_on, cx.a_lim, cx.why_lim, stat)
    spectral = tuple(k._replace(required=False, why=k.why + " (advisory: the time histories decide)")
                     if k.key in REPLACED else k for k in c2.checks)
    return Verified(c2, spectral + th, margins, key)


def _closeness_spectral(c) -> tuple:
    return (sum(1 for k in c.checks if k.required and not k.passed), max(k.ratio for k in c.checks if k.required))


class _Screen:
    """The design records' plate peaks on a grid of periods and friction coefficients, from which every
    candidate's travel floor and felt acceleration are estimated (bilinear in T and log mu) before the
    exact runs. A Coulomb plate under a record scaled by s with friction mu travels s times what it does
    under the record with friction mu / s (the equation of motion scales exactly), so the collapse level
    and the reserve come from the same grid."""

    def __init__(self, records, pool, scales, slc_ratio, stat, g, executor):
        Ts = [c.T for c in pool]
        lo = min(c.mu_low for c in pool)
        hi = max(c.mu_high for c in pool)
        s_max = max([1.0, C.GAMMA_X] + ([max(scales)] if scales else []) + [slc_ratio(t) for t in (min(Ts), max(Ts))])
        self.T = np.linspace(min(Ts), max(Ts), SCREEN_PERIODS) if max(Ts) > min(Ts) else np.array([min(Ts)])
        self.mu = np.geomspace(max(lo / (1.2 * s_max), 1e-5), max(hi, 1.01e-5) * 1.01, SCREEN_MUS)
        self.scales, self.slc_ratio, self.stat, self.g = scales, slc_ratio, stat, g
        items = []
        for T in self.T:
            R_hat = g * T * T / (4 * math.pi ** 2)
            for mu in self.mu:
                items.append((R_hat, float(mu), float(mu), list(records)))
        if executor is None or getattr(executor, "workers", 1) < 2:
            peaks = _peaks((items, g))
        else:
            from ..compute.executors import chunks

            blocks = chunks(len(items), executor, per_worker=2, min_chunk=4)
            peaks = [p for part in executor.map(_peaks, [([items[i] for i in b], g) for b in blocks],
                                                desc="isolator: screening") for p in part]
        n = len(records)
        self.u = np.array([p.travel_low for p in peaks]).reshape(len(self.T), len(self.mu), n)
        self.a = np.array([p.felt_low for p in peaks]).reshape(len(self.T), len(self.mu), n)
        self._log_mu, self._j = np.log(self.mu), np.arange(len(self.mu))
        self._u_record = [self.u[:, :, i].tolist() for i in range(n)]     # per record, as Python floats

    def _x(self, T) -> tuple:
        """(i0, i1, fx): where T falls on the grid of periods."""
        if len(self.T) < 2:
            return 0, 0, 0.0
        x = np.interp(T, self.T, np.arange(len(self.T)))
        i0 = int(min(math.floor(x), len(self.T) - 2))
        return i0, min(i0 + 1, len(self.T) - 1), x - i0

    def _at(self, arr, T, mu, at_T=None):
        """Per-record values at (T, mu), bilinear in T and log mu (clamped to the grid); ``at_T``:
        ``self._x(T)`` when known. ``arr`` may also be one record's grid (nested lists): one value."""
        i0, i1, fx = self._x(T) if at_T is None else at_T
        y = np.interp(math.log(max(mu, 1e-12)), self._log_mu, self._j)
        j0 = int(min(math.floor(y), len(self.mu) - 2))
        fy = y - j0
        if isinstance(arr, list):
            fx, fy = float(fx), float(fy)     # Python floats on Python floats (the values are the same)
        return ((1 - fx) * (1 - fy) * arr[i0][j0] + fx * (1 - fy) * arr[i1][j0]
                + (1 - fx) * fy * arr[i0][j0 + 1] + fx * fy * arr[i1][j0 + 1])

    def floor(self, c) -> tuple[float, float]:
        """(travel floor m, felt m/s^2) estimated for candidate ``c``."""
        T, lo, hi, R_hat = c.T, c.mu_low, c.mu_high, c.R_hat
        f = np.mean if self.stat == "mean" else np.max
        x = self._x(T)
        u = max(f(self._at(self.u, T, m, x)) for m in (lo, hi))
        a = max(f(self._at(self.a, T, m, x)) for m in (lo, hi))
        s = self.slc_ratio(T)
        u_slc = max(f(s * self._at(self.u, T, m / s, x)) for m in (lo, hi))
        need = max(travel_need(u, hi, R_hat), travel_need(u_slc, hi, R_hat, SLC_MARGIN))
        if self.scales:
            per = [max(sc * self._at(self._u_record[i], T, m / sc, x) for m in (lo, hi))
                   for i, sc in enumerate(self.scales)]
            need = max(need, travel_need(float(np.median(per)), hi, R_hat, C.RESERVE_MARGIN))
        return need, a


def _check_inputs(records, mu, mu_low, mu_high):
    if not records or not all(isinstance(m, GroundMotion) for m in records):
        raise InputError("the verification needs at least one design record (GroundMotion)")
    if any(m.kind == "none" or not m.pga > 0 for m in records):
        raise InputError("every design record must be a ground motion (not zero)")
    for name, v in (("mu_low", mu_low), ("mu_high", mu_high)):
        if v is not None and not (isinstance(v, (int, float)) and math.isfinite(v) and 0 <= v < 0.5):
            raise InputError(f"friction bound {name} must be in [0, 0.5), got {v!r}")
    if mu is not None and mu_low is not None and mu_high is not None and not mu_low <= mu <= mu_high:
        raise InputError(f"friction bounds must hold the nominal mu: mu_low {mu_low:g} <= mu {mu:g} <= mu_high "
                         f"{mu_high:g}")


def verify(statue, *, records, mu: float | None = None, mu_low: float | None = None, mu_high: float | None = None,
           a_lim: float | None = None, a_lim_why: str | None = None, records_info: dict | None = None,
           extra_sets=(), fixed_model=None, design_pga: float | None = None, reserve_level: float = RESERVE_LEVEL,
           rtol: float = 1e-7, balls=BALLS, R_grid=R_GRID, g: float = G, executor=None, spectrum=None,
           motion=None, slc=None, slc_why: str | None = None, **kwargs):
    """The cheapest isolator for ``statue`` (RockingParams) that passes every spectral and time-history
    check (module docstring) on the design set ``records`` and the ``extra_sets`` (RecordSet), at the
    collapse level ``slc`` (a spectrum; None: the design one x gamma_x) and, with ``fixed_model`` (the
    fixed-base RockingModel), with a reserve up to where the statue overturns on a fixed base (capped at
    ``reserve_level`` x ``design_pga``, m/s^2; None: the records' mean PGA). ``mu`` None: each ball/surface
    pair's measured law (bearing.py). The keyword arguments go to design.search."""
    records = list(records)
    if mu is not None and (mu_low is None or mu_high is None):
        lo, hi = friction_bounds(mu)
        mu_low = lo if mu_low is None else mu_low
        mu_high = hi if mu_high is None else mu_high
    _check_inputs(records, mu, mu_low, mu_high)
    srch = search(statue, spectrum=spectrum, motion=motion, slc=slc, slc_why=slc_why, mu=mu, mu_low=mu_low,
                  mu_high=mu_high, a_lim=a_lim, a_lim_why=a_lim_why, balls=balls, R_grid=R_grid, g=g, **kwargs)
    cx = srch.cx
    info = dict(records_info or {})
    sets = [RecordSet("design", tuple(records), info.get("seeds", ""), info)] + [
        s if isinstance(s, RecordSet) else RecordSet(f"extra {i + 1}", tuple(s)) for i, s in enumerate(extra_sets)]
    n0 = len(records)
    stat = _statistic(n0)
    pga0 = design_pga if design_pga is not None else float(np.mean([m.pga for m in records]))
    reserve, a50, scales = None, None, None
    if fixed_model is not None:
        from .reserve import overturning_scales

        caps = [reserve_level * pga0 / m.pga for m in records]
        reserve = overturning_scales(fixed_model, records, caps, rtol=rtol, executor=executor)
        thresholds = np.array([r.scale * m.pga for r, m in zip(reserve, records)])
        a50 = min(float(np.exp(np.mean(np.log(thresholds)))), reserve_level * pga0)
        scales = [a50 / m.pga for m in records]
    if spectrum is not None:
        hi_sp = slc

        def slc_ratio(T):
            if hi_sp is None:
                return C.GAMMA_X
            return float(hi_sp.Se(T)) / float(spectrum.Se(T))
    else:
        def slc_ratio(T):
            return C.GAMMA_X
    runner = _Runner(sets, scales, slc_ratio, g, executor)
    reserve_on = reserve is not None
    pool = [c for c in srch.candidates if c.passes(ignore=REPLACED + ("fuse_layout",))]
    screen = _Screen(records, pool, scales, slc_ratio, stat, g, executor) if pool else None
    estimated = []                      # (the re-cut candidate, its spectral price: a lower bound of the verified)
    with collector_paused():
        for c in pool:
            floor, felt = screen.floor(c)
            c2 = resized(c, floor * (1 + SCREEN_CLEARANCE))
            if felt <= cx.a_lim and c2.passes(ignore=REPLACED):
                estimated.append((c2, c.cost))
    estimated.sort(key=lambda e: e[0].cost)
    low = [math.inf] * (len(estimated) + 1)     # the least spectral price of the candidates not yet verified
    for k in range(len(estimated) - 1, -1, -1):
        low[k] = min(low[k + 1], estimated[k][1])
    verified: list[Verified] = []
    best = None
    i = 0
    while i < len(estimated) and len(verified) < MAX_VERIFIED:
        if best is not None and (low[i] > best.cost * (1 + COST_TOLERANCE)
                                 or estimated[i][0].cost > best.cost * (1 + COST_TOLERANCE + SCREEN_SLACK)):
            break
        batch = [c for c, _ in estimated[i:i + BATCH]]
        i += len(batch)
        runner.fill([_key(c) for c in batch])
        for c in batch:
            v = _verify_one(c, runner, reserve_on, stat)
            verified.append(v)
            if v.passed and (best is None or _better(v, best)):
                best = v
    if not verified:                    # nothing passes even the estimate: verify the nearest few as they are
        near = sorted((c for c in pool if c.makeable), key=lambda c: c.cost)[:BATCH] or \
            sorted(srch.candidates, key=_closeness_spectral)[:1]
        runner.fill([_key(c) for c in near])
        verified = [_verify_one(c, runner, reserve_on, stat) for c in near]
    n_pass = sum(v.passed for v in verified)
    if best is not None:
        chosen, failure, wwp = best, None, None
    else:
        made = [v for v in verified if v.candidate.makeable]
        # the nearest verified device that can be made; when none can, the nearest verified one all the same (it
        # says why: the note and nearest_makeable false), never an undersized one the time histories did not cut
        chosen = min(made or verified, key=lambda v: (sum(1 for k in v.checks if k.required and not k.passed),
                                                      max(k.ratio for k in v.checks if k.required), v.cost))
        bad = {k.key for k in chosen.checks if k.required and not k.passed}
        failure = failure_text(chosen.checks) + (f" [nearest of {len(verified)} candidates verified, "
                                                 f"{len(srch.candidates)} tried; {srch.ranges}]")
        wwp = what_would_pass(chosen.candidate, srch.candidates, reasons=bad,
                              felt=min(runner.get(v.key).sets[0][2] for v in verified), checks=chosen.checks)
    dem = runner.get(chosen.key)
    R_hat, lo, hi = chosen.key
    tail_info = None
    if reserve is not None:
        from .reserve import capacity_scales, tail

        caps = [reserve_level * pga0 / m.pga for m in records]
        dev_s = capacity_scales(R_hat, lo, hi, records, chosen.candidate.capacity, hi * R_hat, caps, g)
        tail_info = tail([r.scale * m.pga for r, m in zip(reserve, records)],
                         [s_ * m.pga for s_, m in zip(dev_s, records)])
    set_rows = []
    for s, (name, u, a) in zip(sets, dem.sets):
        si = s.info or {}
        set_rows.append({"name": name, "seeds": s.seeds or si.get("seeds", ""), "records": len(s.records),
                         "travel": u, "felt": a, "need": travel_need(u, hi, R_hat),
                         "rules_met": si.get("rules_met"), "band_s": si.get("band_s"),
                         "band_reason": si.get("band_reason")})
    T = 2 * math.pi * math.sqrt(R_hat / g)
    verification = {
        "margins": {k: _fin(v) for k, v in chosen.margins.items()}, "passed": chosen.passed,
        "definitions": DEFINITIONS, "criterion": CRITERION, "statistic": stat,
        "statistic_rule": f"the mean over a set's records with at least {N_MIN} (NTC 2018 7.3.5, EN 1998-1 "
                          "4.3.3.4.3), else the most unfavourable record",
        "records": {"count": n0, "source": info.get("source", "given"), "rules_met": info.get("rules_met"),
                    "labels": [m.label for m in records],
                    **{k: v for k, v in info.items() if k not in ("source", "rules_met")}},
        "sets": set_rows,
        "mu": chosen.candidate.mu, "mu_low": lo, "mu_high": hi, "friction": chosen.candidate.friction.to_dict(),
        "mu_rule": "every record at both friction bounds, rounded outward to powers of 1.05 (EN 15129 / ASCE 7-16 "
                   "17.2.8.4 bound analyses); each demand takes the bound that governs it",
        "a_lim": cx.a_lim, "a_lim_why": cx.why_lim,
        "model": "top plate alone, Coulomb (exact while the statue stays in full contact)",
        "slc": {"rule": cx.slc_why, "scale": slc_ratio(T), "travel": dem.slc_travel, "felt": dem.slc_felt,
                "need": travel_need(dem.slc_travel, hi, R_hat, SLC_MARGIN)},
        "reserve": None if reserve is None else {
            "level": reserve_level, "design_pga": pga0, "pga": a50, "pga_over_design": a50 / pga0,
            "thresholds": [r.scale * m.pga for r, m in zip(reserve, records)],
            "overturns": [r.overturns for r in reserve],
            "travel_per_record": list(dem.per_record_reserve), "travel": dem.reserve_travel,
            "need": travel_need(dem.reserve_travel, hi, R_hat, C.RESERVE_MARGIN), "margin": C.RESERVE_MARGIN,
            "rule": "the PGA where the fixed-base statue overturns in half the design records (the geometric mean of "
                    "each record's lowest overturning PGA, isolator/reserve.py; at most "
                    f"{reserve_level:g} x the design PGA): every record scaled to it, the median travel + mu_high "
                    "R_hat must fit, so that at most half the records exceed the capacity where half overturn the "
                    "statue without the device: the device's failure median lies at or right of the fixed base's "
                    "overturning median",
            "tail": tail_info,
            "tail_rule": "each design record's lowest PGA at which the device passes its capacity (either friction "
                         "bound, mu_high R_hat off centre) against the lowest at which the statue overturns on a fixed "
                         "base: the empirical curves, compared rank by rank"},
        "candidates_verified": len(verified), "candidates_passing": n_pass, "runs": runner.runs,
        "search": "cheapest first by the price re-cut for the screen's travel estimate; stops once every "
                  f"candidate left has a spectral price more than {COST_TOLERANCE:.0%} above the best verified one "
                  f"or an estimated price more than {COST_TOLERANCE + SCREEN_SLACK:.0%} above it, or after "
                  f"{MAX_VERIFIED} verified",
    }
    ranked = sorted(verified, key=lambda v: (not v.passed, v.cost))
    table = {"criterion": CRITERION, "tried": len(srch.candidates), "verified": len(verified), "passing": n_pass,
             "ranges": srch.ranges,
             "order": "the chosen device, then the verified candidates that can be made (passing first, cheapest "
                      "first), then candidates not verified that can be made, cheapest first",
             "checks": [{"key": k.key, "name": k.name, "unit": k.unit, "required": k.required, "level": k.level}
                        for k in chosen.checks],
             "check_columns": ["value", "limit", "ratio", "passed"], "margin_definitions": DEFINITIONS,
             "rows": [_row(v) for v in [chosen] + [v for v in ranked if v is not chosen and v.candidate.makeable]
                      [:SHOWN_PASSING]]}
    not_run = sorted((c for c in srch.candidates if c.makeable and not c.passes(ignore=REPLACED)),
                     key=lambda c: c.cost)[:SHOWN_FAILING]
    table["rows"] += [c.row() for c in not_run]
    table["shown"] = len(table["rows"])
    m = chosen.margins
    notes = [f"verified on {len(sets)} record sets of {n0} records at mu {lo:.4g} and {hi:.4g}: {n_pass} of "
             f"{len(verified)} candidates verified pass; margins travel {m['travel']:.2f}, acceleration "
             f"{m['acceleration']:.2f}, bearing {m['bearing']:.2f}, SLC travel {m['travel_slc']:.2f}"
             + (f", reserve {m['reserve']:.2f}" if m.get("reserve") is not None else "")]
    if wwp:
        notes.append(wwp["text"])
    return _design_from(chosen.candidate, statue, inputs=srch.inputs, tried=len(srch.candidates), candidates=table,
                        failure=failure, notes=tuple(notes), what_would_pass=wwp, evaluated=srch.candidates,
                        checks=chosen.checks, verification=verification)


def _better(a: Verified, b: Verified) -> bool:
    cheapest = min(a.cost, b.cost)
    ta, tb = a.cost <= cheapest * (1 + COST_TOLERANCE), b.cost <= cheapest * (1 + COST_TOLERANCE)
    if ta and tb:
        return _least(a) > _least(b)
    return a.cost < b.cost


def _least(v: Verified) -> float:
    return min((1 / k.ratio if k.ratio > 0 else math.inf) for k in v.checks if k.required)


def _fin(x) -> float | None:
    return float(f"{x:.6g}") if isinstance(x, (int, float)) and math.isfinite(x) else None


def _row(v: Verified) -> dict:
    row = v.candidate.row()
    row["checks"] = [[_fin(c.value), _fin(c.limit), _fin(c.ratio), c.passed] for c in v.checks]
    row.update(passed=v.passed, margins={k: _fin(x) for k, x in v.margins.items()},
               worst_ratio=_fin(max(c.ratio for c in v.checks if c.required)))
    return row
