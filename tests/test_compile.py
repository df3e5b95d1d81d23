"""The numba kernels (statue2model/compute/compile.py): one compiled signature per
kernel whatever path calls it, spawned workers load them from the cache instead of
compiling, the first compilation is announced, and a changed dependency empties the
isolator caches numba would otherwise keep."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from statue2model.compute import compile as C
from statue2model.compute.executors import ProcessExecutor
from statue2model.rocking import kernel as K
from statue2model.hazard import motions
from statue2model.rocking.model import RockingModel
from statue2model.rocking.spectrum import stability_spectrum
from statue2model.rocking.sweeps import variability
from statue2model.geometry.rocking_params import RockingParams
from statue2model.isolator.device import Isolator
from statue2model.isolator.sweeps import isolated_spectrum

ROOT = Path(__file__).resolve().parents[1]
G = 9.81

# every path into the kernels the pipeline and the commands take, in a fresh process
PATHS = r"""
import json
import numpy as np
from statue2model.compute import compile as C
from statue2model.hazard import motions
from statue2model.rocking.batch import run_batch
from statue2model.rocking.engine import simulate as rock
from statue2model.rocking.model import RockingModel
from statue2model.rocking.spectrum import stability_spectrum
from statue2model.rocking.sweeps import variability
from statue2model.geometry.rocking_params import RockingParams
from statue2model.isolator.coupled import simulate_coupled
from statue2model.isolator.device import Isolator
from statue2model.isolator.time_history import simulate as plate
from statue2model.isolator.sweeps import isolated_spectrum, isolated_variability
G = 9.81
C.warm_up(progress=None)
model = RockingModel.imperfect(RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0), alpha_L=0.7, alpha_R=0.8,
                               e_L=0.9, e_R=0.9)
rec = motions.synthetic_record(duration=4.0, dt=0.01, pga=0.3 * G, seed=1)     # read-only samples
scaled = rec.scaled(1.5)                                                          # writable samples
pulse = motions.cosine_pulse(0.3 * G, 2.0)
iso_c = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01)
iso_b = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01, model="boucwen")
stability_spectrum(model, [1.0, 2.0], np.array([0.2, 0.6]) * G)
variability(model, rec, [1, 3])
variability(model, scaled, np.array([1.0, 3.0]))
run_batch(model, model.kernel_vector()[None, :], [1], [[0.5, 6.0, 0.0, 0.0, 1.0, 0.0]], np.zeros(2), [5.0])
for m in (rec, scaled, pulse):
    rock(model, m, dt_out=0.01)
    m.acc([0.1, 0.5])
    for iso in (iso_c, iso_b):
        plate(iso, m, dt_out=0.01)
        simulate_coupled(iso, model, m, dt_out=0.01, screen=False)
from statue2model.rocking.stack import Pedestal, StackModel, simulate_stack, simulate_stack_batch
stack = StackModel(RockingParams.rectangular_block(b=0.1, h=0.5, m=20.0), Pedestal(0.3, 0.5, 30.0))
for m in (rec, scaled, pulse):
    simulate_stack(stack, m, t_end=5.0)
    simulate_stack_batch([stack], m, scales=[1.0], t_end=5.0)
isolated_spectrum(iso_c, model, [1.0], np.array([0.3]) * G)
isolated_variability(iso_b, model, rec, np.array([1.0, 2.0]))
out = {}
for name, fn, sig in C.kernels():
    out[name] = {"signatures": [str(s) for s in fn.signatures], "expected": str(sig)}
print(json.dumps(out))
"""


def _python(code: str, env: dict | None = None, timeout: float = 600) -> subprocess.CompletedProcess:
    path = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                          check=False, env={**os.environ, "PYTHONPATH": path, **(env or {})})


def test_one_signature_per_kernel_on_every_path():
    """Records (read-only samples), scaled records and pulses (writable), python ints
    and lists, the batch, the plate and the coupled kernels: each kernel is compiled
    for its declared signature only (a second one would be a second compilation)."""
    res = _python(PATHS)
    assert res.returncode == 0, res.stderr[-3000:]
    stats = json.loads(res.stdout.strip().splitlines()[-1])
    assert set(stats) == set(C.names())
    for name, s in stats.items():
        assert s["signatures"] == [s["expected"]], f"{name} compiled for {s['signatures']}"


def test_spawned_worker_loads_the_kernels_from_the_cache():
    """The parent compiles (or finds) the kernels before the pool starts; a spawned
    worker then loads every kernel it runs from the cache: no miss, i.e. no compilation,
    also for a record's samples that arrive writable after pickling."""
    C.ensure_compiled()
    model = RockingModel.imperfect(RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0), alpha_L=0.7,
                                   alpha_R=0.8, e_L=0.9, e_R=0.9)
    rec = motions.synthetic_record(duration=3.0, dt=0.01, pga=0.3 * G, seed=2)
    iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01)
    with ProcessExecutor(1) as ex:
        stability_spectrum(model, [1.0, 2.0], np.array([0.2, 0.6]) * G, executor=ex)
        variability(model, rec, np.array([1.0, 4.0]), executor=ex)
        isolated_spectrum(iso, model, [1.5], np.array([0.4]) * G, executor=ex)
        (stats,) = ex.map(C.kernel_stats, [0])
    assert {k: s["cache_misses"] for k, s in stats.items()} == {k: 0 for k in stats}
    for name in ("statue2model.rocking.kernel.simulate_batch", "statue2model.isolator.coupled_kernel.simulate_kernel"):
        assert stats[name]["cache_hits"] == 1 and len(stats[name]["signatures"]) == 1


