"""statue2model run: project file, content-hash cache, interruption and resume, the
report in a headless browser, and a folder of scans on local processes and on a
local Dask cluster with the same numbers."""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.errors import InputError
from statue2model.io.paths import MESHES_DIR, default_scan
from statue2model.pipeline import cache
from statue2model.pipeline.config import (
    ProjectConfig,
    default_toml,
    load_config,
    load_config_text,
)
from statue2model.pipeline.run import run_collection, run_project

SMALL = """
[prototype]
scale = "1:6"
previews = false
[dynamics]
freq = "0.5:4:4"
amp = "0.1g:1g:4"
pga = "0.2g:1.2g:4"
motion = "synthetic:duration=6,pga=0.4g,seed=2"
[crosscheck]
quick = true
motion = "sine:amp=0.4g,freq=2"
[run]
stages = "all"
"""


def small_toml(extra: str = "") -> str:
    """SMALL with the sections of ``extra`` merged over it."""
    import tomli_w
    import tomllib

    base = tomllib.loads(SMALL)
    for sec, table in tomllib.loads(extra).items():
        base.setdefault(sec, {}).update(table)
    return tomli_w.dumps(base)


def small_config(extra: str = "") -> ProjectConfig:
    return load_config_text(small_toml(extra), "test.toml")


def quiet(msg):
    pass


# --- project file -------------------------------------------------------------------------------
def test_defaults_are_the_thesis_choices():
    cfg = load_config(None)
    assert (cfg.prototype.scale, cfg.prototype.board, cfg.prototype.glue, cfg.prototype.tool) == (2.0, 0.009, 0.0005, 0.003)
    assert (cfg.prototype.board_density, cfg.prototype.rod_density) == (620.0, 7850.0)
    assert cfg.isolator.mu is None and cfg.isolator.fuse_release == pytest.approx(0.075 * 9.81)
    assert (cfg.isolator.surface, cfg.isolator.layout, cfg.isolator.extra_sets) == ("auto", "auto", 3)
    assert cfg.scan.density == 2650.0 and cfg.model.kind == "housner"


def test_default_file_round_trips(tmp_path):
    p = tmp_path / "project.toml"
    assert main(["config", "--out", str(p)]) == 0
    assert load_config(p).to_dict() == ProjectConfig().to_dict()
    assert p.read_text().startswith("# The project file")
    assert main(["config", "--out", str(p)]) == 2           # never overwrites
    cfg = small_config('[model]\nkind = "imperfect"\nalpha_L = 0.159\nalpha_R = 0.175\ntheta_L = 4.55e-3\n')
    again = load_config_text(cfg.to_toml(), "resolved")
    assert again.to_dict() == cfg.to_dict()
    assert default_toml().count("[") >= 7


