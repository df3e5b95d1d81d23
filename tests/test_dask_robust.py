"""The Dask cluster of docs/run.md: loopback only, and one clear line when it fails (issue #24, item 9).

The cluster is started with the very commands of the docs' recipe (the bash block of
docs/run.md's "Scale out"), on free ports in place of 8786 / 8787 (other tests may hold
those), and

* every listening socket of the scheduler, the worker's nanny and the worker is on
  127.0.0.1 (psutil; before: the worker's port, which runs pickled work, and the
  dashboards listened on every interface);
* all workers gone during a sweep: one line after STATUE2MODEL_WORKER_TIMEOUT s, status 2
  (before: waited forever without a word);
* the scheduler lost during a sweep: one line, status 2, no Dask traceback (before:
  Dask's own 20-line traceback came first);
* a cluster without any worker when connecting: one line after the timeout.

Only loopback addresses are used.
"""
from __future__ import annotations

import os
import re
import shlex
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow
distributed = pytest.importorskip("distributed")
psutil = pytest.importorskip("psutil")

RUN_MD = Path(__file__).resolve().parents[1] / "docs" / "run.md"
BIN = Path(sys.executable).parent
ENV = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
ENV.pop("STATUE2MODEL_WORKER_TIMEOUT", None)


def recipe() -> tuple[list[str], list[str]]:
    """The `dask scheduler` and `dask worker` command lines of docs/run.md's bash blocks."""
    text = RUN_MD.read_text(encoding="utf-8")
    lines = [ln.strip() for body in re.findall(r"^```bash\n(.*?)^```", text, re.S | re.M)
             for ln in body.splitlines()]
    sched = [ln for ln in lines if ln.startswith("dask scheduler")]
    work = [ln for ln in lines if ln.startswith("dask worker")]
    assert len(sched) == 1 and len(work) == 1, "docs/run.md: one `dask scheduler` and one `dask worker` line"

    def argv(line: str) -> list[str]:
        return shlex.split(line.split("#")[0].rstrip().removesuffix("&"))

    return argv(sched[0]), argv(work[0])


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cluster:
    """The recipe's scheduler and (optionally) worker, on free ports; killed on exit."""

    def __init__(self, worker: bool = True):
        sched, work = recipe()
        self.port, dash = _free_port(), _free_port()

        def ports(argv):
            return [a.replace("8786", str(self.port)).replace("8787", str(dash)) for a in argv]

        self.address = f"tcp://127.0.0.1:{self.port}"
        self.scheduler = self._start(ports(sched))
        self.worker = self._start(ports(work)) if worker else None
        self._wait(worker)

    @staticmethod
    def _start(argv: list[str]) -> subprocess.Popen:
        exe = BIN / argv[0]
        return subprocess.Popen([str(exe if exe.exists() else argv[0]), *argv[1:]], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL, env=ENV, start_new_session=True)

    def _wait(self, worker: bool) -> None:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            if self.scheduler.poll() is not None:
                pytest.fail(f"the recipe's scheduler exited ({self.scheduler.returncode})")
            try:
                with distributed.Client(self.address, timeout=2, set_as_default=False) as c:
                    if not worker or sum(c.nthreads().values()) >= 1:
                        return
            except (OSError, TimeoutError):
                pass
            time.sleep(0.3)
        pytest.fail("the recipe's cluster did not come up in 60 s")

    def processes(self) -> list:
        out = []
        for p in (self.scheduler, self.worker):
            if p is not None and p.poll() is None:
                root = psutil.Process(p.pid)
                out += [root] + root.children(recursive=True)
        return out

    @staticmethod
    def kill(p: subprocess.Popen | None) -> None:
        if p is not None and p.poll() is None:
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait(10)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.kill(self.worker)
        self.kill(self.scheduler)


@pytest.fixture(scope="module")
def params_json(tmp_path_factory) -> str:
    path = tmp_path_factory.mktemp("dask") / "params.json"
    path.write_text('{"m": 407.4, "h": 0.7316, "b_L": 0.3110, "b_R": 0.2026, "I_G": 60.0}')
    return str(path)


