"""A time history that stops (the isolator's capacity, overturning) ends in every file with its last
finite state and a line or field saying why: no nan or inf in any file (issue #24, item 6)."""
from __future__ import annotations

import json
import re

import numpy as np

from statue2model.cli import main
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.isolator.coupled import simulate_coupled
from statue2model.isolator.device import Isolator
from statue2model.isolator.time_history import CAPACITY_EXCEEDED, STOPPED_PREFIX, simulate
from statue2model.rocking.identify import read_time_series
from statue2model.rocking.model import RockingModel

NONFINITE = re.compile(r"(?<![A-Za-z_])(nan|inf|infinity)(?![A-Za-z_])", re.IGNORECASE)


def test_simulate_csv_ends_at_the_capacity_stop_without_nan(tmp_path, capsys):
    out = tmp_path / "sim.json"
    assert main(["isolator", "simulate", "--R", "0.3", "--r", "0.0183", "--mass", "21", "--mu", "0.01",
                 "--capacity", "50mm", "--motion", "cosine:amp=0.4g,freq=0.5", "--json", str(out)]) == 0
    capsys.readouterr()
    text = out.with_suffix(".csv").read_text()
    d = json.loads(out.read_text())
    assert d["outcome"] == CAPACITY_EXCEEDED
    assert not NONFINITE.search(text) and not NONFINITE.search(out.read_text())
    lines = text.splitlines()
    assert lines[0] == "t_s,u_m,v_m_s,a_abs_m_s2,z"
    assert lines[-1].startswith(STOPPED_PREFIX + CAPACITY_EXCEEDED) and "none after the stop" in lines[-1]
    rows = np.array([[float(x) for x in line.split(",")] for line in lines[1:-1]])
    assert np.all(np.isfinite(rows))
    assert rows[-1, 0] <= d["t_capacity"] < rows[-1, 0] + 0.005 + 1e-12      # the last sample before the stop
    assert np.all(np.abs(rows[:, 1]) <= 0.05 + 1e-12)
    t, u = read_time_series(out.with_suffix(".csv"), "displacement")     # `isolator identify` still reads it
    assert t.size == rows.shape[0] and np.array_equal(u, rows[:, 1])


def test_history_without_a_stop_has_no_stop_line():
    res = simulate(Isolator(R=0.3, r=0.0183, M=21.0, mu=0.01, capacity=0.5), motions.free(), u0=0.05, t_end=2.0)
    text = res.history_csv()
    assert STOPPED_PREFIX not in text and len(text.splitlines()) == res.t.size + 1


def test_coupled_history_ends_at_the_stop_with_why():
    iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01, capacity=0.03)
    model = RockingModel.housner(RockingParams.rectangular_block(b=0.2, h=0.25, m=10.0))
    res = simulate_coupled(iso, model, motions.free(), u0=0.02, v0=0.5, t_end=3.0, dt_out=0.01)
    assert res.capacity_exceeded and not np.all(np.isfinite(res.u))          # the kernel's marker in memory
    d = res.to_dict(history=True)
    h = d["history"]
    assert d["history_stopped"] == CAPACITY_EXCEEDED
    assert all(v is not None and np.isfinite(v) for col in h.values() for v in col)
    assert len(h["t"]) == len(h["u"]) and 0 < len(h["t"]) < res.t.size and h["t"][-1] <= res.t_capacity