@pytest.mark.parametrize("text, words", [
    ("[prototype]\nbord = 0.009\n", "unknown key 'bord' in [prototype] (did you mean 'board'?)"),
    ("[protoype]\nscale = 2\n", "unknown section [protoype] (did you mean [prototype]?)"),
    ("[prototype]\nboard = \"9 furlongs\"\n", "[prototype] board"),
    ("[prototype]\nscale = \"1:0\"\n", "[prototype] scale"),
    ("[model]\nalpha_L = 0.5\n", "belong to kind = \"imperfect\""),
    ("[model]\nkind = \"imperfect\"\nalpha_L = 1.5\n", "alpha_L must be in (0, 1]"),
    ("[dynamics]\nfreq = \"1:2\"\n", "[dynamics] freq"),
    ("[dynamics]\nmotion = \"earthquake\"\n", "earthquake"),
    ("[isolator]\nspectrum = \"ec8:ag=0.25g,ground=S1\"\n", "S1"),
    ("[isolator]\nmu = 0.7\n", "mu must be in [0, 0.5)"),
    ("[run]\nworkers = 0\n", "workers must be >= 1"),
    ("[scan]\nunits = \"furlong\"\n", "[scan] units"),
    ("[prototype]\ncompensate = 1\n", "true or false"),
    ("scan = 3\n", "must be a [section]"),
    ("[scan\n", "not valid TOML"),
    ("[prototype]\nscale = \"auto\"\n", "[prototype] scale = 'auto': needs a value (default \"1:2\")"),
    ("[dynamics]\nenabled = \"auto\"\n", "needs a value (default true)"),
    ("[model]\nkind = \"auto\"\n", "[model] kind"),
    ("[isolator]\nthickness = \"-30mm\"\n", "[isolator] thickness"),
    ("[model]\nkind = \"imperfect\"\nalpha_L = 0.5\nalpha_R = 0.5\ntheta_L = -1\n", "theta_L must be > 0"),
    ("[crosscheck]\niterations = 0\n", "iterations must be >= 1"),
    ("[crosscheck]\nensemble_budget = 0\n", "ensemble_budget must be a positive number of seconds"),
    ("[crosscheck]\ngroove = \"balls\"\n", "[crosscheck] groove"),
    ("[dynamics]\nmotion = \"sine:amp=0,freq=2\"\n", "must be a ground motion"),
])
def test_bad_project_files_name_the_problem(text, words):
    with pytest.raises(InputError) as exc:
        load_config_text(text, "p.toml")
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_units_in_values():
    cfg = load_config_text('[prototype]\nboard = "12mm"\nsheet = "2440x1220mm"\nfeed = "3000 mm/min"\n'
                           '[isolator]\nfuse_release = "0.1g"\ngrooves = 3\nthickness = "25mm"\n', "p")
    assert cfg.prototype.board == pytest.approx(0.012)
    assert cfg.prototype.sheet == pytest.approx((2.44, 1.22))
    assert cfg.prototype.feed == pytest.approx(0.05)
    assert cfg.isolator.fuse_release == pytest.approx(0.981)
    assert cfg.isolator.grooves == 3 and cfg.isolator.thickness == pytest.approx(0.025)
    assert load_config_text('[isolator]\nfuse_release = "none"\n', "p").isolator.fuse_release is None


# --- cache ----------------------------------------------------------------------------------------
def test_interrupted_stage_leaves_nothing_that_looks_complete(tmp_path):
    key = cache.stage_key("s", {"a": 1})

    def ok(d):
        (d / "x.txt").write_text("first")
        return {"summary": {"x": 1}}

    def interrupted(d):
        (d / "x.txt").write_text("half")
        raise KeyboardInterrupt

    assert cache.run_stage(tmp_path / "s", key, ok)["cached"] is False
    with pytest.raises(KeyboardInterrupt):
        cache.run_stage(tmp_path / "s", cache.stage_key("s", {"a": 2}), interrupted)
    assert (tmp_path / "s" / "x.txt").read_text() == "first"          # the previous complete result
    assert cache.completed(tmp_path / "s", key) is not None
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]
    with pytest.raises(KeyboardInterrupt):
        cache.run_stage(tmp_path / "new", key, interrupted)
    assert not (tmp_path / "new").exists()


# --- one scan -------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "girl"
    res = run_project(default_scan(), out, small_config(), say=quiet)
    return res


@pytest.mark.slow
def test_one_limit_state_vocabulary_in_every_file(small_run):
    """limit_states.json's rows, fragility.json's limit_states and curve keys, its ratios, the 3D
    classification and the verdict's fragility use the registry's identifiers (issue [21])."""
    from statue2model.assessment import states

    out = small_run.out
    ids = set(states.IDS)
    ls = json.loads((out / "dynamics" / "limit_states.json").read_text())
    assert {r["name"] for r in ls["rows"]} <= ids
    fr = json.loads((out / "dynamics" / "fragility.json").read_text())
    assert set(fr["limit_states"]) <= ids and fr["limit_states"]
    for key in fr["curves"]:
        sid, base = states.STATE_OF_CURVE[key]
        assert sid in ids and key.startswith(sid + "_") and key.endswith(base)
    assert set(fr["ratio_of_medians"]) <= ids | {"overturning_alone"}
    cls = json.loads((out / "crosscheck" / "classification.json").read_text())
    for base in ("fixed", "isolated"):
        if cls.get(base):
            assert set(cls[base]["states"]) <= ids
    v = json.loads((out / "run.json").read_text())["verdict"]
    assert set((v.get("fragility") or {}).get("limit_states") or {}) <= ids


