"""Fragility studies (assessment/fragility.py, rocking/sampling.py, cli/fragility.py).

Closed form: a slender block (Housner, linearised) under a rectangular pulse of duration
t_p and amplitude a overturns iff a >= a* = g delta / (1 - exp(-p t_p)) (MODEL.md section 3).
With a = IM x eps, eps lognormal(0, beta) as the parameter samples (im_factor),
P(overturn | IM) = Phi(ln(IM / a*) / beta): the fit must recover a* and beta.
"""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from statue2model.compute.executors import ProcessExecutor, SerialExecutor
from statue2model.hazard import motions
from statue2model.rocking import RockingModel
from statue2model.assessment.fragility import (
    FragilityStudy,
    fit_lognormal,
    lognormal_cdf,
    pgv,
    run_fragility,
)
from statue2model.rocking.sampling import (
    grid,
    latin_hypercube,
    lognormal_factor,
    nominal,
    thesis_theta_R,
)
from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.report.fragility_plots import plot_fragility

BLOCK = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
STATUE = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})


def a_star(tp: float) -> float:
    return BLOCK.g * BLOCK.delta_L / (1.0 - math.exp(-BLOCK.p_L * tp))


@pytest.mark.parametrize("tp, beta", [(0.25, 0.3), (0.6, 0.5)])
def test_rectangular_pulse_recovers_closed_form(tp, beta):
    model = RockingModel.housner(BLOCK, e_L=0.9, e_R=0.9, linearised=True)
    a = a_star(tp)
    levels = a * np.exp(beta * np.linspace(-2.5, 2.5, 11))
    res = run_fragility(model, [motions.rect_pulse(1.0, tp)], levels, lognormal_factor(beta, 200, seed=3),
                        FragilityStudy(n_boot=40, free_time=5.0))
    c = res.curves["overturning_fixed"]
    assert c.status == "ok" and res.bootstrap_unit == "samples"
    assert abs(c.median / a - 1) < 0.01, (c.median, a)          # measured: 7e-5 (tp 0.25)
    assert abs(c.beta / beta - 1) < 0.05, (c.beta, beta)        # measured: 0.3 %
    assert c.median_ci[0] <= a <= c.median_ci[1]
    # the counts themselves follow the closed form: each run overturns iff IM eps >= a*
    eps = res.samples.im_factors()
    expected = [(lv * eps >= a).sum() for lv in levels]
    assert np.array_equal(c.n_fail, expected)


def test_fit_recovers_known_curve_and_edge_cases():
    lv = np.geomspace(1.0, 10.0, 15)
    n = np.full(lv.size, 10_000)
    z = np.round(n * lognormal_cdf(lv, 3.0, 0.4))
    med, beta, st = fit_lognormal(lv, z, n)
    assert st == "ok" and abs(med - 3.0) < 0.01 and abs(beta - 0.4) < 0.005
    assert fit_lognormal(lv, 0 * z, n)[2] == "no failures"
    assert fit_lognormal(lv, n, n)[2] == "all failed"
    step = (lv > 4).astype(int) * 10
    med, beta, st = fit_lognormal(lv, step, np.full(lv.size, 10))
    assert st == "step" and lv[lv <= 4].max() < med < lv[lv > 4].min()


def test_pgv_and_pgv_levels():
    assert pgv(motions.rect_pulse(2.0, 0.3)) == pytest.approx(0.6)
    rec = motions.record([0.0, 1.0, 1.0, 0.0], 0.1)
    assert pgv(rec) == pytest.approx(0.2)
    model = RockingModel.housner(BLOCK, e_L=0.9, e_R=0.9, linearised=True)
    tp = 0.25
    # PGV of a rectangular pulse is a tp: the median in PGV is a* tp
    res = run_fragility(model, [motions.rect_pulse(1.0, tp)], a_star(tp) * tp * np.exp(0.3 * np.linspace(-2, 2, 9)),
                        lognormal_factor(0.3, 100, seed=1), FragilityStudy(im="pgv", n_boot=0, free_time=5.0))
    assert res.curves["overturning_fixed"].median == pytest.approx(a_star(tp) * tp, rel=0.01)


def _statue_study(executor, isolator=None):
    model = RockingModel.imperfect(STATUE, 0.159, 0.175, 4.55e-3, 4.55e-3)
    recs = [motions.synthetic_record(6.0, 0.01, 1.0, seed=s) for s in range(3)]
    smp = latin_hypercube({"theta_R": (1.78e-2 * STATUE.delta_R, 2.26e-2 * STATUE.delta_R), "e": (0.75, 0.85)}, 3,
                          seed=0)
    return run_fragility(model, recs, np.linspace(0.05, 1.0, 5) * 9.81, smp, FragilityStudy(n_boot=10),
                         isolator=isolator, executor=executor)


