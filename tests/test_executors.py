"""Executors: order, progress, errors, and sweeps bit-identical to the in-process run
on local processes and on a Dask cluster (loopback only)."""
import json
import math
import operator
import time

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.hazard import motions
from statue2model.rocking import RockingModel
from statue2model.rocking.spectrum import stability_spectrum
from statue2model.rocking.sweeps import parameter_sweep, variability
from statue2model.errors import InputError
from statue2model.compute.executors import (
    DaskExecutor,
    ProcessExecutor,
    SerialExecutor,
    chunks,
    make_executor,
)
from statue2model.io.files import write_json
from statue2model.geometry.rocking_params import RockingParams

A1 = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
MODEL = RockingModel.imperfect(A1, 0.65, 0.65, 0.13 * A1.delta_L, 0.13 * A1.delta_R, e_L=0.93, e_R=0.93)
FREQS = np.linspace(1, 6, 6)
AMPS = np.linspace(0.05, 1.0, 8) * 9.81
RECORD = motions.synthetic_record(8.0, 0.01, 1.0, seed=3)


def _slow_square(x):
    """Later items finish first, so the order of the results is really tested."""
    time.sleep(0.02 * (5 - x) if x < 5 else 0.0)
    return x * x


def _fail_on_three(x):
    if x == 3:
        raise ValueError("three is bad")
    return x


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  host="127.0.0.1") as c:
        yield c


@pytest.fixture(scope="module")
def processes():
    with ProcessExecutor(2) as ex:
        yield ex


@pytest.fixture(scope="module")
def dask(cluster):
    with DaskExecutor(cluster.scheduler_address) as ex:
        yield ex


@pytest.fixture(params=["serial", "processes", "dask"])
def executor(request):
    if request.param == "serial":
        with SerialExecutor() as ex:
            yield ex
    else:
        yield request.getfixturevalue(request.param)


@pytest.mark.slow
def test_map_keeps_order_and_shows_progress(executor, capsys):
    items = list(range(8))
    assert executor.map(_slow_square, items, desc="squares") == [x * x for x in items]
    assert "squares" in capsys.readouterr().err
    assert executor.map(operator.neg, []) == []
    assert executor.map(math.factorial, (4, 2)) == [24, 2]   # any iterable, builtins pickle too
    assert executor.name in executor.describe() and executor.workers >= 1


def test_map_raises_the_task_error(executor):
    with pytest.raises(ValueError, match="three is bad"):
        executor.map(_fail_on_three, range(6))
    assert executor.map(abs, [-1]) == [1]     # still usable afterwards


def test_describe_and_workers(processes, dask, cluster):
    assert processes.describe() == "processes, 2 workers" and processes.name == "processes"
    assert dask.workers == 2 and dask.describe() == f"dask at {cluster.scheduler_address}, 2 workers"
    assert SerialExecutor().workers == 1 and SerialExecutor().name == "serial"


def test_make_executor_and_chunks():
    with make_executor(workers=3) as ex:
        assert isinstance(ex, ProcessExecutor) and ex.workers == 3
    for bad in (0, -2, 1.5):
        with pytest.raises(InputError, match="workers"):
            make_executor(workers=bad)
    with pytest.raises(InputError, match="not both"):
        make_executor("tcp://127.0.0.1:1", workers=2)
    blocks = chunks(1000, 2)
    assert len(blocks) == 8 and np.array_equal(np.concatenate(blocks), np.arange(1000))
    assert [b.size for b in chunks(20, 4, min_chunk=8)] == [7, 7, 6]
    assert chunks(0, 2) == [] and len(chunks(3, 2)) == 1
    assert [b.tolist() for b in chunks(5, SerialExecutor(), min_chunk=1)] == [[0, 1], [2], [3], [4]]


@pytest.mark.slow
def test_unreachable_scheduler_is_one_clear_line():
    with pytest.raises(InputError, match=r"cannot reach the Dask scheduler at tcp://127\.0\.0\.1:1") as err:
        make_executor("tcp://127.0.0.1:1", timeout=2)
    assert "\n" not in str(err.value)
    with pytest.raises(InputError, match="nonsense"):
        DaskExecutor("nonsense", timeout=1)


def _same(a, b, fields):
    for f in fields:
        x, y = getattr(a, f), getattr(b, f)
        assert x.dtype == y.dtype and np.array_equal(x, y), f