@pytest.mark.slow
def test_run_writes_every_stage_report_and_resolved_config(small_run):
    res = small_run
    assert {k: v["status"] for k, v in res.stages.items()} == {
        "params": "done", "prototype": "done", "isolator": "done", "dynamics": "done", "crosscheck": "done"}
    out = res.out
    props = json.loads((out / "params" / "props.json").read_text())
    assert props["a_R"] == pytest.approx(2.7170, abs=1e-4)
    assert min(p.name for p in (out / "prototype" / "layers").iterdir()) == "layer_001.dxf"
    assert (out / "prototype" / "layers.png").is_file()
    design = json.loads((out / "isolator" / "design.json").read_text())
    # the default scan (~410 kg) gets a device that passes every required check, the ball load (long-term
    # and at SLC), the collapse level and the reserve among them; its plates, drawing and price are written
    assert design["passed"] and design["what_would_pass"] is None and design["cost"] > 0
    checks = {c["key"]: c for c in design["checks"]}
    for key in ("ball_load", "ball_load_slc", "travel_slc", "th_travel", "th_travel_slc", "th_acceleration",
                "reserve", "depth", "proud"):
        assert checks[key]["required"] and checks[key]["passed"], key
    assert {c["level"] for c in design["checks"]} >= {"design", "SLC", "reserve", "static"}
    assert all({"key", "name", "passed", "required", "value", "limit"} <= set(c) for c in design["checks"])
    assert len(design["verification"]["sets"]) == 4
    for name in ("bottom_plate.dxf", "top_plate.dxf", "bottom_plate.3mf", "drawing.svg"):
        assert (out / "isolator" / "plates" / name).is_file(), name
    bom = (out / "isolator" / "bom.csv").read_text().splitlines()
    assert bom[0] == "item,material,quantity,unit,unit_cost,cost" and bom[-1].startswith("total,")
    assert float(bom[-1].split(",")[-1]) == pytest.approx(design["cost"], abs=0.01)
    # the device never makes the statue worse: its failure median at or right of the fixed base's overturning
    dyn = json.loads((out / "run.json").read_text())["stages"]["dynamics"]["data"]
    assert dyn["fragility_median_isolated"] >= dyn["fragility_median_fixed"]
    for name in ("spectrum_fixed", "spectrum_isolated", "variability", "history"):
        assert (out / "dynamics" / f"{name}.json").is_file() and (out / "dynamics" / f"{name}.png").is_file()
    cc = json.loads((out / "crosscheck" / "crosscheck.json").read_text())
    s = cc["summary"]
    assert s["n_cases"] + s["n_not_applicable"] + s["n_diagnostic"] == len(cc["cases"]) and s["n_cases"] > 3
    assert s["n_cases"] == sum(c["status"] in ("met", "missed") for c in cc["cases"])
    # the 2D/3D classification over the design records (>= 7 records), fixed base and the exact isolator
    cls = json.loads((out / "crosscheck" / "classification.json").read_text())
    for base in ("fixed", "isolated"):
        info = cls[base]["info"]
        assert info["n_records"] >= 7 and info["n_runs"] == info["n_records"] * len(info["levels_g"])
        assert {s: a["status"] for s, a in cls[base]["states"].items()}.keys() == {"full_contact", "overturning", "capacity"}
    assert cls["fixed"]["states"]["capacity"]["status"] == "not applicable"
    assert cls["isolated"]["states"]["capacity"]["status"] != "not applicable"
    assert load_config(out / "config.toml").to_dict() == small_config().to_dict()
    run = json.loads((out / "run.json").read_text())
    assert run["stages"]["dynamics"]["status"] == "done"
    page = res.report.read_text()
    for title in ("Rocking parameters", "Prototype: layers and sheets", "Rolling-ball isolator",
                  "2D analyses", "3D cross-check", "2D model against 3D physics", "Design checks",
                  "2D model against 3D physics over the design records"):
        assert title in page
    a = cls["fixed"]["states"]["full_contact"]["accuracy"]           # the report prints the json's numbers
    assert a["value"] is not None and f"{a['value']:.2f} [{a['lo']:.2f}-{a['hi']:.2f}]" in page


