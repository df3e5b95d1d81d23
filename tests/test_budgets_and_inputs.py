"""Requests beyond the machine, booleans where numbers are due, workers and their
parent, scheduler trust, BOM-prefixed CSV (issue 9: never trust their input)."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
import tracemalloc
from argparse import Namespace

import numpy as np
import pytest

from statue2model.compute import budget, executors
from statue2model.cli import main
from statue2model.hazard import motions
from statue2model.rocking.identify import read_time_series
from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.pipeline.config import load_config, load_config_text

BLOCK = {"m": 500.0, "h": 0.8, "b_L": 0.2, "b_R": 0.2, "I_G": 120.0}


@pytest.fixture
def params(tmp_path):
    p = tmp_path / "props.json"
    p.write_text(json.dumps(BLOCK))
    return p


# --- A. requests beyond the machine -------------------------------------------------------------
def test_budget_numbers():
    assert budget.MEMORY_BUDGET <= 4 * budget.GiB
    phys = budget.physical_memory()
    if phys:
        assert budget.MEMORY_BUDGET <= phys // 2
    assert budget.human_bytes(1e11 * 40) == "3.6 TiB" and budget.human_bytes(512) == "512 B"
    assert budget.num(1e9) == "1e9" and budget.num(0.01) == "0.01"
    assert budget.check_history(10.0, 0.01, 72) == 1001


def test_rock_t_end_1e9_refused_at_once_without_allocating(params, capsys):
    import statue2model.rocking.engine  # noqa: F401  (imports out of the timing)
    import statue2model.report.dynamics_plots  # noqa: F401

    main(["rock", str(params), "--motion", "cosine:amp=0.5g,freq=2", "--t-end", "1", "--json",
          str(params.parent / "warm.json")])
    capsys.readouterr()
    tracemalloc.start()
    t0 = time.perf_counter()
    rc = main(["rock", str(params), "--motion", "cosine:amp=0.5g,freq=2", "--t-end", "1e9", "--dt-out", "0.01",
               "--json", str(params.parent / "out" / "rock.json")])
    wall = time.perf_counter() - t0
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    err = capsys.readouterr().err
    assert rc == 2 and peak < 20e6, (rc, wall, peak)      # refused before allocating the history
    assert len(err.strip().splitlines()) == 1
    # 1e11 samples x 256 B: 23 TiB; the line names the estimate, the budget and the options that reduce it
    assert "--t-end 1e9 s with output every 0.01 s needs 23 TiB for the history (budget" in err
    assert "use a coarser --dt-out or a shorter --t-end" in err and "MemoryError" not in err
    assert not (params.parent / "out").exists()      # refused before the output folder was made


def test_library_entry_points_refuse_before_allocating():
    from statue2model.rocking import RockingModel
    from statue2model.rocking.engine import simulate
    from statue2model.rocking.spectrum import stability_spectrum
    from statue2model.rocking.sweeps import parameter_sweep, variability

    model = RockingModel.housner(RockingParams.from_dict(BLOCK))
    pulse = motions.cosine_pulse(0.5 * 9.81, 2.0)
    with pytest.raises(InputError, match=r"t_end 1e9 s with output every 0\.002 s needs .*TiB.*budget"):
        simulate(model, pulse, t_end=1e9, dt_out=0.002)
    with pytest.raises(InputError, match=r"100000 x 100000 = 1e\+10 runs is more than 1e\+07 runs"):
        stability_spectrum(model, np.linspace(1, 2, 100_000), np.linspace(0.1, 1, 100_000))
    with pytest.raises(InputError, match="PGA levels"):
        variability(model, pulse, np.linspace(0.1, 1, 20_000_000))
    with pytest.raises(InputError, match="values of alpha"):
        parameter_sweep(model, pulse, "alpha", np.ones(20_000_000))
    with pytest.raises(InputError, match=r"synthetic record of 1e9 s at dt 0\.01 s needs .*use a shorter duration"):
        motions.parse_spec("synthetic:duration=1e9")
    with pytest.raises(InputError, match="use a coarser dt"):
        motions.cosine_pulse(1.0, 1e-9).sampled(1e-6)


def test_isolator_histories_refused_before_allocating():
    from statue2model.rocking import RockingModel
    from statue2model.isolator.coupled import simulate_coupled
    from statue2model.isolator.device import Isolator
    from statue2model.isolator.time_history import simulate

    iso = Isolator(R=1.0, r=0.01, M=800.0, mu=0.0073)
    pulse = motions.cosine_pulse(1.0, 1.0)
    with pytest.raises(InputError, match="plate history .*coarser dt_out"):
        simulate(iso, pulse, t_end=1e9, dt_out=0.005)
    model = RockingModel.housner(RockingParams.from_dict(BLOCK))
    with pytest.raises(InputError, match="coupled history"):
        simulate_coupled(iso, model, pulse, t_end=1e9, dt_out=0.005)


def test_project_file_grid_of_1e10_cells_refused(tmp_path, capsys):
    text = '[dynamics]\nfreq = "0.5:10:100000"\namp = "0.02g:1g:100000"\n'
    with pytest.raises(InputError, match=r"\[dynamics\] freq x amp .*100000 x 100000 = 1e\+10 runs .*5\.8 TiB"):
        load_config_text(text, "p.toml")
    p = tmp_path / "project.toml"
    p.write_text(text)
    assert main(["run", "--config", str(p), "--stages", "params", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "fewer frequencies or amplitudes" in err
    with pytest.raises(InputError, match=r"\[crosscheck\] motion of 20000 s .* needs 13 GiB"):
        load_config_text('[crosscheck]\nmotion = "synthetic:duration=20000"\n', "p.toml")
    # the defaults pass
    load_config(None)
    load_config_text('[dynamics]\nfreq = "0.5:10:1000"\namp = "0.02g:1g:1000"\n')


# --- B. booleans where numbers are due ---------------------------------------------------------------
@pytest.mark.parametrize("line", ["[prototype]\nboard = true", "[scan]\ndensity = false",
                                  "[prototype]\nsheet = [true, 1.25]", "[isolator]\nmu = true",
                                  "[crosscheck]\ndt = true", "[run]\nworkers = true"])
def test_project_file_booleans_refused(line):
    with pytest.raises(InputError, match="true|whole number"):
        load_config_text(line + "\n", "p.toml")


def test_project_file_booleans_still_read_where_due():
    assert load_config_text("[prototype]\ncompensate = true\n").prototype.compensate is True
    with pytest.raises(InputError, match="true or false"):
        load_config_text("[prototype]\ncompensate = 1\n")


def test_params_json_booleans_and_strings_refused(tmp_path, capsys):
    for bad in (True, "1.2", None):
        with pytest.raises(InputError, match="rocking parameter m must be a number"):
            RockingParams.from_dict({**BLOCK, "m": bad})
    assert RockingParams.from_dict({**BLOCK, "m": np.float32(500)}).m == 500.0
    p = tmp_path / "p.json"
    p.write_text(json.dumps({**BLOCK, "h": True}))
    assert main(["rock", str(p), "--motion", "cosine:amp=0.5g,freq=2"]) == 2
    assert "rocking parameter h must be a number, got true" in capsys.readouterr().err


# --- C. workers ---------------------------------------------------------------------------------
def test_workers_capped_to_the_cores_with_a_note(capsys):
    from statue2model.cli.dynamics import _executor

    cores = executors.available_cores()
    assert cores <= (os.cpu_count() or 1)
    with _executor(Namespace(workers=64, scheduler=None)) as ex:
        assert ex.workers == cores and ex.asked == 64
    out = capsys.readouterr().out
    assert f"running on processes, {cores} worker" in out and "64 asked: capped to the" in out
    with executors.make_executor(workers=1, cap=True) as ex:
        assert ex.describe() == "processes, 1 worker"      # no note when not capped
    assert executors.ProcessExecutor(64).workers == 64     # the library does as asked


PARENT = """
import time
from statue2model.compute.executors import ProcessExecutor
if __name__ == "__main__":
    ex = ProcessExecutor(2)
    ex.map(time.sleep, [0.1, 0.1, 0.1, 0.1])
    print(" ".join(str(p) for p in ex._pool._processes), flush=True)
    time.sleep(120)
