"""The sliding limit state in a run (issue [22], item 2): [sliding] friction, the row's demand on the run's
own design records against an independent rigid-plastic block, its capacity, and the verdict's words."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from statue2model.assessment.limit_states import evaluate
from statue2model.assessment.support import FLOOR_ALLOWANCE, Support
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.quantities import G
from statue2model.rocking.model import RockingModel
from statue2model.rocking.sliding import Friction


def independent_block(mu_s: float, mu_k: float, t: np.ndarray, a: np.ndarray, dt: float = 1e-4):
    """Peak sliding toward +x and toward -x (m) of a rigid-plastic block on a support accelerating as the
    samples (t, a), by fixed small steps of the stick-slip law (no closed form, nothing of the package)."""
    tt = np.arange(0.0, t[-1] + 5.0, dt)
    aa = np.interp(tt, t, a, left=0.0, right=0.0)
    u = v = hi = lo = 0.0
    for ak in aa.tolist():
        if v == 0.0:
            if abs(ak) <= mu_s * G:
                continue
            s = -math.copysign(1.0, ak)
        else:
            s = math.copysign(1.0, v)
        vn = v - (ak + s * mu_k * G) * dt
        if v != 0.0 and vn * v <= 0.0:
            u += v * dt / 2
            v = 0.0
        else:
            u += (v + vn) * dt / 2
            v = vn
        hi, lo = max(hi, u), min(lo, u)
    return hi, -lo


def _box_run(tmp_path, size=(0.5, 0.5, 0.4), sliding="mu_statue = 0.2\n", extra=""):
    import trimesh

    from statue2model.cli import main

    trimesh.creation.box(extents=list(size)).export(tmp_path / "box.stl")
    (tmp_path / "project.toml").write_text(
        '[scan]\nunits = "m"\nup = "z"\n[sliding]\n' + sliding + "[isolator]\nenabled = false\n"
        "[prototype]\nenabled = false\n[dynamics]\nfragility = false\n" + extra)
    out = tmp_path / "o"
    code = main(["run", str(tmp_path / "box.stl"), "--config", str(tmp_path / "project.toml"), "--out", str(out)])
    return code, out


def test_a_squat_box_slides_as_an_independent_block_on_the_runs_own_records(tmp_path):
    """Done-when of issue [22]: a squat 0.5 x 0.5 x 0.4 m box on the floor with mu_statue 0.2: the sliding
    demand within 5 % of an independent rigid-plastic block on the run's own design records."""
    code, out = _box_run(tmp_path)
    assert code == 0
    ls = json.loads((out / "dynamics" / "limit_states.json").read_text())
    row = next(r for r in ls["rows"] if r["name"] == "sliding" and r["base"] == "fixed")
    pos, neg = [], []
    for k in range(1, ls["n_records"] + 1):
        t, a = np.loadtxt(out / "dynamics" / "records" / f"record_{k:02d}.csv", delimiter=",", skiprows=1,
                          unpack=True, usecols=(0, 1))
        hi, lo = independent_block(0.2, 0.2 * 0.75, t, a)
        pos.append(hi)
        neg.append(lo)
    d = row["details"]
    assert d["demand_pos"] == pytest.approx(np.mean(pos), rel=0.05)
    assert d["demand_neg"] == pytest.approx(np.mean(neg), rel=0.05)
    assert row["demand"] == pytest.approx(max(np.mean(pos), np.mean(neg)), rel=0.05) and row["demand"] > 1e-3
    assert row["capacity"] == FLOOR_ALLOWANCE and "default floor allowance" in d["capacity_source"]
    assert d["mu_s"] == 0.2 and d["mu_k"] == pytest.approx(0.15)
    run = json.loads((out / "run.json").read_text())
    assert any(b.startswith("Sliding: it slides on the floor") for b in run["verdict"]["bullets"])


def test_a_box_that_slides_beyond_its_allowance_is_told_to_be_restrained(tmp_path):
    """The verdict reads the sliding row: an allowance of 1 mm is passed; the code is SLIDES, the headline
    says how far it slides against what it may, and the number printed is the row's."""
    code, out = _box_run(tmp_path, sliding='mu_statue = 0.2\nallowance = "1mm"\n')
    assert code == 0
    v = json.loads((out / "run.json").read_text())["verdict"]
    row = next(r for r in v["limit_states"]["rows"] if r["name"] == "sliding")
    assert row["exceeded"] and row["capacity"] == pytest.approx(0.001)
    assert v["code"] == "SLIDES" and v["headline"].startswith("Restrain it against sliding: it slides on the floor")
    assert f"{row['demand'] * 1000:.0f} mm" in v["headline"] and "more than the 1 mm it may" in v["headline"]


def test_the_sliding_row_can_fail_and_counts_each_side():
    """A pulse toward +x slides the block toward -x: the row is that side's, with its own count."""
    blk = RockingParams.rectangular_block(b=0.25, h=0.2, m=100.0)
    recs = [motions.rect_pulse((0.3 + 0.01 * k) * G, 0.4) for k in range(7)]
    sup = Support(Friction(0.2, 0.15), (0.05, 0.5), "test capacities")
    ls = evaluate(RockingModel.housner(blk), recs, support=sup)
    row = ls.row("sliding", "fixed")
    assert row.details["side"] == "toward -x" and row.details["demand_pos"] == 0.0
    assert row.capacity == 0.5 and row.exceeded is False
    tight = evaluate(RockingModel.housner(blk), recs, support=Support(Friction(0.2, 0.15), (0.5, 0.05), "tight"))
    assert tight.row("sliding", "fixed").exceeded and tight.row("sliding", "fixed").n_exceeding == 7
    json.dumps(tight.to_dict(), allow_nan=False)
