"""The validity screen's slip (crosscheck/screen.py slip_of): the pivot's slip per contact phase and
the standing base's slide before lift-off count; the base's drift after lift-off does not. Hand-made
results (no engine) and one short block run."""
from types import SimpleNamespace

import numpy as np
import pytest

from statue2model.crosscheck.screen import SLIP_LIMIT, slip_of, validity_screen


def _run(slide, pivot_slip, uplift_time, t=None):
    """A result with the slide history and the pivot slip's running maximum (its last value is max_pivot_slip)."""
    t = np.arange(len(slide), dtype=float) if t is None else np.asarray(t, dtype=float)
    ps = np.asarray(pivot_slip, dtype=float)
    return SimpleNamespace(t=t, slide=np.asarray(slide, dtype=float), uplift_time=uplift_time,
                           max_pivot_slip=float(ps.max(initial=0.0)))


def test_drift_after_lift_off_is_not_slip():
    # lifts at 1.5 s; the base centre reads 9 mm and 131 mm upright later (drift of many phases, yaw walk);
    # each contact phase's pivot slip stays at 1.2 mm: the slip is 1.2 mm and the screen passes
    r = _run([0.0, 1e-5, np.nan, 9e-3, np.nan, 0.131], [0.0, 0.0, 5e-4, 1.2e-3, 1.2e-3, 1.2e-3], 1.5)
    assert slip_of(r) == pytest.approx(1.2e-3)
    s = validity_screen(0.4, 0.8, slip_of(r), 0.0, 1.0)
    assert s["applicable"] and s["slip_mm"] == pytest.approx(1.2)


def test_slide_from_rest_before_lift_off_counts():
    # slides 5 mm standing (pivot vertices anchored at rest read only 1 mm here), then lifts at 2.5 s
    r = _run([0.0, -2e-3, -5e-3, np.nan, 0.0], [0.0, 1e-3, 1e-3, 1e-3, 1e-3], 2.5)
    assert slip_of(r) == pytest.approx(5e-3)
    s = validity_screen(0.4, 0.8, slip_of(r), 0.0, 1.0)
    assert not s["applicable"] and s["reasons"] == ["3D pivot slips 5.0 mm > 2 mm"]


def test_never_lifting_run_counts_its_whole_slide():
    r = _run([0.0, 1e-3, 3e-3, 4e-3], [0.0, 0.0, 0.0, 0.0], None)
    assert slip_of(r) == pytest.approx(4e-3) and slip_of(r) > SLIP_LIMIT


def test_release_counts_the_pivot_slip_only():
    # a release (uplift_time 0): the slide from rest never counts, the pivot's 3 mm does; mismatched input is refused
    t = [0.0, 0.5, 1.0, 1.5]
    r = _run([0.0, np.nan, 7e-3, np.nan], [0.0, 2e-4, 1e-3, 3e-3], 0.0, t=t)
    assert slip_of(r) == pytest.approx(3e-3)
    with pytest.raises(ValueError, match="samples"):
        slip_of(SimpleNamespace(t=np.zeros(3), slide=np.zeros(2), uplift_time=None, max_pivot_slip=0.0))


def test_block_release_does_not_slip():
    """A block released at half its delta (0.6 s, ~0.1 s of CPU): its pivot holds (no drift reads as slip)."""
    from statue2model.crosscheck.statue_scene import StatueScene, simulate_statue
    from statue2model.hazard import motions

    sc = StatueScene.block(b=0.1, h=0.5, m=100.0)
    r = simulate_statue(sc, motions.free(), theta0=0.5 * sc.params.delta_R, t_end=0.6)
    assert slip_of(r) == r.max_pivot_slip < SLIP_LIMIT
