"""No non-finite number ever reaches a file, a table or a sentence (issue #24, item 1).

* the JSON writer turns every nan / inf (numpy too, nested) into null: the file is strict JSON;
* a fragility fit is identified only with runs at two levels or more, a failure and a survival;
  an undefined median is null with its reason ("no failure at any level", "one level: spread
  not identified"), and so are its bands;
* bootstrap replicates without a failure (median above the levels) never give an infinite band
  end: the end is null and the note counts them (checked against an independent recount);
* the README's example (maria_barjatinskaja, density 2700, EC8 ag 0.30 g ground B), which ended
  in "Out of range float values are not JSON compliant: inf", runs to its report;
* a reversed ``fragility_levels`` is refused at once, naming the key.
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from statue2model.hazard import motions
from statue2model.rocking import RockingModel
from statue2model.assessment.fragility import (
    REASONS,
    FragilityStudy,
    _fit_all,
    fit_lognormal,
    run_fragility,
)
from statue2model.rocking.sampling import lognormal_factor
from statue2model.geometry.rocking_params import RockingParams
from statue2model.io.csvsafe import csv_text
from statue2model.io.files import write_json

ROOT = Path(__file__).resolve().parents[1]
MARIA = ROOT / "meshes" / "maria_barjatinskaja.ply"
NONFINITE = re.compile(r"(?<![A-Za-z_])(nan|inf|infinity)(?![A-Za-z_])", re.IGNORECASE)


def _strict(text: str):
    """json.loads that refuses NaN, Infinity and -Infinity."""
    def refuse(name):
        raise ValueError(f"non-finite constant {name} in JSON")

    return json.loads(text, parse_constant=refuse)


def _walk_numbers(obj):
    if isinstance(obj, dict):
        for v in obj.values():
            yield from _walk_numbers(v)
    elif isinstance(obj, list):
        for v in obj:
            yield from _walk_numbers(v)
    elif isinstance(obj, float):
        yield obj


# --- (a) the writer ----------------------------------------------------------------------------
def test_write_json_turns_every_nonfinite_into_null(tmp_path):
    data = {"a": float("inf"), "b": [1.5, float("nan"), -float("inf")], "c": {"d": np.float64("inf"),
            "e": (np.float32("nan"), 2)}, "f": np.array([[1.0, np.nan], [np.inf, -np.inf]]),
            "g": [{"h": [np.float64("-inf")]}], "ok": np.float64(0.25), "n": np.int64(3)}
    path = write_json(tmp_path / "x.json", data)
    back = _strict(path.read_text())
    assert back == {"a": None, "b": [1.5, None, None], "c": {"d": None, "e": [None, 2]},
                    "f": [[1.0, None], [None, None]], "g": [{"h": [None]}], "ok": 0.25, "n": 3}
    assert not NONFINITE.search(path.read_text())


def test_csv_cells_never_nan_or_inf():
    text = csv_text(["x", "y"], [[float("nan"), 1.0], [np.float64("inf"), -np.inf]])
    assert text.splitlines() == ["x,y", ",1.0", ","]


# --- (b) fits that are not identified ------------------------------------------------------------
def test_fit_needs_two_levels_a_failure_and_a_survival():
    # one level: any spread passes through one point (before: median 2.3 g, beta 3.77, "ok")
    med, beta, st = fit_lognormal([5.0], [3], [7])
    assert st == "one level" and math.isnan(med) and math.isnan(beta)
    assert REASONS[st] == "one level: spread not identified"
    # levels with no run do not count: one level with runs is still one level
    assert fit_lognormal([1.0, 5.0, 9.0], [0, 3, 0], [0, 7, 0])[2] == "one level"
    assert fit_lognormal([1.0, 2.0, 4.0], [0, 0, 0], [7, 7, 7])[2] == "no failures"
    assert fit_lognormal([1.0, 2.0, 4.0], [7, 7, 7], [7, 7, 7])[2] == "all failed"
    assert REASONS["no failures"] == "no failure at any level" and REASONS["all failed"] == "failure at every level"
    # two levels, one failure and one survival: identified (a step between them)
    med, beta, st = fit_lognormal([1.0, 2.0], [0, 7], [7, 7])
    assert st == "step" and 1.0 < med < 2.0


def test_one_level_study_is_not_fitted_with_reason(tmp_path):
    """A real one-level study: the block at its closed-form overturning amplitude a* with a
    lognormal im_factor overturns in about half the runs; one point identifies no curve."""
    block = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
    model = RockingModel.housner(block, e_L=0.9, e_R=0.9, linearised=True)
    tp = 0.25
    a_star = block.g * block.delta_L / (1.0 - math.exp(-block.p_L * tp))
    res = run_fragility(model, [motions.rect_pulse(1.0, tp)], [a_star], lognormal_factor(0.3, 40, seed=3),
                        FragilityStudy(n_boot=20, free_time=5.0))
    c = res.curves["overturning_fixed"]
    assert 0 < c.n_fail[0] < c.n_trials[0]                # a failure and a survival, at one level
    assert c.status == "one level" and not c.fitted and c.reason == "one level: spread not identified"
    d = _strict(json.dumps(_strict((res.write_json(tmp_path / "f.json")).read_text())))
    cd = d["curves"]["overturning_fixed"]
    assert cd["median"] is None and cd["beta"] is None and cd["reason"] == "one level: spread not identified"
    assert cd["median_ci"] == [None, None] and cd["band_lo"] == [None] and cd["fitted"] == [None]
    res.write_csv(tmp_path / "f.csv")
    assert not NONFINITE.search((tmp_path / "f.csv").read_text())
    assert "one level: spread not identified" in (tmp_path / "f.csv").read_text()
    line = next(ln for ln in res.summary_lines() if ln.startswith("overturning"))
    assert "not fitted (one level: spread not identified)" in line and not NONFINITE.search(line)
    # the uplift needs no levels: it is fitted on each run's exact uplift PGA, identified at one level too
    assert res.curves["full_contact_fixed"].status == "exact" and res.curves["full_contact_fixed"].spread is None


def _counts(fail_records, R=6, L=5, top=2, S=1):
    """(R, S, L) bool: the records in ``fail_records`` fail at the ``top`` highest levels, the others never."""
    f = np.zeros((R, S, L), dtype=bool)
    for r in fail_records:
        f[r, :, L - top:] = True
    return f


def test_no_failure_curve_is_null_with_reason_and_no_band(tmp_path):
    lv = np.geomspace(1.0, 10.0, 5)
    fails = {"overturning_fixed": _counts([])}
    valid = {"fixed": np.ones_like(fails["overturning_fixed"])}
    curves, ratio = _fit_all(lv, fails, valid, FragilityStudy(n_boot=50), "records")
    c = curves["overturning_fixed"]
    assert c.status == "no failures" and c.reason == "no failure at any level"
    d = _strict(write_json(tmp_path / "c.json", c.to_dict()).read_text())
    assert d["median"] is None and d["reason"] == "no failure at any level"
    assert d["median_ci"] == [None, None] and d["beta_ci"] == [None, None]       # not [0.0, 0.0]
    assert d["band_lo"] == [None] * 5 and d["band_hi"] == [None] * 5
    assert "median is undefined (no failure at any level)" in d["median_ci_note"]


# --- (c) bootstrap replicates without a failure --------------------------------------------------
def test_bootstrap_band_never_infinite_and_counts_replicates_without_failure(tmp_path):
    """Six records, only record 0 overturns (at the two top levels): a replicate without record 0
    (probability (5/6)^6 = 0.33) has no failure, its median lies above the levels; the 95th
    percentile of the medians falls there: the upper end is null and the note gives the count,
    recounted here from the same random draws. The isolated side fails on records 0-2: its ratio
    band's lower end falls on the replicates where the fixed median is above the levels."""
    lv = np.geomspace(1.0, 10.0, 5)
    fails = {"overturning_fixed": _counts([0]), "overturning_alone_isolated": _counts([0, 1, 2], top=3),
             "capacity_isolated": _counts([]), "overturning_isolated": _counts([0, 1, 2], top=3)}
    valid = {"fixed": np.ones_like(fails["overturning_fixed"]), "isolated": np.ones_like(fails["overturning_fixed"])}
    study = FragilityStudy(n_boot=200, seed=5)
    curves, ratio = _fit_all(lv, fails, valid, study, "records")
    rng = np.random.default_rng(5)
    picks = [rng.integers(0, 6, 6) for _ in range(200)]
    no_failure = sum(0 not in p for p in picks)
    assert 40 < no_failure < 95                              # ~ 200 x 0.335 = 67
    c = curves["overturning_fixed"]
    assert c.fitted and math.isfinite(c.median)
    assert math.isfinite(c.median_ci[0]) and math.isnan(c.median_ci[1])
    assert f"{no_failure} of 200 replicates had no failure" in c.median_ci_note
    assert c.boot_undefined["no failures"] == no_failure
    assert np.all(np.isfinite(c.band_lo)) and np.all((0 <= c.band_lo) & (c.band_lo <= c.band_hi) & (c.band_hi <= 1))
    r = ratio["overturning"]
    assert r["value"] is not None and math.isfinite(r["value"])
    assert all(x is None or math.isfinite(x) for x in r["ci"]) and r["ci"][0] is None and r["ci_note"]
    # the capacity curve has no failure: its ratio-free curve is null with its reason, bands too
    assert curves["capacity_isolated"].reason == "no failure at any level"
    res = SimpleNamespace(curves=curves, ratio=ratio)
    from statue2model.assessment.study import fragility_data
    from statue2model.assessment.verdict import fragility

    data = fragility_data(res, 2.0, True)
    data.update(fragility_runs=30)
    back = _strict(write_json(tmp_path / "stage.json", {"data": data}).read_text())["data"]
    assert back["fragility_median_ci_fixed"][1] is None and "had no failure" in back["fragility_median_ci_fixed_reason"]
    assert back["fragility_median_fixed_reason"] is None and back["fragility_ratio_ci"][0] is None
    assert "lower end not identified: in " in back["fragility_ratio_ci_reason"]
    for v in _walk_numbers(back):
        assert math.isfinite(v)
    line = fragility(back, 2.0, True)["line"]
    assert "band from" in line and "had no failure" in line and not NONFINITE.search(line)


