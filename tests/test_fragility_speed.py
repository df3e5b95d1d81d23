"""The fast fixed-base path of the fragility study (rocking/kernel.py, rocking/batch.py,
assessment/fragility.py): every change is exact, so each test compares numbers to the bit.

* a body at rest skips the record pieces that cannot lift it (kernel._quiet_until, from the
  suffix extremes of the record): hand-computed cases, and the old path (run_batch
  skip_quiet=False: the stick search reads every piece) against the new one on records that end
  at rest, at several levels, for both bodies (the thesis statue, the bundled default scan);
* the motion piece as a tuple (kernel._piece) against hazard.motion_kernel.segment;
* the written-out DOP853 stages (kernel._step) against the loop over the tableau;
* the statistics of HEAD before this work (1f198ea) on a record that ends at rest;
* a record's runs of every sample of e in one batch (fragility._fixed) against one batch per
  restitution pair.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from statue2model.assessment import fragility as F
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.hazard.motion_kernel import segment
from statue2model.rocking import RockingModel
from statue2model.rocking import kernel as K
from statue2model.rocking.batch import restitution_tables, run_batch, suffix_extremes
from statue2model.rocking.sampling import latin_hypercube

STATUE = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
G = 9.81


def thesis_model():
    return RockingModel.imperfect(STATUE, 0.159, 0.175, 4.55e-3, 4.55e-3)


def scan_model():
    from statue2model.geometry.body import load_body
    from statue2model.io.paths import default_scan

    return RockingModel.housner(load_body(default_scan()).rocking(None))


def records_ending_at_rest():
    """Three 8 s synthetic records, each followed by 4 s of zeros (the ground ends at rest), and one
    with a weak tail (0.5 % of its peak) instead: quiet, yet not zero."""
    out = []
    for seed in range(3):
        r = motions.synthetic_record(8.0, 0.01, 1.0, seed=seed)
        out.append(motions.record(np.r_[r.samples, np.zeros(400)], 0.01, label=f"seed {seed} + rest"))
    r = motions.synthetic_record(8.0, 0.01, 1.0, seed=5)
    t = np.arange(400) * 0.01
    out.append(motions.record(np.r_[r.samples, 0.005 * np.sin(2 * np.pi * 2.0 * t)], 0.01, label="weak tail"))
    return out


# --- the skip of quiet record pieces ----------------------------------------------------------------
def _until(samples, tc, gain=1.0, up=1.0, dn=1.0, dt=0.5, ts=0.0):
    s = K.as_samples(np.asarray(samples, dtype=float))
    hi, lo = suffix_extremes(s)
    M = np.array([gain, 0.0, 0.0, ts, ts + dt * (s.size - 1), dt])
    return K._quiet_until(tc, M, s, hi, lo, up, dn)


def test_quiet_until_hand_computed():
    """Samples 0, 0.5, 2, 0.3, 0.1, 0 at dt 0.5 s from t = 1 s, limits 1 (m/s^2) either side."""
    smp = [0.0, 0.5, 2.0, 0.3, 0.1, 0.0]
    # from piece 0 (t = 1): pieces 0 (0 -> 0.5) cannot lift; piece 1 (0.5 -> 2) can: it starts at 1.5 s
    assert _until(smp, 1.0, ts=1.0) == 1.5
    # from piece 1 itself: nothing to skip
    assert _until(smp, 1.5, ts=1.0) == 1.5
    # from piece 3 (t = 2.5): 0.3, 0.1, 0 and the still ground after: never again
    assert _until(smp, 2.5, ts=1.0) == math.inf
    # a sample exactly at the limit does not lift (u > up lifts): gain 0.5 puts 2 at 1.0
    assert _until(smp, 1.0, gain=0.5, ts=1.0) == math.inf
    # a negative gain turns 2 into -2 < -dn: the same piece lifts
    assert _until(smp, 1.0, gain=-1.0, ts=1.0) == 1.5
    # the limits per side: -2 is within dn = 2.5, so nothing lifts
    assert _until(smp, 1.0, gain=-1.0, dn=2.5, ts=1.0) == math.inf
    # not a piece start, before the record, after it, or no suffix extremes (skip off): unchanged
    for tc in (1.2, 0.5, 3.5):
        assert _until(smp, tc, ts=1.0) == tc
    s = K.as_samples(np.array(smp))
    M = np.array([1.0, 0.0, 0.0, 1.0, 3.5, 0.5])
    assert K._quiet_until(2.5, M, s, np.zeros(0), np.zeros(0), 1.0, 1.0) == 2.5


def test_suffix_extremes_hand_computed():
    hi, lo = suffix_extremes(np.array([1.0, -3.0, 2.0, 0.5]))
    assert hi.tolist() == [2.0, 2.0, 2.0, 0.5] and lo.tolist() == [-3.0, -3.0, 0.5, 0.5]
    khi, klo = K.suffix_extremes(K.as_samples(np.array([1.0, -3.0, 2.0, 0.5])))
    assert khi.tolist() == hi.tolist() and klo.tolist() == lo.tolist()


def _stats(model, rec, gains, samples=None, early="outcome", skip=True):
    """Every run (gains x samples) of ``rec``: (runs, N_S) from run_batch, one restitution table per sample."""
    models = [model] if samples is None else samples.models(model)
    kind, M0, smp = rec.kernel_args()
    n_s, n_g = len(models), gains.size
    M = np.tile(M0, (n_s * n_g, 1))
    M[:, K.MA] *= np.tile(gains, n_s)
    P = np.repeat(np.array([m.kernel_vector(early_exit=early) for m in models]), n_g, axis=0)
    return run_batch(models, P, np.full(n_s * n_g, kind), M, smp, np.full(n_s * n_g, rec.end + 20.0), rtol=1e-8,
                     table_row=np.repeat(np.arange(n_s), n_g), skip_quiet=skip)


@pytest.mark.parametrize("body", ["thesis", "scan"])
def test_skip_of_quiet_pieces_changes_no_number(body):
    """The old path (every piece read) and the new one give the same statistics, every one of them
    (outcome, peaks per side, impacts, steps, times), on records ending at rest, at 12 levels from
    0.05 to 1 g, for 3 parameter samples and both early exits; runs come to rest before the record
    ends, so the skip is taken."""
    if body == "thesis":
        model = thesis_model()
        samples = latin_hypercube({"theta_R": (1.78e-2 * STATUE.delta_R, 2.26e-2 * STATUE.delta_R),
                                   "alpha_R": (0.16, 0.19)}, 3, seed=1)
    else:
        model = scan_model()
        e0 = min(model.e_L.values[0], model.e_R.values[0])
        samples = latin_hypercube({"e": (0.9 * e0, min(1.0, 1.05 * e0))}, 3, seed=1)
    gains = np.linspace(0.05, 1.0, 12) * G
    n_rest = 0
    for rec in records_ending_at_rest():
        g = gains / rec.pga
        for early in ("outcome", True):
            new = _stats(model, rec, g, samples, early, skip=True)
            old = _stats(model, rec, g, samples, early, skip=False)
            same = (new == old) | (np.isnan(new) & np.isnan(old))
            assert same.all(), (rec.label, early, np.argwhere(~same)[:5])
            n_rest += int(np.sum(new[:, K.S_T_REST] < rec.end))
        assert (new[:, K.S_OVERTURNED] > 0).any() or body == "scan"
    assert n_rest >= 10           # runs at rest before the record ends: the skip was taken


def test_head_statistics_on_a_record_ending_at_rest():
    """The statistics HEAD (commit 1f198ea, before this work) gave on the thesis statue, an 8 s
    record then 4 s at rest, rtol 1e-8: overturned, peak |theta| right and left (rad), steps,
    impacts, time at rest (s), final time (s), decided on energy."""
    base = motions.synthetic_record(8.0, 0.01, 1.0, seed=1)
    rec = motions.record(np.r_[base.samples, np.zeros(400)], 0.01)
    gains = np.array([0.5, 1.0, 2.0, 3.0, 4.0, 6.0])
    head = {
        "outcome": [
            (0.0, 0.0001324121244165976, 4.09269225169063e-05, 75, 49, 3.453435095475602, 32.0, 0.0),
            (0.0, 0.001360604363635006, 0.0007129462343047015, 485, 205, 4.189347473338219, 32.0, 0.0),
            (0.0, 0.008405180856887599, 0.004247817325054995, 630, 102, math.nan, 6.26, 1.0),
            (0.0, 0.03425439368852097, 0.013286445062370922, 724, 88, math.nan, 6.62, 1.0),
            (1.0, 0.22464180157980848, 0.010731084357421105, 282, 18, math.nan, 2.8419159672104035, 0.0),
            (1.0, 0.22464180157980848, 0.02957985585000064, 280, 14, math.nan, 2.755594206802953, 0.0)],
        True: [
            (0.0, 0.0001324121244165976, 4.09269225169063e-05, 75, 49, 3.453435095475602, 32.0, 0.0),
            (0.0, 0.001360604363635006, 0.0007129462343047015, 485, 205, 4.189347473338219, 32.0, 0.0),
            (0.0, 0.008405180856887599, 0.004247817325054995, 713, 156, 7.12348794156304, 32.0, 0.0),
            (0.0, 0.03425439368852097, 0.013286445062370922, 866, 138, 7.543398367371767, 32.0, 0.0),
            (1.0, 0.22464180157980848, 0.010731084357421105, 282, 18, math.nan, 2.8419159672104035, 0.0),
            (1.0, 0.22464180157980848, 0.02957985585000064, 280, 14, math.nan, 2.755594206802953, 0.0)],
    }
    cols = (K.S_OVERTURNED, K.S_QMAX_R, K.S_QMAX_L, K.S_N_STEPS, K.S_N_IMP, K.S_T_REST, K.S_T_FINAL, K.S_DECIDED)
    for early, rows in head.items():
        S = _stats(thesis_model(), rec, gains, early=early)
        got = S[:, cols]
        ref = np.array(rows, dtype=float)
        assert np.array_equal(got, ref, equal_nan=True), (early, got)


# --- the exact refactors -----------------------------------------------------------------------------
def test_piece_equals_segment():
    """kernel._piece: the same (end, piece) as motion_kernel.segment, to the bit, for every kind of
    motion, before, inside (piece starts, interiors, the last piece) and after it."""
    rec = motions.synthetic_record(3.0, 0.01, 2.0, seed=4)
    cases = [rec.kernel_args(), motions.record([0.0, 1.0, -2.0, 0.5], 0.37, start=0.4).kernel_args(),
             motions.sine_pulse(1.5, 2.0, start=0.3).kernel_args(), motions.rect_pulse(0.7, 0.25, 0.1).kernel_args(),
             motions.free().kernel_args()]
    seg = np.empty(8)
    for kind, M, smp in cases:
        M = M.copy()
        M[K.MA] *= 1.7
        ts, te, dt = M[K.MT0], M[K.MT1], (M[K.MDT] or 0.1)
        times = [ts - 0.5, ts, te, te + 1.0, 0.0] + [ts + k * dt for k in range(40)] + \
            list(np.linspace(ts - 0.1, te + 0.1, 97)) + [np.nextafter(te, 0.0), np.nextafter(ts + dt, 0.0)]
        for t in times:
            end, piece = K._piece(float(t), kind, M, smp)
            end0 = segment(float(t), kind, M, smp, seg)
            assert end == end0 and np.array_equal(np.array(piece), seg, equal_nan=True), (kind, t)


def test_written_out_stages_equal_the_tableau_loop():
    """kernel._step (the stages written out) against the DOP853 loop in Python floats (the
    arithmetic of D8.stage_state / D8.combine: skip the zero coefficients of A, keep those of B)."""
    from statue2model.rocking import dop853 as D8

    model = thesis_model()
    P = tuple(float(x) for x in model.kernel_vector())
    rng = np.random.default_rng(3)
    for _ in range(40):
        t, h = rng.uniform(0, 10), rng.uniform(1e-4, 1e-2)
        th, om = rng.uniform(-0.01, 0.01), rng.uniform(-0.2, 0.2)
        s = 1 if th >= 0 else -1
        reg = int(rng.integers(0, 2))
        seg = (rng.normal(), rng.normal(), t - 0.003, 0.0, 0.0, 0.0, 0.0, math.nan)
        f0 = K._rhs(t, th, s, reg, P, seg)
        Ks = np.zeros((D8.N_STAGES_EXTENDED, 2))
        thn, omn = K._step(t, th, om, f0, h, s, reg, P, seg, Ks)
        ref = np.zeros((D8.N_STAGES_EXTENDED, 2))
        ref[0] = om, f0
        for i in range(1, D8.N_STAGES):
            dth = dom = 0.0
            for j in range(i):
                a = float(D8.A[i, j])
                if a != 0.0:
                    dth += a * ref[j, 0]
                    dom += a * ref[j, 1]
            ref[i] = om + h * dom, K._rhs(t + float(D8.C[i]) * h, th + h * dth, s, reg, P, seg)
        bth = bom = 0.0
        for j in range(D8.N_STAGES):
            bth += float(D8.B[j]) * ref[j, 0]
            bom += float(D8.B[j]) * ref[j, 1]
        assert (thn, omn) == (th + h * bth, om + h * bom)
        assert np.array_equal(Ks[:D8.N_STAGES], ref[:D8.N_STAGES])


def test_restitution_tables_hand_computed():
    a = RockingModel.housner(STATUE, e_L=0.8, e_R=0.9)
    b = RockingModel.housner(STATUE, e_L=0.7, e_R=0.6)
    tables, lengths = restitution_tables([a, b])
    assert tables.shape[0] == 8 and lengths.tolist() == [1] * 8
    assert tables[[1, 3, 5, 7], 0].tolist() == [0.8, 0.9, 0.7, 0.6]


def test_one_batch_per_record_equals_one_per_restitution_pair():
    """fragility._fixed runs a record's rows of every sample of e in one batch; its statistics
    (keep_stats) equal those of one batch per sample (run_batch with the sample's own model) and
    of the SerialExecutor's blocks, and its outcomes those run_fragility reports."""
    from statue2model.compute.executors import SerialExecutor

    model = scan_model()
    e0 = min(model.e_L.values[0], model.e_R.values[0])
    samples = latin_hypercube({"e": (0.9 * e0, min(1.0, 1.05 * e0))}, 4, seed=2)
    recs = records_ending_at_rest()[:2]
    levels = np.linspace(0.1, 1.0, 6) * G
    study = F.FragilityStudy(n_boot=0)
    ims = np.array([F.intensity(r, "pga") for r in recs])
    gains = levels[None, :] / ims[:, None]
    fails, valid, n_int, _, st = F._fixed(model, recs, gains, samples, study, None, 20_000_000, keep_stats=True)
    with SerialExecutor() as ex:
        fails2, _, _, _, st2 = F._fixed(model, recs, gains, samples, study, ex, 20_000_000, keep_stats=True)
    assert np.array_equal(st, st2, equal_nan=True) and np.array_equal(fails, fails2)
    models = samples.models(model)
    fac = samples.im_factors()
    lims = np.array([m.uplift_limits for m in models])
    for r, rec in enumerate(recs):
        kind, M0, smp = rec.kernel_args()
        hi, lo = rec.extremes()
        for s_, m in enumerate(models):
            g = gains[r] * fac[s_]
            M = np.tile(M0, (g.size, 1))
            M[:, K.MA] *= g
            quiet = (g * hi <= lims[s_, 0]) & (-g * lo <= lims[s_, 1])
            S = run_batch(m, np.tile(m.kernel_vector(early_exit="outcome"), (g.size, 1)), np.full(g.size, kind), M,
                          smp, np.full(g.size, rec.end + study.free_time), rtol=study.rtol, quiet=quiet,
                          skip_quiet=False)
            assert np.array_equal(st[r, s_], S, equal_nan=True), (r, s_)
    res = F.run_fragility(model, recs, levels, samples, study)
    assert np.array_equal(res.fails["overturning_fixed"], fails) and res.stats["integrated_fixed"] == n_int
    assert fails.any() and not fails.all()


def test_run_batch_refuses_a_bad_table_row():
    from statue2model.errors import InputError

    a = RockingModel.housner(STATUE, e_L=0.8, e_R=0.9)
    kind, M, smp = motions.sine_pulse(3.0, 2.0).kernel_args()
    P = np.tile(a.kernel_vector(), (2, 1))
    for models, rows, match in (([a, a], None, "table_row"), ([a], [0, 1], "0..0"), ([], [0, 0], "RockingModel")):
        with pytest.raises(InputError, match=match):
            run_batch(models, P, [kind] * 2, np.tile(M, (2, 1)), smp, [5.0, 5.0], table_row=rows)
