"""Samples of the uncertain model parameters, for fragility studies.

A :class:`ParameterSamples` holds n values of each varied parameter (theta_R,
alpha_L, e, ... in the units of :class:`~statue2model.rocking.model.RockingModel`:
rad for theta, dimensionless alpha and e) and turns them into n models. The special
name ``im_factor`` (dimensionless, > 0) is not a model parameter: it multiplies the
ground motion of a run at every intensity level (an uncertain amplification between
the intensity measure and the motion the body feels).

* :func:`latin_hypercube` - n points of a Latin hypercube (scipy.stats.qmc, seeded)
  spread uniformly over each parameter's range [lo, hi].
* :func:`grid` - n evenly spaced values of one parameter (the thesis' 49-value sweep
  of theta_R / delta_R over [1.78, 2.26] x 1e-2, Table 24: :func:`thesis_theta_R`).
* :func:`lognormal_factor` - ``im_factor`` = exp(beta z), z at the n stratified
  normal quantiles of a Latin hypercube: a lognormal(0, beta) amplification.
* :func:`nominal` - n copies of the model (nothing varied).
* the default fragility study's joint design over these names is assessment/study.py
  ``study_design``; the isolator's friction bounds are isolator/friction.py ``friction_bounds``.

Three more special names, not fields of a RockingModel: ``e_factor`` (> 0) multiplies both
sides' restitution (every value of a velocity table; the result is capped at 1, so the
asymmetry e_L != e_R is kept), ``alpha_factor`` (> 0) multiplies alpha_L and alpha_R (capped
at 1), and ``mu`` (in [0, 1)) is the isolator's rolling friction of the sample
(:meth:`ParameterSamples.mu_values`; the rocking models do not read it).

Example
-------
>>> import numpy as np
>>> s = latin_hypercube({"theta_R": (0.004, 0.005), "e": (0.8, 0.9)}, 4, seed=1)
>>> s.n, sorted(s.values), bool(s.values["e"].min() >= 0.8)
(4, ['e', 'theta_R'], True)
>>> g = grid("alpha_R", 0.1, 0.2, 3)
>>> g.values["alpha_R"].tolist()
[0.1, 0.15000000000000002, 0.2]
>>> f = lognormal_factor(0.3, 1000, seed=2).values["im_factor"]
>>> round(float(np.log(f).std()), 3), round(float(np.median(f)), 3)    # dispersion 0.3, median 1
(0.3, 1.0)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from .model import RockingModel
from .sweeps import SWEEPABLE

IM_FACTOR = "im_factor"
E_FACTOR = "e_factor"
ALPHA_FACTOR = "alpha_factor"
MU = "mu"
FACTORS = (IM_FACTOR, E_FACTOR, ALPHA_FACTOR, MU)
"""Sampleable names that are not fields of a RockingModel (module docstring)."""
SAMPLEABLE = SWEEPABLE + FACTORS
THESIS_THETA_R = (1.78e-2, 2.26e-2)
"""theta_R / delta_R range of the thesis' uncertainty sweep (Table 24, 49 values)."""
MAX_SAMPLES = 100_000