@pytest.mark.slow
def test_identical_serial_processes_dask():
    from statue2model.isolator.device import Isolator

    iso = Isolator(R=0.31, r=0.0095, M=STATUE.m + 8.0, mu=0.0073, capacity=0.15)
    ref = _statue_study(None, iso)
    assert set(ref.curves) == {"full_contact_fixed", "overturning_fixed", "full_contact_isolated",
                               "overturning_alone_isolated", "capacity_isolated", "overturning_isolated"}
    assert ref.curves["overturning_fixed"].n_fail.sum() > 0 and ref.curves["capacity_isolated"].n_fail.sum() > 0
    others = [SerialExecutor(), ProcessExecutor(2)]
    cluster = None
    try:
        import distributed
    except ImportError:          # Dask is an optional extra: serial vs processes only
        distributed = None
    if distributed is not None:
        import logging

        from statue2model.compute.executors import DaskExecutor

        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                           host="127.0.0.1", silence_logs=logging.ERROR)
        others.append(DaskExecutor(cluster.scheduler_address))
    try:
        for ex in others:
            res = _statue_study(ex, iso)
            for k in ref.fails:
                assert np.array_equal(res.fails[k], ref.fails[k]), (ex, k)
            assert res.curves["overturning_fixed"].median == ref.curves["overturning_fixed"].median
    finally:
        for ex in others:
            ex.close()
        if cluster is not None:
            cluster.close()


def test_outputs(tmp_path):
    res = _statue_study(None)
    d = res.to_dict()
    assert d["curves"]["overturning_fixed"]["n_trials"].sum() == 3 * 5 * 3
    res.write_json(tmp_path / "f.json")
    res.write_csv(tmp_path / "f.csv")
    plot_fragility(res, tmp_path / "f.png")
    lines = (tmp_path / "f.csv").read_text().splitlines()
    assert lines[0].startswith("outcome,pga_m_s2,n_fail,n_trials") and len(lines) == 1 + 2 * 5    # uplift, overturn
    assert (tmp_path / "f.png").stat().st_size > 10_000


def test_sampling():
    model = RockingModel.imperfect(STATUE, 0.159, 0.175, 4.55e-3, 4.55e-3)
    s = thesis_theta_R(model, 49)
    th = s.values["theta_R"]
    assert th.size == 49 and th[0] == pytest.approx(1.78e-2 * STATUE.delta_R) and th[-1] == pytest.approx(
        2.26e-2 * STATUE.delta_R)
    ms = latin_hypercube({"alpha": (0.1, 0.2)}, 10, seed=4).models(model)
    assert all(m.alpha_L == m.alpha_R for m in ms)
    u = np.sort(latin_hypercube({"e": (0.0, 1.0)}, 10, seed=4).values["e"])
    assert np.all((u >= np.arange(10) / 10) & (u <= np.arange(1, 11) / 10))     # one per stratum
    assert latin_hypercube({"e": (0.0, 1.0)}, 5, seed=7).values["e"].tolist() == \
        latin_hypercube({"e": (0.0, 1.0)}, 5, seed=7).values["e"].tolist()


@pytest.mark.parametrize("call, match", [
    (lambda m, r: run_fragility(m, [], [1.0], nominal()), "non-empty list"),
    (lambda m, r: run_fragility(m, r, [0.0, 1.0], nominal()), "finite and > 0"),
    (lambda m, r: run_fragility(m, r, [2.0, 1.0], nominal()), "strictly increasing"),
    (lambda m, r: run_fragility(m, [motions.record([0, 0, 0], 0.01)], [1.0], nominal()), "zero PGA"),
    (lambda m, r: run_fragility(m, r, [1.0], nominal(), FragilityStudy(im="sa")), "intensity measure"),
    (lambda m, r: run_fragility(m, r, [1.0], grid("alpha_L", 0.5, 1.5, 3)), "parameter sample 2"),
    (lambda m, r: latin_hypercube({"colour": (0, 1)}, 3), "cannot sample"),
    (lambda m, r: lognormal_factor(-1.0, 3), "beta must be >= 0"),
    (lambda m, r: run_fragility(m, r, [1.0] * 1, nominal(), isolator="iso"), "must be an Isolator"),
])
def test_bad_input_one_line(call, match):
    model = RockingModel.imperfect(BLOCK, 0.65, 0.65)
    with pytest.raises(InputError, match=match) as err:
        call(model, [motions.rect_pulse(1.0, 0.2)])
    assert "\n" not in str(err.value)


def test_cli(tmp_path):
    import json

    (tmp_path / "p.json").write_text(json.dumps(BLOCK.to_dict()))
    cmd = [sys.executable, "-m", "statue2model", "fragility", str(tmp_path / "p.json"), "--records",
           "synthetic:2,duration=4", "--levels", "0.1g:1.5g:5", "--samples", "3", "--vary", "e=0.8:0.9",
           "--boot", "5", "--out", str(tmp_path / "out")]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300, check=False)
    assert r.returncode == 0, r.stderr
    assert "2 records x 5 levels x 3 samples = 30 runs" in r.stdout
    assert {p.name for p in (tmp_path / "out").iterdir()} >= {"fragility.json", "fragility.csv", "fragility.png"}
    bad = subprocess.run(cmd[:8] + ["0.1:1:5", "--out", str(tmp_path / "o2")], capture_output=True, text=True, check=False,
                         timeout=300)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "has no unit" in bad.stderr