def test_undefined_ratio_has_no_band():
    """Isolated side failing everywhere ("all failed", median below the levels): the ratio and its
    band are null with the note (before: a band 0.0-0.76 around an undefined ratio)."""
    lv = np.geomspace(1.0, 10.0, 5)
    fails = {"overturning_fixed": _counts([0, 1, 2, 3]), "overturning_alone_isolated": _counts(range(6), top=5),
             "capacity_isolated": _counts([]), "overturning_isolated": _counts(range(6), top=5)}
    valid = {"fixed": np.ones_like(fails["overturning_fixed"]), "isolated": np.ones_like(fails["overturning_fixed"])}
    curves, ratio = _fit_all(lv, fails, valid, FragilityStudy(n_boot=100), "records")
    r = ratio["overturning"]
    assert r["value"] is None and r["ci"] == [None, None]
    assert "isolated failure at every level" in r["note"]
    from statue2model.assessment.study import fragility_data

    data = fragility_data(SimpleNamespace(curves=curves, ratio=ratio), 2.0, True)
    assert data["fragility_ratio"] is None and "failure at every level" in data["fragility_ratio_reason"]
    assert data["fragility_median_isolated"] is None and data["fragility_median_ci_isolated"] is None
    assert data["fragility_median_isolated_reason"] == "failure at every level"