@dataclass(frozen=True, eq=False)
class ParameterSamples:
    """n samples: ``values`` maps a name of SAMPLEABLE to an (n,) float array; ``method``
    ("lhs", "grid", "lognormal", "nominal" or "given") and ``seed`` say how they were drawn."""

    values: dict = field(default_factory=dict)
    n_samples: int = 1
    method: str = "nominal"
    seed: int | None = None

    def __post_init__(self):
        n = check_count(self.n_samples, "number of samples")
        for name, v in self.values.items():
            if name not in SAMPLEABLE:
                raise InputError(f"cannot sample {name!r}; choose one of {', '.join(SAMPLEABLE)}")
            a = np.asarray(v, dtype=float)
            if a.shape != (n,):
                raise InputError(f"samples of {name}: expected {n} values, got shape {a.shape}")
            if not np.all(np.isfinite(a)):
                raise InputError(f"samples of {name} must be finite")
            if name in (IM_FACTOR, E_FACTOR, ALPHA_FACTOR) and np.any(a <= 0):
                raise InputError(f"samples of {name} must be > 0")
            if name == MU and np.any((a < 0) | (a >= 1)):
                raise InputError("samples of mu (the isolator's rolling friction) must lie in [0, 1)")

    @property
    def n(self) -> int:
        return int(self.n_samples)

    def im_factors(self) -> np.ndarray:
        """(n,) multipliers of the ground motion (1 where im_factor is not sampled)."""
        return np.asarray(self.values.get(IM_FACTOR, np.ones(self.n)), dtype=float)

    def mu_values(self, mu: float) -> np.ndarray:
        """(n,) rolling friction of the isolator of each sample (``mu`` where it is not sampled)."""
        return np.asarray(self.values.get(MU, np.full(self.n, float(mu))), dtype=float)

    def models(self, model: RockingModel) -> list[RockingModel]:
        """The n models: ``model`` with each sample's values ("alpha", "theta", "e" set both
        sides; ``e_factor``, ``alpha_factor`` scale both sides, capped at 1). A value outside the
        model's domain is an InputError naming the sample."""
        from .model import Restitution

        out = []
        names = [k for k in self.values if k not in FACTORS]
        for i in range(self.n):
            changes = {}
            for name in names:
                v = float(self.values[name][i])
                if name in ("alpha", "theta", "e"):
                    changes[f"{name}_L"] = changes[f"{name}_R"] = v
                else:
                    changes[name] = v
            if E_FACTOR in self.values:
                f = float(self.values[E_FACTOR][i])
                for side in ("e_L", "e_R"):
                    e = changes.get(side, getattr(model, side))
                    e = Restitution.from_value(e, side)
                    changes[side] = Restitution(e.speeds, tuple(min(1.0, v * f) for v in e.values), side)
            if ALPHA_FACTOR in self.values:
                f = float(self.values[ALPHA_FACTOR][i])
                for side in ("alpha_L", "alpha_R"):
                    changes[side] = min(1.0, float(changes.get(side, getattr(model, side))) * f)
            try:
                out.append(model.with_(**changes) if changes else model)
            except InputError as exc:
                raise InputError(f"parameter sample {i}: {exc}") from None
        return out

    def to_dict(self) -> dict:
        return {"n": self.n, "method": self.method, "seed": self.seed,
                "values": {k: np.asarray(v, dtype=float) for k, v in self.values.items()}}


def check_count(n, what: str) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= MAX_SAMPLES:
        raise InputError(f"{what} must be a whole number in 1..{MAX_SAMPLES}, got {n!r}")
    return int(n)


def _range(name: str, lo, hi) -> tuple[float, float]:
    if name not in SAMPLEABLE:
        raise InputError(f"cannot sample {name!r}; choose one of {', '.join(SAMPLEABLE)}")
    try:
        lo, hi = float(lo), float(hi)
    except (TypeError, ValueError):
        raise InputError(f"range of {name} must be two numbers, got {lo!r}, {hi!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi):
        raise InputError(f"range of {name} must be finite with lo <= hi, got [{lo}, {hi}]")
    return lo, hi


def check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}")
    return int(seed)


def latin_hypercube(ranges: dict, n: int, seed: int = 0) -> ParameterSamples:
    """n samples of a Latin hypercube (scipy.stats.qmc.LatinHypercube, ``seed``) over
    ``ranges`` = {name: (lo, hi)}, uniform in each range."""
    from scipy.stats import qmc

    n = check_count(n, "number of samples")
    seed = check_seed(seed)
    if not ranges:
        raise InputError("a Latin hypercube needs at least one parameter range")
    rs = {name: _range(name, *r) for name, r in ranges.items()}
    u = qmc.LatinHypercube(d=len(rs), seed=np.random.default_rng(seed)).random(n)
    vals = {name: lo + (hi - lo) * u[:, j] for j, (name, (lo, hi)) in enumerate(rs.items())}
    return ParameterSamples(vals, n, "lhs", seed)


