"""Sliding of a rigid body on its support: Coulomb friction, static and kinetic (MODEL.md section 10).

Newmark's rigid-plastic sliding block. The body moves with its support (it sticks) while the
support's acceleration |a_g| <= mu_s g. It slides once |a_g| > mu_s g; its displacement relative to
the support, u (m, positive toward +x), then obeys

    u'' = -a_g(t) - s mu_k g,        s = sign(u')   (friction opposes the relative velocity)

and it sticks again where u' returns to 0 with |a_g| <= mu_s g (else it slides on, the other way).
The onset's direction is s = -sign(a_g): the support runs from under the body.

On a record (linear between its samples) the integration is exact: in a step a_g is linear, u' a
quadratic and u a cubic of the time; a stop is the root of the quadratic, an onset the instant
|a_g| reaches mu_s g, both found in closed form; after the motion the body slides to rest at the
deceleration mu_k g. No time step and no tolerance.

The regime before lift-off, for a rigid planar block of half-width b and half-height h (the rocking
parameters along the direction): under a ground acceleration that grows from rest, it slides first
where mu_s g < g b / h (:func:`slides_first`), and while it slides the friction force mu_k m g cannot
lift it when mu_k < b / h. Slide-rock (a sliding body that starts to rock, Shenton 1996: possible at
high accelerations even where mu > b / h, through impacts and vertical motion) is not modelled here.

Example: a 0.3 g rectangular pulse of 0.5 s under a body with mu_s 0.25, mu_k 0.2
-------
>>> from statue2model.hazard import motions
>>> r = simulate_sliding(Friction(0.25, 0.2), motions.rect_pulse(0.3 * 9.81, 0.5))
>>> round(r.u_max, 4), r.n_slides, round(r.t_first, 3)
(0.1839, 1, 0.0)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..quantities import G


@dataclass(frozen=True)
class Friction:
    """Coulomb friction of a body on its support: ``mu_s`` static, ``mu_k`` kinetic (0 <= mu_k <= mu_s)."""

    mu_s: float
    mu_k: float

    def __post_init__(self):
        for name in ("mu_s", "mu_k"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0 or v > 5:
                raise InputError(f"friction {name} must be a number in (0, 5] (a support without friction "
                                 f"never stops the body), got {v!r}")
        if self.mu_k > self.mu_s:
            raise InputError(f"the kinetic friction mu_k {self.mu_k:g} exceeds the static mu_s {self.mu_s:g}")


@dataclass(frozen=True)
class SlidingResult:
    """``u_max`` the peak |u| (m), ``u_pos`` / ``u_neg`` the peak displacement toward +x / toward -x (m,
    >= 0; u_max is the larger), ``u_end`` the displacement where the body comes to rest (m, signed),
    ``t_first`` the first onset (s; None: it never slides), ``n_slides`` the sliding phases,
    ``slide_time`` their total duration (s), ``t_rest`` when it last came to rest (s)."""

    u_max: float
    u_end: float
    t_first: float | None
    n_slides: int
    slide_time: float
    t_rest: float
    u_pos: float = 0.0
    u_neg: float = 0.0

    @property
    def slides(self) -> bool:
        return self.t_first is not None

    def to_dict(self) -> dict:
        return {"u_max": self.u_max, "u_end": self.u_end, "t_first": self.t_first, "n_slides": self.n_slides,
                "slide_time": self.slide_time, "t_rest": self.t_rest, "u_pos": self.u_pos, "u_neg": self.u_neg,
                "slides": self.slides}


def slides_first(friction: Friction, b_over_h: float) -> bool:
    """Whether a rigid planar block slides before it lifts under a ground acceleration growing from rest:
    mu_s g is reached before g b / h (module docstring)."""
    return friction.mu_s < b_over_h


def _first_crossing(a0: float, k: float, h: float, level: float) -> float | None:
    """The first tau in (0, h] where |a0 + k tau| exceeds ``level`` (it is at most ``level`` at 0)."""
    if k == 0.0:
        return None
    out = []
    for target in (level, -level):
        tau = (target - a0) / k
        if 0.0 < tau <= h:
            out.append(tau)
    return min(out) if out else None


def _stop(v0: float, a0: float, k: float, s: float, c: float, h: float) -> float | None:
    """The first tau in (0, h] where the relative velocity v(tau) = v0 - (a0 + s c) tau - k tau^2 / 2
    returns to 0 (v0 has the sign s), or None."""
    A, B, C = -0.5 * k, -(a0 + s * c), v0
    roots = []
    if abs(A) < 1e-300:
        if B != 0.0:
            roots.append(-C / B)
    else:
        disc = B * B - 4.0 * A * C
        if disc >= 0.0:
            q = -0.5 * (B + math.copysign(math.sqrt(disc), B)) if B != 0.0 else math.sqrt(max(-C / A, 0.0))
            roots += [q / A] if q == 0.0 else [q / A, C / q]
    good = [t for t in roots if 1e-15 < t <= h]
    return min(good) if good else None


def _next_moving_step(t: np.ndarray, a: np.ndarray, mus: float, stop_at: float) -> np.ndarray:
    """For each step i (t[i] to t[i + 1]): the first step j >= i in which a body at rest at its start may
    start to slide (len(t) - 1: none). A step where it cannot is one that :func:`simulate_sliding`'s loop
    passes at rest without changing anything: no time left (h <= 0), |a0| <= mu_s g at its start and no
    crossing of +-mu_s g within it, each decided by the loop's own float operations, on whole arrays."""
    n = t.size - 1
    t0, span, a0 = t[:-1], t[1:] - t[:-1], a[:-1]
    h = np.minimum(span, stop_at - t0)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = (a[1:] - a0) / span
        cross = np.zeros(n, dtype=bool)
        for target in (mus, -mus):
            tau = (target - a0) / k
            cross |= (k != 0.0) & (0.0 < tau) & (tau <= h)
    rest = (h <= 0) | ((np.abs(a0) <= mus) & ~cross)
    nxt = np.where(rest, n, np.arange(n))
    return np.minimum.accumulate(nxt[::-1])[::-1] if n else nxt