@pytest.mark.slow
def test_report_figures_load_in_headless_chromium(small_run):
    from statue2model.report.browser import check_figures, find_chromium

    if find_chromium() is None:
        if os.environ.get("CI"):
            pytest.fail("no headless browser: .ci/install installs chromium-headless-shell")
        pytest.skip("no headless browser (apt-get install chromium-headless-shell)")
    check = check_figures(small_run.report)
    # every stage's figure, plus the key figure beside the verdict on page 1 (the fragility curves)
    n_figs = sum(len(m.get("figures", [])) for m in small_run.stages.values()) + 1
    assert check.ok, check
    assert check.total == check.loaded == n_figs >= 8


def test_stages_not_asked_for_are_taken_from_their_folders(small_run, tmp_path):
    out = tmp_path / "copy"
    shutil.copytree(small_run.out, out)
    res = run_project(default_scan(), out, small_config(), stages=["params"], say=quiet)
    assert {k: v["status"] for k, v in res.stages.items()} == {k: "cached" for k in res.stages}
    page = res.report.read_text()
    # every stage's figure and page 1's key figure
    assert page.count("<img") == sum(len(m.get("figures", [])) for m in small_run.stages.values()) + 1


@pytest.mark.slow
def test_unchanged_inputs_are_cached_and_a_change_recomputes_what_depends_on_it(small_run, tmp_path):
    out = tmp_path / "copy"                       # a copy: small_run's own folder stays as its run left it
    shutil.copytree(small_run.out, out)
    cfg = small_config()
    again = run_project(default_scan(), out, cfg, stages=["isolator", "dynamics"], say=quiet, report=False)
    assert [again.stages[n]["status"] for n in ("params", "isolator", "dynamics")] == ["cached"] * 3
    t_before = (out / "dynamics" / "stage.json").stat().st_mtime_ns
    changed = small_config('[model]\nrtol = 1e-8\n')            # only the 2D analyses and the isolator read [model]
    res = run_project(default_scan(), out, changed, stages=["dynamics"], say=quiet, report=False)
    assert [res.stages[n]["status"] for n in ("params", "isolator", "dynamics")] == ["cached", "done", "done"]
    assert (out / "dynamics" / "stage.json").stat().st_mtime_ns != t_before
    forced = run_project(default_scan(), out, changed, stages=["params"], force=True, say=quiet, report=False)
    assert forced.stages["params"]["status"] == "done"
    assert load_config(out / "config.toml").model.rtol == 1e-8


@pytest.mark.slow
def test_executors_give_identical_numbers(small_run, tmp_path):
    """small_run (no executor: every stage in this process) against the same stages from scratch on
    2 worker processes."""
    from statue2model.compute.executors import ProcessExecutor

    a = small_run
    with ProcessExecutor(2) as ex:
        b = run_project(default_scan(), tmp_path / "b", small_config(), stages=["dynamics"], say=quiet, report=False,
                        executor=ex)
    assert [b.stages[n]["status"] for n in ("params", "isolator", "dynamics")] == ["done"] * 3
    assert a.stages["dynamics"]["data"] == b.stages["dynamics"]["data"]
    for name in ("spectrum_fixed.json", "spectrum_isolated.json", "variability.json"):
        ja = json.loads((a.out / "dynamics" / name).read_text())
        jb = json.loads((b.out / "dynamics" / name).read_text())
        assert ja == jb, name
    fa, fb = (json.loads((x.out / "dynamics" / "fragility.json").read_text()) for x in (a, b))
    assert fa["curves"] == fb["curves"] and fa["ratio_of_medians"] == fb["ratio_of_medians"]
    # 7 records x 7 parameter samples at every level the fixed base ran (coarse and adaptive)
    assert fa["curves"]["overturning_fixed"]["n_trials"] == [7 * 7] * len(fa["curves"]["overturning_fixed"]["levels"])