def _spectrum(params_json, address, out, env=ENV) -> subprocess.Popen:
    """A sweep of 90000 pulses (a few seconds on one worker) on the cluster."""
    return subprocess.Popen([sys.executable, "-m", "statue2model", "spectrum", params_json, "--freq", "0.2:4:300",
                             "--amp", "0.05g:1.5g:300", "--scheduler", address, "--json", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)


def _lines(stderr: str) -> list[str]:
    """stderr without the progress bar (redrawn with carriage returns)."""
    pieces = (s.strip() for s in re.split(r"[\r\n]", stderr))
    return [s for s in pieces if s and not re.search(r"\d+/\d+ \[|task/s", s)]


def test_recipe_listens_on_loopback_only(params_json, tmp_path):
    sched, work = recipe()
    assert "--host" in sched and "--host" in work          # the recipe itself names the interface
    with Cluster() as c:
        procs = c.processes()
        assert len(procs) >= 3, procs                         # scheduler, nanny, worker
        listening = [(p.pid, " ".join(p.cmdline()[:3]), conn.laddr) for p in procs
                     for conn in p.net_connections(kind="inet") if conn.status == psutil.CONN_LISTEN]
        assert len(listening) >= 4, listening                 # scheduler, dashboard, nanny, worker
        wide = [x for x in listening if x[2].ip != "127.0.0.1"]
        assert not wide, f"listening beyond 127.0.0.1: {wide}"
        # and the cluster works: a small sweep on it
        p = subprocess.run([sys.executable, "-m", "statue2model", "spectrum", params_json, "--freq", "0.5:2:3",
                            "--amp", "0.1g:0.5g:3", "--scheduler", c.address, "--json", str(tmp_path / "s.json")],
                           capture_output=True, text=True, env=ENV, timeout=120)
        assert p.returncode == 0, p.stderr[-1500:]
        assert "running on dask" in p.stdout


def _kill_during_run(params_json, out: Path, which: str, env=ENV):
    """Start a sweep on a fresh cluster, kill its ``which`` ("scheduler" or "worker") once the
    sweep runs; returns (the finished process, its stderr, seconds from the kill to the exit)."""
    with Cluster() as c:
        p = _spectrum(params_json, c.address, out, env=env)
        try:
            assert "running on dask" in p.stdout.readline()
            time.sleep(0.5)
            c.kill(getattr(c, which))
            t0 = time.monotonic()
            _, err = p.communicate(timeout=90)
        finally:
            if p.poll() is None:
                p.kill()
        return p, err, time.monotonic() - t0


def test_scheduler_lost_is_one_line(params_json, tmp_path):
    p, err, took = _kill_during_run(params_json, tmp_path / "s.json", "scheduler")
    assert p.returncode == 2, (p.returncode, err[-2000:])
    lines = _lines(err)
    assert len(lines) == 1 and re.match(r"statue2model: error: lost the Dask scheduler at tcp://127\.0\.0\.1:\d+ "
                                        r"during the run", lines[0]), err[-3000:]
    assert "Traceback" not in err and "distributed." not in err
    assert not (tmp_path / "s.json").exists()


def test_all_workers_gone_is_one_line_after_the_timeout(params_json, tmp_path):
    p, err, took = _kill_during_run(params_json, tmp_path / "s.json", "worker",
                                    env={**ENV, "STATUE2MODEL_WORKER_TIMEOUT": "2"})
    assert p.returncode == 2, (p.returncode, err[-2000:])
    lines = _lines(err)
    assert len(lines) == 1 and "no Dask worker at tcp://127.0.0.1:" in lines[0], err[-3000:]
    assert "STATUE2MODEL_WORKER_TIMEOUT=2" in lines[0] and "Traceback" not in err
    assert took >= 2, f"stopped {took:.1f} s after the worker left, before its 2 s timeout"
    assert not (tmp_path / "s.json").exists()


def test_no_worker_when_connecting_is_one_line():
    from statue2model.compute.executors import DaskExecutor
    from statue2model.errors import InputError

    with Cluster(worker=False) as c:
        with pytest.raises(InputError, match=r"^no Dask worker at tcp://127\.0\.0\.1:\d+ for 1 s"):
            DaskExecutor(c.address, worker_timeout=1.0)


def test_worker_timeout_is_checked(monkeypatch):
    from statue2model.compute.executors import WORKER_TIMEOUT, _worker_timeout
    from statue2model.errors import InputError

    monkeypatch.delenv("STATUE2MODEL_WORKER_TIMEOUT", raising=False)
    assert _worker_timeout(None) == WORKER_TIMEOUT == 60.0
    monkeypatch.setenv("STATUE2MODEL_WORKER_TIMEOUT", "7.5")
    assert _worker_timeout(None) == 7.5 and _worker_timeout(3) == 3.0
    for bad in ("0", "-1", "nan", "inf", "soon"):
        monkeypatch.setenv("STATUE2MODEL_WORKER_TIMEOUT", bad)
        with pytest.raises(InputError, match="STATUE2MODEL_WORKER_TIMEOUT must be a number of seconds > 0"):
            _worker_timeout(None)


def test_a_tasks_own_oserror_is_not_a_lost_scheduler(tmp_path):
    """A task that raises FileNotFoundError (an OSError) on a healthy cluster: that very
    exception reaches the caller, and the executor still works (before: "lost the Dask
    scheduler ..." because OSError counted as a lost connection)."""
    from distributed import LocalCluster

    from statue2model.compute.executors import DaskExecutor

    missing = str(tmp_path / "no such file")
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp", host="127.0.0.1",
                      dashboard_address=None) as cluster:
        with DaskExecutor(cluster.scheduler_address) as ex:
            with pytest.raises(FileNotFoundError) as info:
                ex.map(os.stat, [str(tmp_path), missing])
            assert "no such file" in str(info.value)
            assert [st.st_ino for st in ex.map(os.stat, [str(tmp_path)])] == [os.stat(tmp_path).st_ino]


def test_log_filter_goes_with_an_executor_never_closed():
    """The executor's filter on distributed's loggers/handlers is removed when the executor
    is garbage-collected, for a library user who never closes it (before: kept for the
    whole process)."""
    import gc
    import logging

    from distributed import LocalCluster

    from statue2model.compute.executors import DaskExecutor, _DropConnectionLogs

    def ours(target) -> list:
        return [f for f in target.filters if isinstance(f, _DropConnectionLogs)]

    targets = [logging.getLogger("distributed.client"), logging.getLogger("distributed.core")]
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp", host="127.0.0.1",
                      dashboard_address=None) as cluster:
        targets += list(logging.getLogger("distributed").handlers)
        before = [len(ours(t)) for t in targets]
        ex = DaskExecutor(cluster.scheduler_address)
        client = ex._client
        assert [len(ours(t)) for t in targets] == [b + 1 for b in before]
        del ex
        gc.collect()
        assert [len(ours(t)) for t in targets] == before
        client.close()
