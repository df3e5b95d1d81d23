"""``statue2model validate`` on an executor: the 2D runs of a test as one compiled batch (the numbers of one
``simulate`` a model, as before), the tests on local processes and on a Dask cluster (loopback only), the
3D scenes one task a test x distinct contact: every P the same as in this process, one test after the other."""
from __future__ import annotations

import json

import pytest

from statue2model.cli import main
from statue2model.compute.executors import DaskExecutor, ProcessExecutor
from statue2model.crosscheck.statue_scene import StatueScene, simulate_statue
from statue2model.geometry.body import load_body
from statue2model.hazard import motions
from statue2model.io.paths import default_scan
from statue2model.pipeline.validate import (
    Contact,
    _distinct,
    band_scenes,
    predict_2d,
    predict_2d_sets,
    predict_3d,
    specimen_models,
)
from statue2model.quantities import G
from statue2model.rocking.engine import simulate


@pytest.fixture(scope="module")
def scan():
    return load_body(default_scan())


def _records():
    """Motions of a lab campaign (sampled records), from quiet to toppling, and two analytic pulses."""
    out = [motions.synthetic_record(6.0, 0.005, pga * G, seed=k) for k, pga in enumerate((0.15, 0.45, 1.6))]
    return out + [motions.sine_pulse(a * G, f) for a, f in ((0.7, 1.5), (1.0, 1.0), (0.3, 4.0))]


def _reference_2d(models, records):
    """The 854e6ff path: one engine.simulate a model a motion."""
    P, L = [], []
    for rec in records:
        rs = [simulate(m, rec) for m in models]
        P.append(sum(bool(r.overturned) for r in rs) / len(rs))
        L.append(sum(r.uplift_time is not None for r in rs) / len(rs))
    return P, L


def _reference_3d(body, records, indices):
    """The 854e6ff path: every scene of the band (with its full mesh) run in this process."""
    scenes = [StatueScene.from_body(body, 0.0, tol=c.tol) for c in body.base.cases]
    out = {}
    for i in indices:
        rs = [simulate_statue(sc, records[i]) for sc in scenes]
        out[i] = (sum(bool(r.overturned) for r in rs) / len(rs), sum(r.uplift_time is not None for r in rs) / len(rs))
    return out


@pytest.mark.parametrize("contact", [Contact(), Contact(0.6, 1.05)])
def test_2d_batch_gives_the_numbers_of_one_simulate_a_model(scan, contact):
    models = specimen_models(scan, 0.0, contact)
    records = _records()
    P, L = predict_2d(models, records)
    P0, L0 = _reference_2d(models, records)
    assert P.tolist() == P0 and L.tolist() == L0
    # a real check: quiet and toppling tests, and a test the models of the band disagree on
    assert 0.0 in P0 and 1.0 in P0 and 0.0 in L0 and 1.0 in L0
    assert any(0.0 < p < 1.0 for p in P0 + L0)


def test_the_identification_grid_as_one_batch_gives_each_contacts_numbers(scan):
    """identify's contacts (alpha x restitution) run together, a batch a motion: each set's P as alone."""
    sets = [specimen_models(scan, 0.0, Contact(a, f)) for a, f in ((1.0, 0.9), (0.7, 1.0), (0.4, 1.05))]
    records = _records()
    got = predict_2d_sets(sets, records)
    for models, (P, L) in zip(sets, got):
        assert (P.tolist(), L.tolist()) == _reference_2d(models, records)
    assert got[0][0].tolist() != got[2][0].tolist()       # the contacts differ: a mix-up would show


def test_a_flat_base_gives_one_scene_a_scan_three(scan, tmp_path):
    import trimesh

    box = trimesh.creation.box(extents=(0.2, 0.3, 0.8))
    box.apply_translation((0, 0, 0.4))
    box.export(tmp_path / "rock.stl")
    body = load_body(tmp_path / "rock.stl", units="m", up="z")
    flat = band_scenes(body, 0.0)
    assert len(flat) == len(body.base.cases) == 3
    assert _distinct(flat) == ([flat[0]], [0, 0, 0])
    scenes = band_scenes(scan, 0.0)
    assert len(scenes) == 3 and _distinct(scenes)[1] == [0, 1, 2]
    assert all(sc.mesh is None for sc in scenes)      # the runs collide the hull: the mesh does not travel


@pytest.fixture(scope="module")
def processes():
    with ProcessExecutor(2) as ex:
        yield ex


@pytest.fixture(scope="module")
def dask():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  host="127.0.0.1") as c, DaskExecutor(c.scheduler_address) as ex:
        yield ex


@pytest.mark.slow
@pytest.mark.parametrize("where", ["processes", "dask"])
def test_the_pool_gives_the_serial_numbers(scan, where, request):
    ex = request.getfixturevalue(where)
    models = specimen_models(scan, 0.0)
    records = _records()
    P, L = predict_2d(models, records)
    Pw, Lw = predict_2d(models, records, ex)
    assert Pw.tolist() == P.tolist() and Lw.tolist() == L.tolist()
    sets = [models, specimen_models(scan, 0.0, Contact(0.5, 1.05))]
    assert [(a.tolist(), b.tolist()) for a, b in predict_2d_sets(sets, records, ex)] == \
        [(a.tolist(), b.tolist()) for a, b in predict_2d_sets(sets, records)]
    short = [records[0], records[4], records[3]]        # quiet, toppling, lifting: a few seconds each in 3D
    here = predict_3d(scan, 0.0, short, [0, 1, 2])
    pooled = predict_3d(scan, 0.0, short, [0, 1, 2], ex)
    assert pooled == here == _reference_3d(scan, short, [0, 1, 2])
    assert here[0] == (0.0, 0.0) and here[1][0] == 1.0


def _campaign(folder):
    """test_validate's box campaign with 6 tests."""
    from test_validate import box_campaign

    return box_campaign(folder, 6)


def _predictions(out):
    r = json.loads((out / "validation.json").read_text())
    return r["rows"], r


@pytest.mark.slow
def test_cli_workers_gives_the_numbers_of_this_process(tmp_path, capsys):
    camp = _campaign(tmp_path)
    args = ["validate", str(camp), "--models", "2d,3d", "--sample", "3"]
    assert main(args + ["--out", str(tmp_path / "here")]) == 0
    assert "running on" not in capsys.readouterr().out
    assert main(args + ["--out", str(tmp_path / "pool"), "--workers", "2"]) == 0
    assert "running on processes, 2 workers" in capsys.readouterr().out
    here, r = _predictions(tmp_path / "here")
    pool, _ = _predictions(tmp_path / "pool")
    assert pool == here
    assert sum("p_topple_3d" in row for row in here) == 3 and r["models"]["3d"]["topple"]["n"] == 3
    assert [row["p_topple_2d"] for row in here][0] == 0.0 and [row["p_topple_2d"] for row in here][-1] == 1.0


def test_workers_and_scheduler_together_are_refused(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        main(["validate", "c.toml", "--out", str(tmp_path / "o"), "--workers", "2", "--scheduler",
              "tcp://127.0.0.1:8786"])
    assert e.value.code == 2 and "not allowed with argument" in capsys.readouterr().err