def test_first_compilation_is_announced_once(monkeypatch):
    said, compiled = [], []
    monkeypatch.setattr(C, "_refresh_dependents", lambda: None)
    monkeypatch.setattr(C, "cache_state", lambda: {n: (n != C.names()[-1]) for n in C.names()})

    def warm_up(progress=None, workers=None):
        compiled.append(1)
        return {"seconds": 0.0, "kernels": {C.names()[-1]: {"seconds": 0.0, "compiled": True}}}

    monkeypatch.setattr(C, "warm_up", warm_up)
    assert C.ensure_compiled.__wrapped__(say=said.append) is True
    assert compiled == [1] and len(said) == 2
    assert said[0].startswith("compiling the rocking and isolator kernels once (numba, about ")
    assert " s; cached in " in said[0] and said[1].startswith("compiled in ")
    monkeypatch.setattr(C, "cache_state", lambda: {n: True for n in C.names()})
    said.clear()
    assert C.ensure_compiled.__wrapped__(say=said.append) is False and said == []


def test_estimate_groups_whole_modules():
    groups = C._groups(C.names(), 2)
    assert sorted(n for g in groups for n in g) == sorted(C.names()) and len(groups) == 2
    for g in groups:        # an entry point's module-mates are compiled in the same process
        mods = {n.rsplit(".", 1)[0] for n in g}
        assert all(n in g for n in C.names() if n.rsplit(".", 1)[0] in mods)
    one = C.estimate(workers=1)
    assert one == sum(C.COLD_SECONDS.values()) and C.estimate(workers=2) < one


def test_as_samples_is_read_only_without_copying():
    a = np.linspace(0.0, 1.0, 5)
    s = K.as_samples(a)
    assert not s.flags.writeable and a.flags.writeable and np.shares_memory(a, s)
    assert K.as_samples(s) is s
    b = K.as_samples(np.arange(6)[::2])                    # ints, strided: a float64 C copy
    assert b.dtype == np.float64 and b.flags.c_contiguous and not b.flags.writeable
    assert b.tolist() == [0.0, 2.0, 4.0]
    assert not motions.cosine_pulse(1.0, 1.0).kernel_args()[2].flags.writeable


def test_changed_dependency_empties_the_isolator_caches(tmp_path):
    """Numba keys a cache on the function's own file only: after rocking/kernel.py
    changes, the isolator kernels (which contain its code) must not load."""
    code = r"""
import json
from pathlib import Path
from numba import types as nt
from statue2model.compute import compile as C
from statue2model.isolator import kernel as IK
sig = (nt.float64,) * 4 + (nt.int64,)
C._refresh_dependents()
IK.z_map.compile(sig)
assert C._cached(IK.z_map, sig) is True
C._refresh_dependents()                                   # nothing changed: kept
assert C._cached(IK.z_map, sig) is True
stamp = Path(IK.z_map._cache.cache_path) / "kernel.depends.json"
stamp.write_text(json.dumps({"depends": ["statue2model.rocking.kernel"], "sha256": "0" * 64}))
C._refresh_dependents()                                   # as after an edit of rocking/kernel.py
assert C._cached(IK.z_map, sig) is False
assert json.loads(stamp.read_text())["sha256"] != "0" * 64
print("ok")
"""
    res = _python(code, env={"NUMBA_CACHE_DIR": str(tmp_path)}, timeout=120)
    assert res.returncode == 0 and res.stdout.strip().endswith("ok"), res.stderr[-3000:]


def test_check_reports_an_empty_cache(tmp_path):
    res = subprocess.run([sys.executable, "-m", "statue2model.compute.compile", "--check"], capture_output=True,
                         text=True, timeout=120, check=False, cwd=ROOT,
                         env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)})
    assert res.returncode == 1, res.stderr[-2000:]
    assert res.stdout.count(": not cached") == len(C.KERNELS) and str(tmp_path) in res.stdout
