"""The design spectrum a 1:lambda prototype feels when the full-scale records are Froude-scaled
for it (thesis ch. 6.3.2: times / sqrt(lambda), accelerations unchanged; docs MODEL.md par. 5).

A record compressed in time, a_p(t) = a_f(sqrt(lambda) t), drives an oscillator of period T as
the full-scale record drives one of period sqrt(lambda) T (the same equation in the scaled
time). So the prototype's spectrum is the full-scale one read at sqrt(lambda) T::

    Se_p(T) = Se_f(sqrt(lambda) T)          SDe_p(T) = Se_p(T) T^2 / (4 pi^2) = SDe_f(sqrt(lambda) T) / lambda

(displacements scale as lengths, 1 / lambda). A device of period T on the prototype stands for
one of period sqrt(lambda) T under the statue itself; its design acceleration is the full-scale
spectrum there, not at T. :class:`FroudeSpectrum` wraps any full-scale spectrum (a code
spectrum, a floor spectrum) and is a target wherever one is (``Se``, ``SDe``, ``xi``,
``to_dict``), e.g. for :func:`statue2model.isolator.design.assess` on a prototype. SI units.

Example
-------
>>> from statue2model.hazard.code_spectra import G, ec8
>>> full = ec8(0.25 * G, "C")
>>> proto = FroudeSpectrum(full, 2.0)
>>> bool(proto.Se(1.0) == full.Se(2.0 ** 0.5))
True
>>> round(float(proto.SDe(1.0) / full.SDe(2.0 ** 0.5)), 12)     # lengths 1 : 2
0.5
>>> round(proto.pga / G, 4), proto.to_dict()["scale"]
(0.2875, '1:2')
>>> FroudeSpectrum(full, 0.5)
Traceback (most recent call last):
...
statue2model.errors.InputError: Froude scale lambda must be a number >= 1 (a 1:lambda prototype), got 0.5
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .code_spectra import _periods


@dataclass(frozen=True)
class FroudeSpectrum:
    """The spectrum of the 1:``scale`` prototype of the full-scale spectrum ``full`` (module docstring)."""

    full: object
    scale: float

    def __post_init__(self):
        if not all(callable(getattr(self.full, name, None)) for name in ("Se", "to_dict")):
            raise InputError(f"Froude spectrum: the full-scale spectrum must have Se(T) and to_dict(), got {self.full!r}")
        lam = self.scale
        if isinstance(lam, bool) or not isinstance(lam, (int, float)) or not (math.isfinite(lam) and lam >= 1):
            raise InputError(f"Froude scale lambda must be a number >= 1 (a 1:lambda prototype), got {lam!r}")
        object.__setattr__(self, "scale", float(lam))

    @property
    def time_factor(self) -> float:
        """sqrt(lambda): a prototype period T stands for sqrt(lambda) T at full scale."""
        return math.sqrt(self.scale)

    @property
    def xi(self) -> float:
        """Damping ratio (percent) of the spectrum: the full-scale one's."""
        return float(getattr(self.full, "xi", 5.0))

    def Se(self, T) -> np.ndarray:
        """Pseudo-acceleration (m/s^2) at prototype periods T (s): the full-scale one at sqrt(lambda) T."""
        return np.asarray(self.full.Se(self.time_factor * _periods(T)), dtype=float)

    def SDe(self, T) -> np.ndarray:
        """Spectral displacement (m) at prototype periods T (s): Se T^2 / (4 pi^2)."""
        T = _periods(T)
        return self.Se(T) * T ** 2 / (4.0 * math.pi ** 2)

    @property
    def pga(self) -> float:
        """Se(0), m/s^2: the peak acceleration, the same at both scales."""
        return float(self.Se(0.0))

    def to_dict(self) -> dict:
        """JSON-ready: the scale and the full-scale spectrum."""
        return {"kind": "froude", "scale": f"1:{self.scale:g}", "time_factor": self.time_factor,
                "rule": "Se_p(T) = Se_f(sqrt(lambda) T); SDe_p(T) = SDe_f(sqrt(lambda) T) / lambda",
                "full": self.full.to_dict()}
