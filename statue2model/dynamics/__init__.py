"""Reduced 2D dynamics: the rocking model, ground motions and the sweeps built on them.

Modules: ``model`` (immutable RockingModel, Restitution), ``motions`` (GroundMotion
and its constructors, files, SPEC strings), ``kernel`` (the compiled integrator),
``engine`` (simulate -> RockingResult), ``closed_form`` (Housner's formulas),
``spectrum``, ``sweeps`` (variability over PGA, uncertainty of a parameter),
``identify`` (restitution from free-rocking records).
"""
from . import motions
from .engine import RockingResult, simulate
from .model import Restitution, RockingModel

__all__ = ["RockingModel", "Restitution", "RockingResult", "simulate", "motions"]
