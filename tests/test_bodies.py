"""The body-model seam (issue [22], item 1): every registered body type gives the fields the consumers
read, by its own kernel; a new type is a model, a kernel and a row."""
from __future__ import annotations

from dataclasses import dataclass

import pytest

from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.quantities import G
from statue2model.rocking import bodies
from statue2model.rocking.engine import simulate as simulate_single
from statue2model.rocking.model import RockingModel
from statue2model.rocking.stack import Pedestal, StackModel

STATUE = RockingParams.rectangular_block(b=0.1, h=0.5, m=200.0)
FIELDS = ("overturned", "theta_max_over_delta", "uplift_time", "outcome", "n_impacts")


@pytest.mark.parametrize("model", [RockingModel.housner(STATUE), StackModel(STATUE, Pedestal.box(0.6, 0.6, 1.0, 300.0))])
def test_every_body_type_gives_the_response_fields(model):
    r = bodies.simulate(model, motions.sine_pulse(0.3 * G, 2.0))
    assert isinstance(r, bodies.Response) and all(hasattr(r, f) for f in FIELDS)
    assert r.overturned and r.theta_max_over_delta == 1.0 and r.uplift_time is not None
    up, dn = bodies.uplift_limits(model)
    assert up == pytest.approx(G * 0.1 / 0.5) and dn == pytest.approx(G * 0.2)


def test_the_stack_on_an_immovable_pedestal_is_the_rigid_body():
    heavy = StackModel(STATUE, Pedestal(b=50.0, h=0.1, m=1e6))
    m = motions.sine_pulse(0.25 * G, 2.0)
    a, b = bodies.simulate(heavy, m), simulate_single(RockingModel.housner(STATUE), m)
    assert a.theta_max_over_delta == pytest.approx(b.theta_max_over_delta, rel=1e-4)
    assert a.uplift_time == pytest.approx(b.uplift_time, abs=1e-9) and a.n_impacts == b.n_impacts


def test_a_stack_whose_pedestal_overturns_overturns_the_statue():
    slender = StackModel(RockingParams.rectangular_block(b=0.14, h=0.15, m=400.0), Pedestal.box(0.3, 0.3, 1.2, 50.0))
    r = bodies.simulate(slender, motions.rect_pulse(0.4 * G, 1.0))
    assert r.pedestal.overturned and r.overturned and r.theta_max_over_delta == 1.0


def test_an_unknown_model_is_refused_by_name_and_a_new_type_is_one_row(monkeypatch):
    with pytest.raises(InputError, match="no body type for a str .known: rigid_body, stack"):
        bodies.body_type("a statue")

    @dataclass(frozen=True)
    class Anchored:                                   # a body bolted down: it never moves
        a: float

    @dataclass(frozen=True)
    class Still:
        overturned: bool = False
        theta_max_over_delta: float = 0.0
        uplift_time: float | None = None
        outcome: str = "no motion"
        n_impacts: int = 0

    row = bodies.BodyType("anchored", Anchored, lambda m, motion, rtol=0: Still(), lambda m: (m.a, m.a), None, "")
    monkeypatch.setattr(bodies, "BODY_TYPES", (*bodies.BODY_TYPES, lambda: row))
    assert bodies.simulate(Anchored(5.0), motions.free()).outcome == "no motion"
    assert bodies.uplift_limits(Anchored(5.0)) == (5.0, 5.0)