@pytest.mark.slow
def test_sweeps_bit_identical_on_every_executor(processes, dask):
    sp0 = stability_spectrum(MODEL, FREQS, AMPS)
    v0 = variability(MODEL, RECORD, np.linspace(0.5, 3.0, 7))
    s0 = parameter_sweep(MODEL, RECORD.scaled_to_pga(2.0), "theta_R", np.linspace(0.5, 1.5, 6) * MODEL.theta_R)
    e0 = parameter_sweep(MODEL, RECORD.scaled_to_pga(2.0), "e", np.linspace(0.85, 0.95, 4))
    assert len(set(sp0.codes.ravel().tolist())) >= 3 and sp0.n_integrated > 10  # a grid worth comparing
    for ex in (SerialExecutor(), processes, dask):
        sp = stability_spectrum(MODEL, FREQS, AMPS, executor=ex)
        _same(sp, sp0, ("codes", "theta_max_over_delta", "n_impacts"))
        assert sp.n_integrated == sp0.n_integrated
        fields = ("values", "theta_max_over_delta", "theta_max_L", "theta_max_R", "overturned", "codes",
                  "n_impacts")
        _same(variability(MODEL, RECORD, np.linspace(0.5, 3.0, 7), executor=ex), v0, fields)
        _same(parameter_sweep(MODEL, RECORD.scaled_to_pga(2.0), "theta_R",
                              np.linspace(0.5, 1.5, 6) * MODEL.theta_R, executor=ex), s0, fields)
        _same(parameter_sweep(MODEL, RECORD.scaled_to_pga(2.0), "e", np.linspace(0.85, 0.95, 4), executor=ex),
              e0, fields)


@pytest.fixture
def params(tmp_path):
    path = tmp_path / "props.json"
    write_json(path, A1.to_dict())
    return path


@pytest.mark.slow
def test_cli_workers_and_scheduler_give_the_same_numbers(params, tmp_path, capsys, cluster):
    base = ["spectrum", str(params), "--freq", "1:6:6", "--amp", "0.05g:1g:8", "--alpha", "0.65"]
    results = {}
    for name, extra in (("threads", []), ("workers", ["--workers", "2"]),
                        ("dask", ["--scheduler", cluster.scheduler_address])):
        out = tmp_path / f"{name}.json"
        assert main(base + extra + ["--json", str(out)]) == 0
        stdout = capsys.readouterr().out
        results[name] = json.loads(out.read_text())
        if name == "workers":
            assert "running on processes, 2 workers" in stdout
        if name == "dask":
            assert f"running on dask at {cluster.scheduler_address}, 2 workers" in stdout
    for name in ("workers", "dask"):
        for key in ("codes", "theta_max_over_delta", "n_impacts", "counts", "n_integrated"):
            assert results[name][key] == results["threads"][key], (name, key)

    sweep = ["sweep", str(params), "--motion", "synthetic:duration=6,pga=0.25g,seed=2", "--param", "e",
             "--values", "0.85:0.95:3", "--e", "0.9"]
    assert main(sweep + ["--json", str(tmp_path / "e0.json")]) == 0
    assert main(sweep + ["--workers", "2", "--json", str(tmp_path / "e1.json")]) == 0
    e0, e1 = (json.loads((tmp_path / f).read_text()) for f in ("e0.json", "e1.json"))
    assert e0["theta_max_over_delta"] == e1["theta_max_over_delta"] and e0["outcome"] == e1["outcome"]
    capsys.readouterr()

    assert main(["variability", str(params), "--motion", "cosine:amp=1g,freq=2", "--workers", "0"]) == 2
    assert "workers must be" in capsys.readouterr().err


def _pid_after(x):
    """(x, the process that ran it); x > 0 also burns x s of CPU."""
    import os

    t0 = time.process_time()
    while time.process_time() - t0 < x:
        pass
    return x, os.getpid()


def test_inline_first_runs_short_maps_here_and_long_ones_on_the_pool():
    """inline_first: a map of short items runs in this process (no pool started); one whose
    projected CPU time passes the budget hands the rest to the pool; the results keep the order
    and are those of a serial run."""
    import os

    with ProcessExecutor(2, inline_first=1.0) as ex:
        out = ex.map(_pid_after, [0.0] * 5)
        assert [x for x, _ in out] == [0.0] * 5 and {p for _, p in out} == {os.getpid()}
        assert ex._pool is None
        out = ex.map(_pid_after, [0.0, 0.3, 0.3, 0.3, 0.3, 0.3])     # projected 1.5 s after the second item
        pids = [p for _, p in out]
        assert [x for x, _ in out] == [0.0] + [0.3] * 5
        assert pids[:2] == [os.getpid()] * 2 and os.getpid() not in pids[2:] and ex._pool is not None
        out = ex.map(_pid_after, [0.0, 0.0])                    # the pool is up: it takes every item
        assert os.getpid() not in [p for _, p in out]
    with ProcessExecutor(2) as ex:                              # the default: every item on the pool
        assert os.getpid() not in [p for _, p in ex.map(_pid_after, [0.0, 0.0])]
