"""``statue2model validate``: replay a shake-table campaign and say how often the models were right.

For a campaign (statue2model.assessment.campaign: the specimen's scan, the table's axis in it, the tests'
motion files and observed outcomes) it builds the specimen's Body (the scan read, repaired and stood up),
its rocking geometry along the table's axis (geometry/rocking_params.py: where the rays leave the
footprint), and predicts each test:

2D   P(topple) and P(lift) over SAMPLES: the base contact at half, at and at double its tolerance
     (geometry/base.py: the scan's contact band; each contact hull gives its own b_L, b_R along the axis)
     x the restitution at E_FACTORS of eq. 15's (the scatter of Table 23): 9 runs of the rocking engine
     per test. The model is Housner's, or the imperfect one with the identified alpha.
3D   the PyBullet scene (crosscheck/statue_scene.py) on a sample of the tests (``sample``, spread over
     the tests' PGAs): the body stood on the contact of each end of the band (the scan's points within
     tol / 2, tol and 2 tol of the lowest put on the floor, the 2D model's hulls), one run each: P is
     the fraction of the 3 that topple (lift). eq. 15's restitution is the scene's own (a plastic
     contact and the geometry), so the 3D sample has no restitution factor.

The decision rule: a model predicts the outcome when P >= DECISION (0.5). Scores per model and outcome
(assessment/campaign.py scores): the confusion counts, accuracy, precision, recall with 95 % Wilson
intervals, and the Brier score of P.

``identify``: another campaign (another object, the same kind of set-up) on which the contact's effective
parameters are identified before predicting this one, as the thesis does with a prototype: the uplift
reduction alpha (alpha_L = alpha_R: the real contact lifts at alpha times the scanned geometry's uplift, the
thesis' imperfect model, eqs. 33-38) and a factor on the restitution, on the grid ALPHAS x E_GRID, the
pair with the best balanced accuracy of the topple prediction (ties: the lower Brier score). The identified
values and the other campaign's scores with them are reported.

Writes ``OUT/validation.json`` (per test: the observed outcome, each model's P and prediction, the table's
PGA and PGV; the scores; the identification) and ``OUT/validation.html`` (the scores, the confusion
matrices, outcome against PGA and PGV, the misses listed).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import InputError

E_FACTORS = (0.95, 1.0, 1.05)
"""The restitution at these multiples of eq. 15's (Table 23's scatter, as the fragility study samples it)."""
DECISION = 0.5
"""A model predicts the outcome when its P >= DECISION."""
ALPHAS = (1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3)
E_GRID = (0.9, 1.0, 1.05)
MODELS = ("2d", "3d")
SAMPLE_3D = 10
"""Tests run in 3D by default (spread over the PGAs)."""


@dataclass(frozen=True)
class Contact:
    """What the prediction assumes of the contact: the uplift reduction alpha and the restitution factor."""

    alpha: float = 1.0
    e_factor: float = 1.0
    source: str = "the scan as it is (no identification)"


def _body(campaign):
    from ..geometry.body import load_body

    s = campaign.specimen
    return load_body(s.scan, units=s.units, up=s.up, density=None if s.mass is not None else s.density, mass=s.mass)


def specimen_models(body, direction: float, contact: Contact = Contact()) -> list:
    """The 2D models of the samples (module docstring): one per contact hull x restitution factor."""
    from ..rocking.model import RockingModel

    p0 = body.rocking(direction)
    hulls = [c for c in body.base.cases] if body.base is not None else [None]
    models = []
    for case in hulls:
        p = p0
        if case is not None:
            b_L, b_R = case.b(body.mass.com, direction)
            if b_L <= 0 or b_R <= 0:
                continue
            p = replace(p0, b_L=b_L, b_R=b_R)
        for f in E_FACTORS:
            k = f * contact.e_factor
            e_L, e_R = min(1.0, p.e_L * k), min(1.0, p.e_R * k)
            if contact.alpha >= 1.0:
                models.append(RockingModel.housner(p, e_L=e_L, e_R=e_R))
            else:
                models.append(RockingModel.imperfect(p, contact.alpha, contact.alpha, e_L=e_L, e_R=e_R))
    if not models:
        raise InputError("the specimen's centre of mass lies outside every contact hull: it would not stand")
    return models


def _pooled(executor, n_tasks: int) -> bool:
    """Whether ``n_tasks`` tasks go to ``executor``'s workers: a Dask cluster always, local processes when
    there are 2 or more (one would only add a process start to this process's work), never one task alone."""
    if executor is None or n_tasks < 2:
        return False
    return getattr(executor, "name", "") == "dask" or getattr(executor, "workers", 1) >= 2


def _run_2d(task) -> np.ndarray:
    """P(topple) and P(lift) over each set of models, of each motion of one block of tests: ``task`` =
    (model sets, motions); returns (sets, len(motions), 2). Each motion's runs, every model of every set, are
    one batch of the compiled kernel (rocking/batch.py run_batch: a row per model, the motion's samples
    shared), the numbers of one ``simulate`` per model (rocking/engine.py: the same kernel, rtol, end time
    motion.end + FREE_TIME and the skip of a ground that cannot lift the body). Module level so that it
    pickles (an executor's task)."""
    from ..rocking import kernel as K
    from ..rocking.batch import run_batch
    from ..rocking.engine import FREE_TIME, quiet_ground

    sets, motions = task
    models = [m for ms in sets for m in ms]
    ends = np.cumsum([0] + [len(ms) for ms in sets])
    n = len(models)
    P = np.array([m.kernel_vector() for m in models])
    rows = np.arange(n, dtype=np.int64)
    out = np.empty((len(sets), len(motions), 2))
    for j, motion in enumerate(motions):
        kind, M, samples = motion.kernel_args()
        hi, lo = motion.extremes()
        quiet = np.array([quiet_ground(m, hi, lo) for m in models])
        S = run_batch(models, P, kind, np.tile(M, (n, 1)), samples, np.full(n, motion.end + FREE_TIME),
                      quiet=quiet, table_row=rows)
        top, lift = S[:, K.S_OVERTURNED] > 0, np.isfinite(S[:, K.S_T_UPLIFT])
        for k in range(len(sets)):
            r = slice(ends[k], ends[k + 1])
            out[k, j] = np.count_nonzero(top[r]) / len(sets[k]), np.count_nonzero(lift[r]) / len(sets[k])
    return out


def predict_2d_sets(sets, motions, executor=None) -> list[tuple[np.ndarray, np.ndarray]]:
    """[(P(topple), P(lift)) per motion] over each set of sample models (the contacts of an identification):
    here, one batch a motion (every set's models) on one thread; with an executor of 2 workers or more,
    blocks of motions (compute/executors.py chunks, about 4 a worker) on its workers, each motion sent once.
    The same numbers either way."""
    motions = list(motions)
    if not motions:
        return [(np.zeros(0), np.zeros(0)) for _ in sets]
    if not _pooled(executor, len(motions)):
        from ..compute.executors import SerialExecutor

        # one numba thread: a batch of a few rows a motion in 2 threads meets at a barrier each motion, and on a
        # loaded machine each barrier waits for a descheduled thread (200 tests at load 15: 8 s CPU, 65 s wall)
        with SerialExecutor() as here:
            res = here.map(_run_2d, [(sets, motions)])[0]
    else:
        from ..compute.executors import chunks

        blocks = chunks(len(motions), executor, min_chunk=1)
        parts = executor.map(_run_2d, [(sets, [motions[i] for i in b]) for b in blocks], desc="validate: 2D")
        res = np.concatenate(parts, axis=1)
    return [(res[k, :, 0].copy(), res[k, :, 1].copy()) for k in range(len(sets))]


def predict_2d(models, motions, executor=None) -> tuple[np.ndarray, np.ndarray]:
    """(P(topple), P(lift)) per motion over the sample models (:func:`predict_2d_sets` of one set)."""
    return predict_2d_sets([models], motions, executor)[0]


def _sample(pgas: np.ndarray, k: int) -> list[int]:
    """``k`` test indices spread over the PGAs (their ranks, evenly)."""
    order = np.argsort(pgas, kind="stable")
    if k >= len(order):
        return sorted(int(i) for i in order)
    pick = np.unique(np.round(np.linspace(0, len(order) - 1, k)).astype(int))
    return sorted(int(order[i]) for i in pick)


def _run_3d(task) -> tuple[bool, bool]:
    """One PyBullet run: ``task`` = (StatueScene, motion); (overturned, lifted). Module level so that it pickles
    (an executor's task)."""
    from ..crosscheck.statue_scene import simulate_statue

    scene, motion = task
    r = simulate_statue(scene, motion)
    return bool(r.overturned), r.uplift_time is not None


def band_scenes(body, direction: float) -> list:
    """The PyBullet scenes of the contact band's ends (module docstring; the nominal contact alone without a
    band), each without its full mesh (the runs collide the convex hull: the scene then pickles in a few kB)."""
    from ..crosscheck.statue_scene import StatueScene

    tols = [c.tol for c in body.base.cases] if body.base is not None else [None]
    scenes = []
    for t in tols:
        try:
            scenes.append(replace(StatueScene.from_body(body, direction, tol=t), mesh=None))
        except InputError:
            continue              # a contact the body cannot stand on (G outside its hull) is no scene
    if not scenes:
        raise InputError("the specimen cannot stand on any contact of its band: no 3D scene")
    return scenes


def _distinct(scenes) -> tuple[list, list[int]]:
    """(the distinct scenes, the distinct scene of each): the ends of a band whose contact hulls are the same
    (a flat base) give one scene, run once (a run is deterministic: the same scene, the same result)."""
    import pickle

    keys, uniq, which = {}, [], []
    for sc in scenes:
        k = pickle.dumps(sc)
        if k not in keys:
            keys[k] = len(uniq)
            uniq.append(sc)
        which.append(keys[k])
    return uniq, which


def predict_3d(body, direction: float, motions, indices, executor=None) -> dict:
    """{test index: (P(topple), P(lift))} of the PyBullet scene on the tests ``indices``, over the
    scenes of the contact band (module docstring; the nominal contact alone without a band). One task per
    test x distinct scene, here one after the other, or with an executor of 2 workers or more on its workers
    (the longest motions handed out first). The same numbers either way."""
    scenes = band_scenes(body, direction)
    uniq, which = _distinct(scenes)
    indices = list(indices)
    pairs = [(i, u) for i in indices for u in range(len(uniq))]
    pairs.sort(key=lambda iu: -motions[iu[0]].end)             # stable: the longest runs first
    tasks = [(uniq[u], motions[i]) for i, u in pairs]
    if not _pooled(executor, len(tasks)):
        res = [_run_3d(t) for t in tasks]
    else:
        res = executor.map(_run_3d, tasks, desc="validate: 3D")
    got = dict(zip(pairs, res))
    out = {}
    for i in indices:
        rs = [got[(i, u)] for u in which]
        out[i] = (sum(r[0] for r in rs) / len(rs), sum(r[1] for r in rs) / len(rs))
    return out


def _read_one(task) -> tuple:
    """One test's motion file: ``task`` = (path, LabFormat, label); (GroundMotion, notes, PGV m/s). Module level
    so that it pickles (an executor's task)."""
    from ..assessment.fragility import pgv
    from ..hazard.lab import read_lab_motion

    path, fmt, label = task
    m, notes = read_lab_motion(path, fmt, label=label)
    return m, notes, pgv(m)


def _read_motions(campaign, executor=None) -> tuple[list, list[list[str]], np.ndarray]:
    """(motions, notes, PGVs in m/s) of the campaign's tests, read here or, with an executor, on its workers
    (a lab file of 40 s is 8000 lines of text: reading is most of a 2D campaign's time)."""
    tasks = [(t.file, campaign.motion, t.name) for t in campaign.tests]
    if _pooled(executor, len(tasks)):
        res = executor.map(_read_one, tasks, desc="validate: motion files")
    else:
        res = [_read_one(t) for t in tasks]
    return [r[0] for r in res], [r[1] for r in res], np.array([r[2] for r in res], dtype=float)


def _balanced(obs, pred) -> float:
    obs, pred = np.asarray(obs, bool), np.asarray(pred, bool)
    pos, neg = obs.sum(), (~obs).sum()
    parts = []
    if pos:
        parts.append((pred & obs).sum() / pos)
    if neg:
        parts.append((~pred & ~obs).sum() / neg)
    return float(np.mean(parts)) if parts else 0.0


def identify(campaign_path, executor=None, say=lambda m: None) -> dict:
    """The contact parameters identified on the campaign at ``campaign_path`` (module docstring)."""
    from ..assessment.campaign import load_campaign, scores

    other = load_campaign(campaign_path)
    body = _body(other)
    motions, _, _ = _read_motions(other, executor)
    obs = [t.toppled for t in other.tests]
    outcome = "topple"
    if len(set(obs)) < 2 and all(t.lifted is not None for t in other.tests) and \
            len({t.lifted for t in other.tests}) == 2:
        obs, outcome = [t.lifted for t in other.tests], "lift"      # the outcome that varies there
    grid = [(a, f) for a in ALPHAS for f in E_GRID]
    say(f"identify: {len(grid)} contacts (alpha x restitution) on {len(motions)} tests")
    sets = [specimen_models(body, other.specimen.direction, Contact(a, f)) for a, f in grid]
    best, rows = None, []
    for (a, f), (P_top, P_lift) in zip(grid, predict_2d_sets(sets, motions, executor)):
        P = P_top if outcome == "topple" else P_lift
        pred = P >= DECISION
        s = scores(obs, pred, P)
        row = {"alpha": a, "e_factor": f, "balanced_accuracy": _balanced(obs, pred), "brier": s["brier"],
               "recall": s["recall"]["value"], "precision": s["precision"]["value"]}
        rows.append(row)
        key = (row["balanced_accuracy"], -row["brier"])
        if best is None or key > best[0]:
            best = (key, row)
    chosen = best[1]
    return {"campaign": other.name, "tests": len(other.tests), "outcome": outcome, "alpha": chosen["alpha"],
            "e_factor": chosen["e_factor"], "balanced_accuracy": chosen["balanced_accuracy"],
            "brier": chosen["brier"], "grid": rows,
            "rule": "alpha_L = alpha_R and a factor on eq. 15's restitution over "
                    f"{len(ALPHAS)} x {len(E_GRID)} values; the best balanced accuracy of the {outcome} prediction "
                    "(topple where that campaign has toppled and standing tests, else lift), then the lower Brier "
                    "score"}


def validate(campaign_path, out, models=("2d",), identify_path=None, sample: int = SAMPLE_3D, executor=None,
             say=lambda m: None, contact: Contact | None = None) -> dict:
    """Replay the campaign at ``campaign_path``; write OUT/validation.json and validation.html; return the record.
    ``contact``: the contact to assume (Python only; ``identify_path`` identifies it instead)."""
    from ..assessment.campaign import load_campaign
    from ..io.files import write_json
    from ..quantities import G

    bad = [m for m in models if m not in MODELS]
    if bad or not models:
        raise InputError(f"--models must name {' and/or '.join(MODELS)}, got {','.join(models) or 'none'}")
    campaign = load_campaign(campaign_path)
    out = Path(out)
    contact = contact or Contact()
    ident = None
    if identify_path is not None:
        ident = identify(identify_path, executor, say)
        contact = Contact(ident["alpha"], ident["e_factor"], f"identified on campaign {ident['campaign']}")
    say(f"validate: {len(campaign.tests)} tests of {campaign.name}")
    body = _body(campaign)
    direction = campaign.specimen.direction
    p0 = body.rocking(direction)
    motions, notes, pgvs = _read_motions(campaign, executor)
    pgas = np.array([m.pga for m in motions])
    tests = campaign.tests
    rows = [{"name": t.name, "file": t.file.name, "toppled": t.toppled, "lifted": t.lifted,
             "peak_rotation": t.peak_rotation, "pga": float(a), "pga_g": float(a / G), "pgv": float(v),
             "notes": n} for t, a, v, n in zip(tests, pgas, pgvs, notes)]
    result = {"schema": "statue2model.validation/1", "campaign": campaign.name, "tests": len(tests),
              "specimen": {"scan": campaign.specimen.scan.name, "mass": body.mass.mass, "direction_deg": direction,
                           "h": p0.h, "b_L": p0.b_L, "b_R": p0.b_R, "a_L": p0.a_L, "a_R": p0.a_R,
                           "obliquity_L": p0.obliquity_L, "obliquity_R": p0.obliquity_R,
                           "contact_band": None if body.base is None else
                           body.base.rows(body.mass.com, direction, p0.g)},
              "contact": {"alpha": contact.alpha, "e_factor": contact.e_factor, "source": contact.source},
              "identification": ident, "decision": f"A model predicts the outcome when P >= {DECISION:g}",
              "models": {}, "rows": rows}
    if "2d" in models:
        say("validate: 2D on every test")
        smodels = specimen_models(body, direction, contact)
        P, L = predict_2d(smodels, motions, executor)
        for r, p, q in zip(rows, P, L):
            r["p_topple_2d"], r["topple_2d"] = float(p), bool(p >= DECISION)
            r["p_lift_2d"], r["lift_2d"] = float(q), bool(q >= DECISION)
        result["models"]["2d"] = _model_scores(tests, rows, "2d", range(len(tests)),
                                               f"{len(smodels)} runs a test: the contact hulls x restitution "
                                               f"{', '.join(f'{f:g}' for f in E_FACTORS)}")
    if "3d" in models:
        idx = _sample(pgas, int(sample))
        say(f"validate: 3D on {len(idx)} of {len(tests)} tests")
        res = predict_3d(body, direction, motions, idx, executor)
        for i, (top, lift) in res.items():
            rows[i].update(p_topple_3d=float(top), topple_3d=bool(top >= DECISION), p_lift_3d=float(lift),
                           lift_3d=bool(lift >= DECISION))
        n_band = len(body.base.cases) if body.base is not None else 1
        result["models"]["3d"] = _model_scores(tests, rows, "3d", idx,
                                               f"PyBullet runs on the {n_band} contacts of the band a test, "
                                               f"{len(idx)} tests spread over the PGAs")
    write_json(out / "validation.json", result)
    from ..report.validation_page import write_validation_page

    write_validation_page(result, out / "validation.html", out)
    return result


def _model_scores(tests, rows, model: str, indices, how: str) -> dict:
    from ..assessment.campaign import scores

    idx = list(indices)
    obs = [tests[i].toppled for i in idx]
    out = {"tests": len(idx), "how": how,
           "topple": scores(obs, [rows[i][f"topple_{model}"] for i in idx], [rows[i][f"p_topple_{model}"] for i in idx])}
    lifted = [i for i in idx if tests[i].lifted is not None]
    if lifted:
        out["lift"] = scores([tests[i].lifted for i in lifted], [rows[i][f"lift_{model}"] for i in lifted],
                             [rows[i][f"p_lift_{model}"] for i in lifted])
    out["misses"] = [rows[i]["name"] for i in idx if rows[i][f"topple_{model}"] != tests[i].toppled]
    return out

