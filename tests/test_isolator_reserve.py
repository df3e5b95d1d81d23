"""The reserve: where the fixed-base statue overturns (isolator/reserve.py), and the device's travel there
(isolator/verify.py): the check that keeps the device's failure median at or right of the fixed base's
overturning median must be able to fail."""
from __future__ import annotations

import math

import numpy as np
import pytest

from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.isolator import checks as C
from statue2model.isolator.reserve import overturning_scales
from statue2model.rocking.engine import simulate
from statue2model.rocking.model import RockingModel

BLOCK = RockingModel.housner(RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0))


def test_the_lowest_overturning_scale_of_a_rectangular_pulse():
    """A long rectangular pulse overturns a block once its amplitude passes a threshold (monotonic): the scale
    found overturns it and 2 % less does not (the ladder and its bisections resolve about 1 %)."""
    pulse = motions.rect_pulse(1.0, 0.5)
    (res,) = overturning_scales(BLOCK, [pulse], caps=[50.0])
    assert res.overturns and 1.0 < res.scale < 50.0
    assert simulate(BLOCK, pulse.scaled(res.scale)).overturned
    assert not simulate(BLOCK, pulse.scaled(0.98 * res.scale)).overturned
    # the linearised closed form (MODEL.md 3): a / (g delta) = 1 / (1 - exp(-p t1)) for the rectangular pulse
    delta = math.atan(0.05 / 0.25)
    p = math.sqrt(3 * 9.81 / (4 * math.hypot(0.05, 0.25)))
    closed = 9.81 * delta / (1 - math.exp(-p * 0.5))
    assert res.scale == pytest.approx(closed, rel=0.15)          # nonlinear vs linearised: within 15 %


def test_a_record_that_never_overturns_is_taken_at_its_cap():
    squat = RockingModel.housner(RockingParams.rectangular_block(b=0.4, h=0.3, m=50.0))
    rec = motions.synthetic_record(duration=8.0, pga=1.0, seed=3)
    (res,) = overturning_scales(squat, [rec], caps=[2.0])
    assert not res.overturns and res.scale == 2.0


def test_the_reserve_decides_the_device_and_can_fail():
    """A slender statue on a strong site: with the reserve, the capacity covers 1.05 x the median travel
    where half the records overturn the fixed base; on a plate too small for it the design fails on the
    reserve and says so in one sentence."""
    from statue2model.hazard.code_spectra import ec8
    from statue2model.isolator.verify import verify

    statue = RockingParams.from_dict({"m": 60.0, "h": 0.5, "b_L": 0.12, "b_R": 0.12, "I_G": 6.0})
    recs = [motions.synthetic_record(duration=12.0, pga=0.35 * 9.81, seed=s) for s in range(1, 8)]
    model = RockingModel.housner(statue)
    kw = dict(records=recs, mu=0.0073, spectrum=ec8(0.3 * 9.80665, "B"), thickness=0.03, R_grid=(1.0, 1.5),
              balls=(0.02, 0.03), surfaces="pom", layouts="ring4", fixed_model=model, design_pga=0.36 * 9.81)
    d = verify(statue, **kw)
    res = d.verification["reserve"]
    thresholds = np.array(res["thresholds"])
    assert res["pga"] == pytest.approx(min(np.exp(np.mean(np.log(thresholds))), C.RESERVE_LEVEL * 0.36 * 9.81))
    reserve = next(c for c in d.checks if c.key == "reserve")
    R_hat = d.R_hat
    need = C.RESERVE_MARGIN * res["travel"] + d.verification["mu_high"] * R_hat
    assert reserve.value == pytest.approx(need, rel=1e-9)
    assert res["travel"] == pytest.approx(float(np.median(res["travel_per_record"])), rel=1e-12)
    if d.passed:
        assert reserve.passed and d.capacity >= need * (1 - 1e-9)
    # the two empirical curves compared rank by rank: where the device fails (its travel capacity passed) against
    # where the statue overturns without it, on the same records
    tail = res["tail"]
    assert len(tail["fixed_sorted"]) == len(tail["device_sorted"]) == 7
    assert tail["fixed_sorted"] == sorted(res["thresholds"])
    dominated = all(dv >= fx * (1 - 1e-9) for dv, fx in zip(tail["device_sorted"], tail["fixed_sorted"]))
    assert tail["dominates"] == dominated
    if not dominated:
        a = tail["worse_from"]
        assert sum(x <= a for x in tail["device_sorted"]) == tail["device_fails"] > tail["fixed_fails"] == sum(
            x <= a for x in tail["fixed_sorted"])
    small = verify(statue, side_max=0.45, **kw)
    assert not small.passed
    bad = {c.key for c in small.checks if c.required and not c.passed}
    assert bad & {"reserve", "plate_size", "th_travel", "th_travel_slc", "travel", "travel_slc", "overturning",
                  "overturning_slc"}
    assert small.what_would_pass["text"].count(".") >= 1 and "restrain" in small.what_would_pass["text"]
