"""The rocking engine: the imperfect asymmetric rocking model of a rigid body on a fixed
base (MODEL.md sections 2-3), its compiled integrator and the analyses built on it.

Modules: ``model`` (immutable RockingModel, Restitution), ``kernel`` (the compiled
integrator), ``dop853`` (the DOP853 method shared with the isolator's coupled kernel),
``engine`` (simulate -> RockingResult), ``batch`` (many runs in one call), ``spectrum``
(overturning spectra of pulses), ``sweeps`` (variability over PGA, uncertainty of a
parameter), ``sampling`` (parameter samples), ``identify`` (restitution from
free-rocking records), ``reference`` (scipy solve_ivp, the reference of the tests),
``sliding`` (Coulomb sliding of one body), ``stack`` (a statue on a pedestal: the two-block
rocking model), ``bodies`` (the body types behind one seam: a model, a kernel, a registry row).
Ground motions are :mod:`statue2model.hazard.motions`.
"""
from .engine import RockingResult, simulate
from .model import Restitution, RockingModel

__all__ = ["RockingModel", "Restitution", "RockingResult", "simulate"]