"""


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] not in ("Z", "X")
    except FileNotFoundError:
        return False


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_workers_end_when_their_parent_is_killed(tmp_path):
    script = tmp_path / "parent.py"
    script.write_text(textwrap.dedent(PARENT))
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        pids = [int(x) for x in line.split()]
        assert len(pids) == 2 and all(_alive(p) for p in pids)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    t0 = time.monotonic()
    while any(_alive(p) for p in pids) and time.monotonic() - t0 < 5:
        time.sleep(0.05)
    left = [p for p in pids if _alive(p)]
    for p in left:  # pragma: no cover - clean up after a failure
        os.kill(p, signal.SIGKILL)
    assert not left, f"workers {left} outlived their killed parent"


def test_scheduler_from_a_project_file_needs_confirmation(tmp_path, capsys, monkeypatch):
    def no_connection(*a, **k):  # pragma: no cover - reached only by the bug
        raise AssertionError("tried to connect")

    monkeypatch.setattr(executors, "DaskExecutor", no_connection)
    p = tmp_path / "project.toml"
    p.write_text('[run]\nscheduler = "tcp://10.1.2.3:8786"\n')
    t0 = time.perf_counter()
    rc = main(["run", "--config", str(p), "--stages", "params", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and time.perf_counter() - t0 < 5
    assert len(err.strip().splitlines()) == 1
    assert "[run] scheduler = 'tcp://10.1.2.3:8786' is not on this machine" in err
    assert "--scheduler tcp://10.1.2.3:8786" in err
    assert not (tmp_path / "o").exists()
    for addr, local in (("tcp://127.0.0.1:8786", True), ("127.3.4.5:1", True), ("tcp://[::1]:8786", True),
                        ("tcp://localhost:8786", True), ("tcp://10.1.2.3:8786", False),
                        ("tcp://scheduler.example.org:8786", False), ("tcp://127.0.0.1.evil.org:1", False)):
        assert executors.is_local_address(addr) is local, addr
    with pytest.raises(InputError, match="not a Dask scheduler address"):
        executors.is_local_address("http://x:1")


def test_dask_tasks_carry_their_inputs_and_retry():
    import inspect

    src = inspect.getsource(executors.DaskExecutor.map)
    assert "scatter" not in src and "retries=self.retries" in src and executors.DaskExecutor.retries >= 1


@pytest.mark.slow
def test_a_lost_scheduler_is_one_line(caplog):
    import math

    distributed = pytest.importorskip("distributed")
    # worker in its own process: an in-process worker leaves threads in this one (the 3D tests after it
    # are sensitive to that)
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None)
    try:
        ex = executors.DaskExecutor(cluster.scheduler_address, timeout=2)
        assert ex.map(math.factorial, [3, 4]) == [6, 24]
    finally:
        cluster.close()
    try:
        with pytest.raises(InputError, match="lost the Dask scheduler at .* the sweep did not finish") as err:
            ex.map(math.factorial, [3, 4])
        assert "\n" not in str(err.value)
        assert not any("reconnect to scheduler" in r.getMessage() for r in caplog.records)
    finally:
        ex.close()


# --- D. BOM-prefixed CSV --------------------------------------------------------------------------
@pytest.mark.parametrize("header", ["", "t_s,acc_m_s2\n"])
def test_bom_csv_motion_read_like_the_plain_one(tmp_path, header):
    t = np.arange(50) * 0.01
    a = np.sin(7 * t) + 0.5
    body = header + "".join(f"{x:.2f},{y:.6f}\n" for x, y in zip(t, a))
    plain, bom = tmp_path / "plain.csv", tmp_path / "bom.csv"
    plain.write_text(body, encoding="utf-8")
    bom.write_text(body, encoding="utf-8-sig")
    assert bom.read_bytes()[:3] == b"\xef\xbb\xbf"
    m0, m1 = motions.read_record(plain), motions.read_record(bom)
    assert m1.samples.size == m0.samples.size == 50 and m1.start == m0.start == 0.0
    np.testing.assert_array_equal(m1.samples, m0.samples)
    t0, y0 = read_time_series(plain, "rotation")
    t1, y1 = read_time_series(bom, "rotation")
    np.testing.assert_array_equal(t0, t1)
    np.testing.assert_array_equal(y0, y1)