def simulate_sliding(friction: Friction, motion, t_end: float | None = None, dt: float = 1e-3,
                     g: float = G) -> SlidingResult:
    """The body's sliding under ``motion`` (a GroundMotion of its support, m/s^2 toward +x) with
    ``friction``; exact between the motion's samples (a record's own, a pulse's at ``dt`` s). After the
    motion the body slides to rest; ``t_end`` (s) stops the analysis earlier."""
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"dt must be positive, got {dt}")
    if motion.kind == "none":
        return SlidingResult(0.0, 0.0, None, 0, 0.0, 0.0)
    if motion.kind == "record":
        t = motion.start + motion.dt * np.arange(motion.samples.size)
        a = np.asarray(motion.samples, dtype=float)
        if motion.start > 0:
            t, a = np.concatenate([[0.0], t]), np.concatenate([[0.0], a])
    else:
        n = max(2, int(math.ceil(motion.end / dt)) + 1)
        t = np.linspace(0.0, motion.end, n)
        a = np.asarray(motion.acc(t), dtype=float)
        # a pulse's jumps: the samples on each side of its start and end
        edges = [motion.start, motion.end]
        t = np.unique(np.concatenate([t, [max(e - 1e-12, 0.0) for e in edges], edges]))
        a = np.asarray(motion.acc(t), dtype=float)
    stop_at = math.inf if t_end is None else float(t_end)
    mus, c = friction.mu_s * g, friction.mu_k * g
    u = v = 0.0
    s = 0.0                     # the sliding direction (sign of v); 0: stuck
    u_pos = u_neg = 0.0
    t_first, n_slides, slide_time, t_rest, t_on = None, 0, 0.0, 0.0, 0.0

    def onset(time, acc):
        nonlocal s, t_first, n_slides, t_on
        s = -math.copysign(1.0, acc)
        n_slides += 1
        t_on = time
        if t_first is None:
            t_first = time

    n = t.size - 1
    resume = _next_moving_step(t, a, mus, stop_at)
    i = -1
    while i + 1 < n:
        i += 1
        if s == 0.0 and resume[i] != i:     # at rest through this step and the next ones up to resume[i]
            i = int(resume[i]) - 1
            continue
        t0, h = float(t[i]), float(t[i + 1] - t[i])
        if t0 >= stop_at:
            break
        h = min(h, stop_at - t0)
        if h <= 0:
            continue
        a0 = float(a[i])
        k = (float(a[i + 1]) - a0) / float(t[i + 1] - t[i])
        tau0 = 0.0
        while tau0 < h:
            ac = a0 + k * tau0
            if s == 0.0:
                if abs(ac) > mus:
                    onset(t0 + tau0, ac)
                    continue
                x = _first_crossing(ac, k, h - tau0, mus)
                if x is None:
                    break
                tau0 += x
                onset(t0 + tau0, a0 + k * tau0)
                continue
            rem = h - tau0
            ts = _stop(v, ac, k, s, c, rem)
            step = rem if ts is None else ts
            u += v * step - 0.5 * (ac + s * c) * step * step - k * step ** 3 / 6.0
            v = v - (ac + s * c) * step - 0.5 * k * step * step
            tau0 += step
            if ts is not None:
                v = 0.0
                u_pos, u_neg = max(u_pos, u), max(u_neg, -u)
                slide_time += t0 + tau0 - t_on
                t_rest = t0 + tau0
                s = 0.0
        u_pos, u_neg = max(u_pos, u), max(u_neg, -u)
    if s != 0.0 and t_end is None:          # after the motion: decelerate at mu_k g to rest
        tr = abs(v) / c                     # c > 0: Friction refuses mu_k = 0
        u += v * tr - 0.5 * s * c * tr * tr
        slide_time += float(t[-1]) + tr - t_on
        t_rest = float(t[-1]) + tr
        u_pos, u_neg = max(u_pos, u), max(u_neg, -u)
    return SlidingResult(float(max(u_pos, u_neg)), float(u), t_first, n_slides, float(slide_time), float(t_rest),
                         float(u_pos), float(u_neg))