@pytest.mark.slow
def test_ctrl_c_leaves_no_partial_stage_and_a_rerun_resumes(tmp_path):
    """A real SIGINT to `statue2model run` while the 2D analyses run."""
    out = tmp_path / "run"
    assert main(["run", "--stages", "params", "--out", str(out)]) == 0     # a complete earlier run
    assert {"report.html", "run.json", "config.toml"} <= {p.name for p in out.iterdir()}
    project = tmp_path / "big.toml"
    project.write_text('[dynamics]\nfreq = "0.3:10:120"\namp = "0.05g:1.5g:120"\npga = "0.05g:1.5g:200"\n'
                       '[model]\nrtol = 1e-10\n')
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-m", "statue2model", "run", "--config", str(project), "--out", str(out),
                             "--stages", "dynamics", "--workers", "1"], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env=env)
    seen = []
    for line in proc.stdout:
        seen.append(line)
        if line.startswith("[3/3] dynamics") and "..." in line:
            break
    time.sleep(1.5)
    proc.send_signal(signal.SIGINT)
    rest, _ = proc.communicate(timeout=60)
    assert proc.returncode == 130, "".join(seen) + rest
    assert "interrupted" in rest and "Traceback" not in rest
    assert cache.completed(out / "params", json.loads((out / "params" / "stage.json").read_text())["key"])
    assert not (out / "dynamics").exists()
    assert not [p for p in out.iterdir() if ".partial-" in p.name]
    for stale in ("report.html", "run.json", "config.toml"):   # nothing from the earlier run looks current
        assert not (out / stale).exists(), stale
    r = run_project(default_scan(), out, load_config(project), stages=["isolator"], say=quiet, report=False)
    assert [r.stages[n]["status"] for n in ("params", "isolator")] == ["cached", "cached"]