def grid(name: str, lo: float, hi: float, n: int) -> ParameterSamples:
    """n evenly spaced values of ``name`` from lo to hi (both included)."""
    n = check_count(n, "number of samples")
    lo, hi = _range(name, lo, hi)
    return ParameterSamples({name: np.linspace(lo, hi, n)}, n, "grid", None)


def thesis_theta_R(model: RockingModel, n: int = 49) -> ParameterSamples:
    """The thesis' sweep: theta_R / delta_R over [1.78, 2.26] x 1e-2 (Table 24), n values."""
    d = model.params.delta_R
    return grid("theta_R", THESIS_THETA_R[0] * d, THESIS_THETA_R[1] * d, n)


def lognormal_factor(beta: float, n: int, seed: int = 0) -> ParameterSamples:
    """``im_factor`` = exp(beta z) with z = Phi^-1 of a seeded Latin hypercube in (0, 1):
    n stratified samples of a lognormal with median 1 and dispersion ``beta``."""
    from scipy.stats import norm, qmc

    n = check_count(n, "number of samples")
    seed = check_seed(seed)
    if not (math.isfinite(beta) and beta >= 0):
        raise InputError(f"dispersion beta must be >= 0, got {beta}")
    u = qmc.LatinHypercube(d=1, seed=np.random.default_rng(seed)).random(n)[:, 0]
    return ParameterSamples({IM_FACTOR: np.exp(beta * norm.ppf(u))}, n, "lognormal", seed)


def nominal(n: int = 1) -> ParameterSamples:
    """n samples of the model as it is (nothing varied)."""
    return ParameterSamples({}, check_count(n, "number of samples"), "nominal", None)


def describe(samples: ParameterSamples, model: RockingModel, mu_source: str | None = None) -> str:
    """What ``samples`` vary, in words (the report's 'uncertain parameters')."""
    v = samples.values
    parts = []
    if "theta_R" in v:
        th = v["theta_R"]
        parts.append(f"theta_R {th.min():.4g}-{th.max():.4g} rad (the thesis' range, Table 24: "
                     f"{THESIS_THETA_R[0]:g}-{THESIS_THETA_R[1]:g} delta_R)")
    if E_FACTOR in v:
        f = v[E_FACTOR]
        parts.append(f"the restitution e_L, e_R x {f.min():.3f}-{f.max():.3f} (capped at 1; Table 23's scatter)")
    if ALPHA_FACTOR in v:
        f = v[ALPHA_FACTOR]
        parts.append(f"alpha_L, alpha_R x {f.min():.3f}-{f.max():.3f} (+-10 %, a stated assumption about "
                     f"alpha_L {model.alpha_L:g}, alpha_R {model.alpha_R:g})")
    for name in v:
        if name not in ("theta_R", E_FACTOR, ALPHA_FACTOR, MU):
            parts.append(f"{name} {v[name].min():.4g}-{v[name].max():.4g}")
    text = ", ".join(parts) if parts else "no model parameter"
    if MU in v:
        lo, hi = float(v[MU].min()), float(v[MU].max())
        k = int(np.sum(v[MU] == lo))
        text += (f"; the isolator's friction at its bounds, mu {lo:.4g} ({k} samples) and {hi:.4g} "
                 f"({samples.n - k})" + (f" from {mu_source}" if mu_source else ""))
    if samples.method == "lhs":
        text += f" (a Latin hypercube of {samples.n} samples, seed {samples.seed})"
    if model.kind != "imperfect" and "theta_R" not in v:
        text += "; Housner's model has no theta_R or alpha to vary: e only"
    return text