def test_sentences_and_tables_print_dash_not_nan():
    from statue2model.report.page import _cell, _tables
    from statue2model.assessment.verdict import fragility
    from statue2model.report.tables import format_table

    assert "nan" not in format_table([("a", float("nan"), np.float64("inf"))])
    good, bad = _tables([{"title": "t", "columns": ["a", "b"], "rows": [[float("inf"), 1.0]]}])
    assert good[0]["rows"] == [["-", 1.0]] and bad == 0 and _cell(float("nan")) == "-"
    dyn = {"fragility_runs": 70, "fragility_median_fixed": float("inf"), "fragility_p_design_fixed": float("nan"),
           "fragility_median_fixed_reason": "no failure at any level", "fragility_ratio": float("nan"),
           "fragility_median_isolated": 5.0, "fragility_median_ci_isolated": [float("-inf"), 6.0]}
    line = fragility(dyn, 2.8, True)["line"]
    assert "not fitted (no failure at any level)" in line and not NONFINITE.search(line)


# --- (d) the README example runs to its report ----------------------------------------------------
@pytest.mark.slow
def test_readme_example_ends_with_report_and_strict_json(tmp_path):
    """The README's example (density 2700, EC8 ag 0.30 g ground B) whose fragility bootstrap has
    replicates without failure: exit 0, report.html, every JSON strict, no nan/inf in any CSV.
    Small spectrum grids (the fragility study, the part that failed, is the default one); measured
    about 14 s on the shared 2-core machine."""
    from statue2model.cli import main

    cfg = tmp_path / "project.toml"
    cfg.write_text('[scan]\ndensity = 2700\n[isolator]\nspectrum = "ec8:ag=0.30g,ground=B"\n'
                   '[dynamics]\nfreq = "0.5:10:4"\namp = "0.05g:1g:4"\npga = "0.1g:1g:3"\n')
    out = tmp_path / "maria"
    code = main(["run", str(MARIA), "--config", str(cfg), "--out", str(out), "--stages", "params,isolator,dynamics"])
    assert code == 0 and (out / "report.html").is_file()
    files = sorted(out.rglob("*.json"))
    assert len(files) >= 8
    for f in files:
        _strict(f.read_text())
    for f in out.rglob("*.csv"):
        assert not NONFINITE.search(f.read_text()), f
    data = _strict((out / "dynamics" / "stage.json").read_text())["data"]
    for key in ("fragility_median_ci_fixed", "fragility_median_ci_isolated", "fragility_ratio_ci"):
        ci = data[key]
        if ci is None or None in ci:
            assert data[f"{key}_reason"], key                 # a null comes with its reason
    page = (out / "report.html").read_text()
    assert not re.search(r">[^<]*(?<![A-Za-z_])(nan|inf)(?![A-Za-z_])[^<]*<", page)