def test_run_errors_are_one_line(tmp_path, capsys):
    assert main(["run", str(tmp_path / "none.ply"), "--out", str(tmp_path / "o")]) == 2
    bad = tmp_path / "bad.toml"
    bad.write_text("[dynamics]\namp = \"lots\"\n")
    assert main(["run", "--config", str(bad), "--out", str(tmp_path / "o")]) == 2
    assert main(["run", "--stages", "params,slicing", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 3 and all(e.startswith("statue2model: error: ") for e in err)
    assert "unknown stage(s) slicing" in err[2]
    assert not (tmp_path / "o").exists()


# --- a folder of scans ----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def collection(tmp_path_factory):
    folder = tmp_path_factory.mktemp("scans")
    for name in ("dancing_girl.ply", "maria_barjatinskaja.ply", "nefertiti_bust.obj"):
        shutil.copy(MESHES_DIR / name, folder / name)
    return folder


COLLECTION_CFG = '[crosscheck]\nenabled = false\n[prototype]\nenabled = false\n'


def _numbers(data):
    return [{k: v for k, v in row.items()} for row in data["table"]]


@pytest.mark.slow
def test_folder_of_scans_same_numbers_locally_and_on_dask(collection, tmp_path):
    from distributed import LocalCluster

    from statue2model.compute.executors import make_executor

    cfg = small_config(COLLECTION_CFG)
    with make_executor(workers=2) as ex:
        local = run_collection(collection, tmp_path / "local", cfg, executor=ex, say=quiet)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            make_executor(scheduler=cluster.scheduler_address) as ex:
        assert ex.name == "dask"
        dask = run_collection(collection, tmp_path / "dask", cfg, executor=ex, say=quiet)
    assert [r["scan"] for r in local["table"]] == ["dancing_girl.ply", "maria_barjatinskaja.ply", "nefertiti_bust.obj"]
    assert _numbers(local) == _numbers(dask)
    rows = {r["scan"]: r for r in local["table"]}
    assert rows["dancing_girl.ply"]["weakest uplift [g]"] == pytest.approx(0.2763, abs=1e-3)
    # every groove surface in range: the default scan gets a steel-race device, the light Nefertiti bust
    # (31 kg) a polymer one; Maria's device would exceed the largest plate at the collapse level and the reserve
    assert {r["scan"]: r["isolator passes"] for r in local["table"]} == {
        "dancing_girl.ply": True, "maria_barjatinskaja.ply": False, "nefertiti_bust.obj": True}
    for sub in ("dancing_girl", "maria_barjatinskaja", "nefertiti_bust"):
        assert (tmp_path / "local" / sub / "report.html").is_file()
        if sub == "maria_barjatinskaja":            # no passing device: no isolated analyses
            assert not (tmp_path / "local" / sub / "dynamics" / "spectrum_isolated.json").exists()
            continue
        a = json.loads((tmp_path / "local" / sub / "dynamics" / "spectrum_isolated.json").read_text())
        b = json.loads((tmp_path / "dask" / sub / "dynamics" / "spectrum_isolated.json").read_text())
        assert np.array_equal(a["codes"], b["codes"]) and a["theta_max_over_delta"] == b["theta_max_over_delta"]
    csv = (tmp_path / "local" / "collection.csv").read_text().splitlines()
    assert len(csv) == 4 and csv[0].startswith("rank,object,scan,room,floor,")
    # the verdict in words on every bundled scan (issue [21]): a code, a plain headline whose numbers are
    # the limit-state rows', one design PGA; the collection's row carries the same code
    from test_verdict import _plain

    for sub in ("dancing_girl", "maria_barjatinskaja", "nefertiti_bust"):
        v = json.loads((tmp_path / "local" / sub / "run.json").read_text())["verdict"]
        _plain(v)
        row = next(r for r in local["rows"] if r["object"] == sub)
        assert row["code"] == v["code"] and row["headline"] == v["headline"] and row["status"] == v["status"]
    # a re-run takes every stage of every scan from the cache
    again = run_collection(collection, tmp_path / "local", cfg, executor=None, say=quiet)
    assert all({r["status"][s] for s in ("params", "isolator", "dynamics")} == {"cached"} for r in again["scans"])
    assert _numbers(again) == _numbers(local)


@pytest.mark.slow
def test_collection_cli_and_empty_folder(collection, tmp_path, capsys):
    cfgfile = tmp_path / "p.toml"
    cfgfile.write_text(small_toml(COLLECTION_CFG))
    assert main(["run", str(collection), "--config", str(cfgfile), "--out", str(tmp_path / "c"),
                 "--stages", "params", "--workers", "2"]) == 0
    out = capsys.readouterr().out
    assert "3 scans" in out and "nefertiti_bust.obj" in out
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["run", str(empty), "--out", str(tmp_path / "e")]) == 2
    assert "no scans" in capsys.readouterr().err


@pytest.mark.slow
def test_a_motion_record_named_by_the_project_file_is_part_of_the_cache_key(small_run, tmp_path):
    from statue2model.hazard import motions

    folder = tmp_path / "project"
    folder.mkdir()
    motions.write_record_csv(folder / "record.csv", motions.synthetic_record(duration=4, pga=0.3 * 9.81, seed=3))
    project = folder / "p.toml"
    project.write_text(small_toml('[dynamics]\nmotion = "file:path=record.csv,pga=0.5g"\n'))
    cfg = load_config(project)
    assert cfg.dynamics.motion == f"file:path={(folder / 'record.csv').resolve()},pga=0.5g"
    out = tmp_path / "out"
    shutil.copytree(small_run.out, out)           # the same params and isolator sections: only dynamics runs
    first = run_project(default_scan(), out, cfg, stages=["dynamics"], say=quiet, report=False)
    assert [first.stages[n]["status"] for n in ("params", "isolator", "dynamics")] == ["cached", "cached", "done"]
    assert load_config(out / "config.toml").dynamics.motion == cfg.dynamics.motion    # repeatable from anywhere
    assert run_project(default_scan(), out, cfg, stages=["dynamics"], say=quiet,
                       report=False).stages["dynamics"]["status"] == "cached"
    motions.write_record_csv(folder / "record.csv", motions.synthetic_record(duration=4, pga=0.3 * 9.81, seed=4))
    again = run_project(default_scan(), out, cfg, stages=["dynamics"], say=quiet, report=False)
    assert [again.stages[n]["status"] for n in ("params", "isolator", "dynamics")] == ["cached", "cached", "done"]
    assert again.stages["dynamics"]["data"] != first.stages["dynamics"]["data"]


@pytest.mark.slow
def test_without_the_isolator_the_analyses_run_on_the_fixed_base(tmp_path):
    cfg = small_config('[isolator]\nenabled = false\n[prototype]\nenabled = false\n[crosscheck]\nenabled = false\n')
    res = run_project(default_scan(), tmp_path / "o", cfg, say=quiet)
    assert {k: v["status"] for k, v in res.stages.items()} == {
        "params": "done", "prototype": "disabled", "isolator": "disabled", "dynamics": "done", "crosscheck": "disabled"}
    assert (tmp_path / "o" / "dynamics" / "spectrum_fixed.json").is_file()
    assert not (tmp_path / "o" / "dynamics" / "spectrum_isolated.json").exists()
    assert "no passing isolator design" in " ".join(res.stages["dynamics"]["text"])
    with pytest.raises(InputError, match="disabled in the configuration"):
        run_project(default_scan(), tmp_path / "o", cfg, stages=["isolator"], say=quiet)


@pytest.mark.slow
def test_scheduler_on_the_command_line_wins_and_bad_addresses_are_one_line(tmp_path, capsys):
    cfgfile = tmp_path / "p.toml"
    cfgfile.write_text("[run]\nworkers = 2\n")
    for address in ("foo", "tcp://127.0.0.1:1"):
        assert main(["run", "--config", str(cfgfile), "--scheduler", address, "--stages", "params",
                     "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "not a Dask scheduler address: 'foo'" in err and "cannot reach the Dask scheduler at tcp://127.0.0.1:1" in err
    assert "Traceback" not in err and "not both" not in err


def test_a_point_the_coupled_solver_cannot_finish_is_counted_not_fatal(monkeypatch):
    from statue2model.hazard import motions
    from statue2model.rocking import RockingModel
    from statue2model.geometry.rocking_params import RockingParams
    from statue2model.isolator import sweeps
    from statue2model.isolator.device import Isolator

    statue = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
    iso = Isolator(R=0.9, r=0.0095, M=statue.m + 15.0, mu=0.0073)
    model = RockingModel.housner(statue)
    monkeypatch.setattr(sweeps, "MAX_STEPS", 20)        # far too few steps for any run that moves
    sp = sweeps.isolated_spectrum(iso, model, [1.0], [0.0, 1.0 * 9.81])
    assert sp.codes.tolist() == [[0, sweeps.FAILED]] and np.isnan(sp.theta_max_over_delta[0, 1])
    assert "solver failed" in sp.to_csv()
    sw, acc = sweeps.isolated_variability(iso, model, motions.cosine_pulse(9.81, 1.0), [0.0, 9.81])
    assert sw.to_dict()["outcome"] == ["no motion", "solver failed"] and np.isnan(acc[1])


def test_the_verdict_rests_on_the_design_set_and_never_contradicts_run_json(small_run):
    """The run's recommendation against the limit states in run.json (the design record set's mean
    demands): no sentence says 'does not protect' while every isolated limit state holds, and so on
    (tests/test_verdict.py's checker); the design set and its limit states are on disk."""
    from test_verdict import _consistent

    run = json.loads((small_run.out / "run.json").read_text())
    v = run["verdict"]
    assert v["limit_states"]["n_records"] >= 7 and v["limit_states"]["statistic"] == "mean"
    _consistent(v)
    ls = json.loads((small_run.out / "dynamics" / "limit_states.json").read_text())
    assert ls["rows"] == v["limit_states"]["rows"]
    sj = json.loads((small_run.out / "dynamics" / "records" / "set.json").read_text())
    assert sj["check"]["met"] and len(sj["files"]) == ls["n_records"]
