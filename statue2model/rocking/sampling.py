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
SAMPLEABLE = SWEEPABLE + (IM_FACTOR,)
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
        n = _count(self.n_samples, "number of samples")
        for name, v in self.values.items():
            if name not in SAMPLEABLE:
                raise InputError(f"cannot sample {name!r}; choose one of {', '.join(SAMPLEABLE)}")
            a = np.asarray(v, dtype=float)
            if a.shape != (n,):
                raise InputError(f"samples of {name}: expected {n} values, got shape {a.shape}")
            if not np.all(np.isfinite(a)):
                raise InputError(f"samples of {name} must be finite")
            if name == IM_FACTOR and np.any(a <= 0):
                raise InputError("samples of im_factor must be > 0")

    @property
    def n(self) -> int:
        return int(self.n_samples)

    def im_factors(self) -> np.ndarray:
        """(n,) multipliers of the ground motion (1 where im_factor is not sampled)."""
        return np.asarray(self.values.get(IM_FACTOR, np.ones(self.n)), dtype=float)

    def models(self, model: RockingModel) -> list[RockingModel]:
        """The n models: ``model`` with each sample's values ("alpha", "theta", "e" set both
        sides). A value outside the model's domain is an InputError naming the sample."""
        out = []
        names = [k for k in self.values if k != IM_FACTOR]
        for i in range(self.n):
            changes = {}
            for name in names:
                v = float(self.values[name][i])
                if name in ("alpha", "theta", "e"):
                    changes[f"{name}_L"] = changes[f"{name}_R"] = v
                else:
                    changes[name] = v
            try:
                out.append(model.with_(**changes) if changes else model)
            except InputError as exc:
                raise InputError(f"parameter sample {i}: {exc}") from None
        return out

    def to_dict(self) -> dict:
        return {"n": self.n, "method": self.method, "seed": self.seed,
                "values": {k: np.asarray(v, dtype=float) for k, v in self.values.items()}}


def _count(n, what: str) -> int:
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


def _seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}")
    return int(seed)


def latin_hypercube(ranges: dict, n: int, seed: int = 0) -> ParameterSamples:
    """n samples of a Latin hypercube (scipy.stats.qmc.LatinHypercube, ``seed``) over
    ``ranges`` = {name: (lo, hi)}, uniform in each range."""
    from scipy.stats import qmc

    n = _count(n, "number of samples")
    seed = _seed(seed)
    if not ranges:
        raise InputError("a Latin hypercube needs at least one parameter range")
    rs = {name: _range(name, *r) for name, r in ranges.items()}
    u = qmc.LatinHypercube(d=len(rs), seed=np.random.default_rng(seed)).random(n)
    vals = {name: lo + (hi - lo) * u[:, j] for j, (name, (lo, hi)) in enumerate(rs.items())}
    return ParameterSamples(vals, n, "lhs", seed)


def grid(name: str, lo: float, hi: float, n: int) -> ParameterSamples:
    """n evenly spaced values of ``name`` from lo to hi (both included)."""
    n = _count(n, "number of samples")
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

    n = _count(n, "number of samples")
    seed = _seed(seed)
    if not (math.isfinite(beta) and beta >= 0):
        raise InputError(f"dispersion beta must be >= 0, got {beta}")
    u = qmc.LatinHypercube(d=1, seed=np.random.default_rng(seed)).random(n)[:, 0]
    return ParameterSamples({IM_FACTOR: np.exp(beta * norm.ppf(u))}, n, "lognormal", seed)


def nominal(n: int = 1) -> ParameterSamples:
    """n samples of the model as it is (nothing varied)."""
    return ParameterSamples({}, _count(n, "number of samples"), "nominal", None)