# --- (e) a reversed fragility_levels ----------------------------------------------------------------
def test_reversed_fragility_levels_refused_at_once(tmp_path, capsys, monkeypatch):
    from statue2model.cli import main
    from statue2model.geometry import body, scan

    def no_work(*a, **k):                                    # refused before any work: no scan is read
        raise AssertionError("the scan was read before the project file was checked")
    monkeypatch.setattr(scan, "read_scan", no_work)
    monkeypatch.setattr(body, "read_scan", no_work)
    cfg = tmp_path / "project.toml"
    cfg.write_text('[dynamics]\nfragility_levels = "1g:0.1g:5"\n')
    code = main(["run", str(MARIA), "--config", str(cfg), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "fragility_levels" in err[0] and "increase" in err[0], err
    assert not (tmp_path / "out").exists()
    for bad in ("0.1g,0.1g,0.2g", "0.1g:0.5g:2"):
        cfg.write_text(f'[dynamics]\nfragility_levels = "{bad}"\n')
        assert main(["run", str(MARIA), "--config", str(cfg), "--out", str(tmp_path / "out")]) == 2
        assert "fragility_levels" in capsys.readouterr().err


def test_failure_text_never_prints_inf():
    """A check with no finite ratio (a fuse that cannot release: value inf) reads 'not met', never 'inf'
    (found on Maria on an upper floor: 'release inf m/s^2 (inf g) ... (ratio inf)')."""
    import math

    from statue2model.isolator.design import Check, failure_text

    checks = [Check("fuse releases before the statue rocks", False, math.inf, 3.44, "no room for a fuse ball"),
              Check("load per ball", False, 1334.0, 460.0, "1334 N vs 460 N"),
              Check("advisory", False, math.inf, 1.0, "x", required=False)]
    text = failure_text(checks)
    assert "inf" not in text.replace("information", "")
    assert text.startswith("fuse releases before the statue rocks: no room for a fuse ball (not met); load per ball")
    assert "(ratio 2.90)" in text and "advisory" not in text
    assert failure_text(checks, shown=1).endswith("; and 1 more")


def test_number_columns_text_is_csv_text_of_num_cells():
    """number_columns_text (the records' CSV, written directly) gives the text csv_text gives for the
    rows of num_cell cells: non-finite values as empty cells, -0.0, tiny and huge numbers, no rows."""
    import numpy as np

    from statue2model.io.csvsafe import csv_text, num_cell, number_columns_text

    rng = np.random.default_rng(0)
    for n in (0, 1, 7, 500):
        t = np.arange(n) * 0.01 - 0.3
        u = rng.normal(0.0, 1.0, n) * 10.0 ** rng.integers(-9, 9, n)
        if n > 3:
            u[:4] = (np.nan, np.inf, -0.0, -np.inf)
        for specs in ((".9g", ".9g"), (".12g", ".0f")):
            want = csv_text(("time_s", "acc_m_s2"), ((num_cell(a, specs[0]), num_cell(b, specs[1])) for a, b in zip(t, u)))
            assert number_columns_text(("time_s", "acc_m_s2"), (t, u), specs) == want