def test_energy_early_exit_decides_without_changing_outcomes():
    """early_exit="outcome": a run stops once its energy plus all the rest of the record could pump
    in stays below the overturning barrier. Outcomes equal those of full runs (with and without the
    sweeps' early exit) over a grid of gains; on a record whose strong part is followed by a weak
    tail the exit fires (S_DECIDED) and the run ends before the record does."""
    from statue2model.rocking import kernel as K
    from statue2model.rocking.batch import run_batch
    from statue2model.rocking.model import RockingModel
    from statue2model.geometry.rocking_params import RockingParams

    p = RockingParams.rectangular_block(0.1, 0.5, 100.0)
    model = RockingModel.housner(p, e_L=0.9, e_R=0.9)
    t = np.arange(0.0, 20.0, 0.01)
    strong = np.where(t < 3.0, np.sin(2 * np.pi * 1.5 * t), 0.0)
    tail = np.where(t >= 3.0, 0.02 * np.sin(2 * np.pi * 3.1 * t), 0.0)        # far below uplift
    rec = motions.record(strong + tail, 0.01)
    kind, M0, smp = rec.kernel_args()
    gains = np.linspace(1.5, 6.0, 40)                                          # m/s^2 peaks of the burst
    M = np.tile(M0, (gains.size, 1))
    M[:, K.MA] *= gains
    out = {}
    for mode in (False, True, "outcome"):
        P = np.tile(model.kernel_vector(early_exit=mode), (gains.size, 1))
        out[mode] = run_batch(model, P, np.full(gains.size, kind), M, smp, np.full(gains.size, 22.0), rtol=1e-8)
    ot = {m: out[m][:, K.S_OVERTURNED] > 0 for m in out}
    assert np.array_equal(ot[False], ot["outcome"]) and np.array_equal(ot[True], ot["outcome"])
    assert ot[False].any() and not ot[False].all()                             # the grid spans the boundary
    dec = (out["outcome"][:, K.S_DECIDED] > 0) & ~ot["outcome"]
    assert dec.any()
    assert np.all(out["outcome"][dec, K.S_T_FINAL] < 20.0)
    with pytest.raises(InputError):
        model.kernel_vector(early_exit="yes")


def test_pgv_of_a_drifting_record_is_read_after_a_high_pass():
    """A 20 s record with a spurious constant acceleration offset (a velocity drift) keeps its PGV:
    the offset is removed by the high-pass (fragility.PGV_HIGHPASS) before integrating."""
    t = np.arange(0.0, 20.0, 0.01)
    a = 2.0 * np.sin(2 * np.pi * 1.0 * t) * np.exp(-((t - 8.0) / 3.0) ** 2)
    clean = pgv(motions.record(a, 0.01))
    drifting = pgv(motions.record(a + 0.05, 0.01))            # raw integral: +1 m/s by the end
    assert clean == pytest.approx(2.0 / (2 * np.pi), rel=0.05)
    assert drifting == pytest.approx(clean, rel=0.05)


def test_a_curve_reads_back_from_its_json():
    """fragility.json's curves read back typed (issue [21]): FragilityCurve.from_dict of to_dict gives the
    same JSON for a fitted curve, a step and one without failures; an unknown key is refused by name."""
    import json

    from statue2model.assessment.fragility import FragilityCurve
    from statue2model.errors import InputError

    block = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
    model = RockingModel.housner(block, e_L=0.9, e_R=0.9)
    recs = [motions.synthetic_record(6.0, 0.01, 1.0, seed=s) for s in range(3)]
    res = run_fragility(model, recs, np.linspace(1.0, 12.0, 6), lognormal_factor(0.2, 4), FragilityStudy(n_boot=20))
    lv = np.array([1.0, 2.0, 3.0, 4.0])
    curves = [*res.curves.values(),
              FragilityCurve("overturning_fixed", lv, np.array([0, 0, 7, 7]), np.full(4, 7), 2.5, 1e-3, "step"),
              FragilityCurve("overturning_fixed", lv, np.zeros(4, dtype=int), np.full(4, 7), math.nan, math.nan,
                             "no failures")]
    for c in curves:
        d = json.loads(json.dumps(_json(c.to_dict())))
        back = FragilityCurve.from_dict(d)
        assert json.loads(json.dumps(_json(back.to_dict()))) == d, c.outcome
    with pytest.raises(InputError, match="unknown outcome 'overturn'"):
        FragilityCurve.from_dict({**d, "outcome": "overturn"})
    with pytest.raises(InputError, match="one length"):
        FragilityCurve.from_dict({**d, "n_fail": [0]})


def _json(x):
    if isinstance(x, dict):
        return {k: _json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple, np.ndarray)):
        return [_json(v) for v in x]
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x
