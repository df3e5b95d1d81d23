"""The body models behind one seam: a new body type is a model, a kernel and a row of :data:`BODY_TYPES`
(issue [22], item 1).

What every consumer of a time history reads of a run (the limit states, the fragility study, the
verdict, the cross-check) is written down once, as :class:`Response`:

    overturned            bool: the run ended overturned (for a stack: the statue or the pedestal with it)
    theta_max_over_delta  peak |theta| / delta of the body the verdict speaks for (the statue), 1 at
                          overturning
    uplift_time           s, the first lift-off of any contact (None: full contact throughout)
    outcome               the kernel's words for the run
    n_impacts             the impacts of the statue's base

and what a body gives before any run, :func:`uplift_limits`: the ground accelerations (toward +x, toward
-x, m/s^2) below which nothing lifts. A body type (:class:`BodyType`) names its model class, its kernel
(``simulate(model, motion, rtol=...) -> Response``), its static uplift limits and, when it has one, its
batch entry for the fragility study (many runs in one compiled call).

==========  =====================================  =====================================  ==============
name        model                                  kernel                                 batch
==========  =====================================  =====================================  ==============
rigid_body  rocking.model.RockingModel             rocking.engine.simulate (numba DOP853)  rocking.batch
stack       rocking.stack.StackModel               rocking.stack.simulate_stack (numba     -
            (a statue on a pedestal)               DOP853 with events; scipy reference)
==========  =====================================  =====================================  ==============

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking.model import RockingModel
>>> from statue2model.rocking.stack import Pedestal, StackModel
>>> statue = RockingParams.rectangular_block(b=0.1, h=0.5, m=200.0)
>>> for model in (RockingModel.housner(statue), StackModel(statue, Pedestal.box(0.6, 0.6, 1.0, 300.0))):
...     r = simulate(model, motions.sine_pulse(0.25 * 9.81, 2.0))
...     print(body_type(model).name, [round(a / 9.81, 3) for a in uplift_limits(model)], r.overturned,
...           r.uplift_time is not None)
rigid_body [0.2, 0.2] False True
stack [0.2, 0.2] False True
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Protocol, runtime_checkable

from ..errors import InputError


@runtime_checkable
class Response(Protocol):
    """What a run gives every consumer (module docstring)."""

    overturned: bool
    theta_max_over_delta: float
    uplift_time: float | None
    outcome: str
    n_impacts: int


@dataclass(frozen=True)
class BodyType:
    """One row of :data:`BODY_TYPES`: ``name``; ``model`` the model's class (immutable); ``simulate``
    its kernel, (model, motion, rtol=...) -> a :class:`Response`; ``uplift_limits`` model -> (toward +x,
    toward -x) m/s^2; ``batch`` the fragility study's batch entry, or None (the study then runs the
    kernel record by record); ``description``."""

    name: str
    model: type
    simulate: Callable
    uplift_limits: Callable
    batch: Callable | None
    description: str


def _rigid_body() -> BodyType:
    from .batch import run_batch
    from .engine import simulate as run
    from .model import RockingModel

    return BodyType("rigid_body", RockingModel, lambda m, motion, rtol=1e-7: run(m, motion, rtol=rtol),
                    lambda m: tuple(float(a) for a in m.uplift_limits), run_batch,
                    "one rigid body rocking on a fixed base (the imperfect asymmetric model, MODEL.md 2-3)")


def _stack() -> BodyType:
    from .stack import StackModel, simulate_stack

    def limits(m):
        lim = m.uplift_limits
        return tuple(float(min(lim["statue"][k], lim["pedestal"][k])) for k in (0, 1))

    return BodyType("stack", StackModel, lambda m, motion, rtol=1e-9: simulate_stack(m, motion, rtol=rtol),
                    limits, None, "a statue on a pedestal: the two-block rocking model (rocking/stack.py)")


BODY_TYPES: tuple[Callable[[], BodyType], ...] = (_rigid_body, _stack)
"""The body types, each as the function that builds its row (imports stay lazy: a row is built when asked)."""


def body_type(model) -> BodyType:
    """The row of ``model``'s type; an InputError naming the known types for any other object."""
    rows = [row() for row in BODY_TYPES]
    for row in rows:
        if isinstance(model, row.model):
            return row
    raise InputError(f"no body type for a {type(model).__name__} (known: {', '.join(r.name for r in rows)})")


def simulate(model, motion, rtol: float | None = None) -> Response:
    """One run of ``model`` (any registered body type) under ``motion``, by its own kernel."""
    row = body_type(model)
    return row.simulate(model, motion) if rtol is None else row.simulate(model, motion, rtol=rtol)


def uplift_limits(model) -> tuple[float, float]:
    """(toward +x, toward -x) m/s^2: the ground accelerations below which ``model`` stays in full contact."""
    return body_type(model).uplift_limits(model)
