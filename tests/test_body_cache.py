"""The Body is built once per run and kept beside props.json (OUT/params/body.npz):
equal to a fresh one field by field, read instead of the scan by a later run, and a
stale, malformed or tampered file is ignored (the Body is built again), never an error."""
from __future__ import annotations

import dataclasses
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from statue2model.geometry import body as geometry_body
from statue2model.geometry.body_store import body_arrays, read_body, write_body
from statue2model.io.paths import default_scan
from statue2model.pipeline.body_cache import BODY_FILE, body_key
from statue2model.pipeline.cache import file_hash
from statue2model.pipeline.config import load_config_text
from statue2model.pipeline.run import run_project
from statue2model.pipeline.stages import Context

SMALL = '[prototype]\nscale = "1:6"\npreviews = false\n[isolator]\nenabled = false\n'
CC = '[crosscheck]\nquick = true\nisolator = false\nmotion = "sine:amp=0.4g,freq=2"\n'
# what a run writes that does not depend on the clock (DXF headers hold the time; slice.json the timings)
STABLE = ("params/props.json", "params/props_rose.csv", "prototype/bom.csv", "prototype/assembly.txt",
          "prototype/prototype.json", "prototype/prototype.stl")


def config(extra: str = ""):
    return load_config_text(SMALL + extra, "test.toml")


def options(cfg) -> dict:
    s = cfg.scan
    return dict(units=s.units, up=s.up, height=s.height, density=None if s.mass is not None else s.density,
                mass=s.mass, base_tol=s.base_tol)


def assert_same(a, b, where="body"):
    """Field by field: arrays of the same dtype, shape and values; scalars equal and of the same type."""
    assert type(a) is type(b), where
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            assert_same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b), where
    elif isinstance(a, tuple):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{where}[{i}]")
    else:
        assert a == b, where


class Counter:
    """Counts calls of geometry.body.load_body (a Body built) and of its read_scan (the scan read)."""

    def __init__(self, monkeypatch):
        self.built = self.read = 0
        build, read = geometry_body.load_body, geometry_body.read_scan

        def counted_build(*a, **k):
            self.built += 1
            return build(*a, **k)

        def counted_read(*a, **k):
            self.read += 1
            return read(*a, **k)

        monkeypatch.setattr(geometry_body, "load_body", counted_build)
        monkeypatch.setattr(geometry_body, "read_scan", counted_read)


def quiet(msg):
    pass


@pytest.fixture(scope="module")
def first(tmp_path_factory) -> Path:
    """A complete params + prototype run of the default scan; its Body was built once."""
    out = tmp_path_factory.mktemp("first") / "run"
    with pytest.MonkeyPatch.context() as mp:
        n = Counter(mp)
        res = run_project(default_scan(), out, config(), stages=["params", "prototype"], report=False, say=quiet)
    assert [res.stages[s]["status"] for s in ("params", "prototype")] == ["done", "done"]
    assert (n.built, n.read) == (1, 1)                      # params and prototype: one Body
    return out


def copy_of(first: Path, tmp_path: Path) -> Path:
    out = tmp_path / "run"
    shutil.copytree(first, out, symlinks=True)
    return out


def stable_outputs(out: Path) -> dict:
    return {name: file_hash(out / name) for name in STABLE}


def rerun_prototype(out: Path, cfg=None):
    """The prototype computed again, the params stage taken from its folder."""
    res = run_project(default_scan(), out, cfg or config(), stages=["prototype"], force=True, report=False, say=quiet)
    assert (res.stages["params"]["status"], res.stages["prototype"]["status"]) == ("cached", "done")
    return res


def stage_context(cfg, params: Path) -> Context:
    """The Context a later stage of a run gets: the params stage's folder and its manifest."""
    man = json.loads((params / "stage.json").read_text()) if (params / "stage.json").is_file() else {}
    return Context(mesh=default_scan(), config=cfg, dirs={"params": params}, manifests={"params": man})


def restamp(out: Path) -> None:
    """Record body.npz's new bytes in the params stage's manifest, as one who edits a
    folder on purpose would: the stage still looks complete, so the file is read."""
    manifest = out / "params" / "stage.json"
    m = json.loads(manifest.read_text())
    m["files"][BODY_FILE] = file_hash(out / "params" / BODY_FILE)
    manifest.write_text(json.dumps(m))


# --- the stored Body ------------------------------------------------------------------------------
def test_the_stored_body_equals_a_fresh_one_field_by_field(first, monkeypatch):
    cfg = config()
    fresh = geometry_body.load_body(default_scan(), **options(cfg))
    stored = read_body(first / "params" / BODY_FILE, body_key(default_scan(), options(cfg)))
    assert stored is not None
    assert_same(fresh, stored)
    n = Counter(monkeypatch)
    via_stage = stage_context(cfg, first / "params").load_body()
    assert (n.built, n.read) == (0, 0)
    assert_same(fresh, via_stage)
    assert fresh.rocking().to_dict() == stored.rocking().to_dict()
    assert fresh.rose().to_dict() == stored.rose().to_dict()


def test_the_file_is_one_of_the_stage_files(first):
    files = json.loads((first / "params" / "stage.json").read_text())["files"]
    assert BODY_FILE in files and files[BODY_FILE] == file_hash(first / "params" / BODY_FILE)


def test_a_stage_computed_again_replaces_the_file_as_its_own(first, tmp_path):
    out = copy_of(first, tmp_path)
    res = run_project(default_scan(), out, config(), stages=["params"], force=True, report=False, say=quiet)
    assert res.stages["params"]["status"] == "done"          # body.npz is not a foreign file
    assert (out / "params" / BODY_FILE).is_file()


def test_each_stage_gets_its_own_copy(first):
    ctx = stage_context(config(), first / "params")
    a = ctx.load_body()
    a.vertices[:] = 0.0                                       # a stage that writes into its Body ...
    assert ctx.load_body().vertices[:, 2].max() > 1.0         # ... does not change the next stage's


# --- within a run, and across runs ----------------------------------------------------------------
@pytest.mark.slow
def test_one_body_per_run_for_params_prototype_and_crosscheck(tmp_path, monkeypatch):
    pytest.importorskip("pybullet")
    n = Counter(monkeypatch)
    res = run_project(default_scan(), tmp_path / "run", config(CC), stages=["params", "prototype", "crosscheck"],
                      report=False, say=quiet)
    assert [res.stages[s]["status"] for s in ("params", "prototype", "crosscheck")] == ["done"] * 3
    assert (n.built, n.read) == (1, 1)


def test_a_second_run_reads_the_body_not_the_scan(first, tmp_path, monkeypatch):
    out = copy_of(first, tmp_path)
    n = Counter(monkeypatch)
    rerun_prototype(out)
    assert (n.built, n.read) == (0, 0)
    assert stable_outputs(out) == stable_outputs(first)


def _object_array(out: Path, marker: Path) -> None:
    class Planted:                  # what unpickling it would do: leave a file behind
        def __reduce__(self):
            return (Path.touch, (marker,))

    arrays = body_arrays(read_body(out / "params" / BODY_FILE, body_key(default_scan(), options(config()))))
    arrays["vertices"] = np.array([Planted()], dtype=object)
    np.savez(out / "params" / BODY_FILE, **arrays)


def _rewrite(out: Path, change) -> None:
    path = out / "params" / BODY_FILE
    key = body_key(default_scan(), options(config()))
    arrays = body_arrays(read_body(path, key), key)
    change(arrays)
    with open(path, "wb") as fh:
        np.savez(fh, **arrays)


def _meta(change):
    def edit(arrays):
        meta = json.loads(arrays["meta"].tobytes())
        change(meta)
        arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    return edit


def _bytes(out: Path) -> bytes:
    return (out / "params" / BODY_FILE).read_bytes()


def _overwrite(out: Path, at: int, new: bytes) -> None:
    b = _bytes(out)
    (out / "params" / BODY_FILE).write_bytes(b[:at] + new + b[at + len(new):])


def _set(arrays, name, value):
    arrays[name] = value


TAMPER = {
    "changed bytes": lambda out, marker: _overwrite(out, len(_bytes(out)) // 2, b"\xff" * 64),
    "changed header": lambda out, marker: _overwrite(out, 0, b"NOPE"),
    "truncated": lambda out, marker: (out / "params" / BODY_FILE).write_bytes((out / "params" / BODY_FILE).read_bytes()[:999]),
    "not a zip": lambda out, marker: (out / "params" / BODY_FILE).write_text("{}"),
    "wrong key": lambda out, marker: _rewrite(out, _meta(lambda m: m.update(key="0" * 64))),
    "other format": lambda out, marker: _rewrite(out, _meta(lambda m: m.update(format="statue2model.body/0"))),
    "object array": _object_array,
    "wrong shape": lambda out, marker: _rewrite(out, lambda a: _set(a, "vertices", a["vertices"][:, :2].copy())),
    "wrong dtype": lambda out, marker: _rewrite(out, lambda a: _set(a, "faces", a["faces"].astype(float))),
    "non-finite": lambda out, marker: _rewrite(out, lambda a: a["vertices"].__setitem__((0, 0), np.nan)),
    "face out of range": lambda out, marker: _rewrite(out, lambda a: a["faces"].__setitem__((0, 0), 10**9)),
    "extra array": lambda out, marker: _rewrite(out, lambda a: _set(a, "extra", np.zeros(3))),
    "missing array": lambda out, marker: _rewrite(out, lambda a: a.pop("inertia")),
    "scalar type": lambda out, marker: _rewrite(out, _meta(lambda m: m.update(scale=["float", "1.0"]))),
    "a folder": lambda out, marker: ((out / "params" / BODY_FILE).unlink(), (out / "params" / BODY_FILE).mkdir()),
}


@pytest.mark.slow
@pytest.mark.parametrize("how", list(TAMPER))
def test_a_tampered_file_is_ignored_and_the_outputs_do_not_change(first, tmp_path, monkeypatch, how):
    out = copy_of(first, tmp_path)
    marker = tmp_path / "unpickled"
    TAMPER[how](out, marker)
    if how != "a folder":
        restamp(out)
    else:                                                     # the manifest lists body.npz as a file
        m = json.loads((out / "params" / "stage.json").read_text())
        m["files"][BODY_FILE] = "dir"
        (out / "params" / "stage.json").write_text(json.dumps(m))
    assert read_body(out / "params" / BODY_FILE, body_key(default_scan(), options(config()))) is None
    n = Counter(monkeypatch)
    rerun_prototype(out)
    assert (n.built, n.read) == (1, 1)                        # the Body was built from the scan again
    assert stable_outputs(out) == stable_outputs(first)
    assert not marker.exists()                                # nothing in the file was executed


def test_a_missing_file_is_built_again(tmp_path, monkeypatch):
    n = Counter(monkeypatch)
    body = stage_context(config(), tmp_path / "nowhere").load_body()
    assert (n.built, n.read, body.mass.density) == (1, 1, 2650.0)


def test_a_file_the_manifest_does_not_list_is_not_read(first, tmp_path, monkeypatch):
    """A body.npz with the right key that the params stage did not write (not in its manifest,
    or with other bytes than it lists) is never used: the Body is built from the scan."""
    params = copy_of(first, tmp_path) / "params"
    man = json.loads((params / "stage.json").read_text())
    n = Counter(monkeypatch)
    unlisted = Context(mesh=default_scan(), config=config(), dirs={"params": params},
                       manifests={"params": {k: v for k, v in man.items() if k != "files"}})
    assert_same(unlisted.load_body(), geometry_body.load_body(default_scan(), **options(config())))
    assert (n.built, n.read) == (2, 2)                    # the stage's Body and the reference
    man["files"][BODY_FILE] = "0" * 64
    other = Context(mesh=default_scan(), config=config(), dirs={"params": params}, manifests={"params": man})
    other.load_body()
    assert (n.built, n.read) == (3, 3)


def test_the_body_lives_with_the_run(first, monkeypatch):
    """Two Contexts (two runs) share nothing: each builds or reads its own Body."""
    n = Counter(monkeypatch)
    Context(mesh=default_scan(), config=config()).load_body()
    Context(mesh=default_scan(), config=config()).load_body()
    assert (n.built, n.read) == (2, 2)


# --- the key --------------------------------------------------------------------------------------
@pytest.mark.parametrize("setting", ['density = 2400.0', 'mass = 400.0', 'units = "mm"', 'up = "z"',
                                     'height = 1.7', 'base_tol = 0.004'])
def test_a_changed_scan_setting_is_another_key(setting):
    assert body_key(default_scan(), options(config(f"[scan]\n{setting}\n"))) != \
        body_key(default_scan(), options(config()))


def test_a_changed_density_builds_the_body_again(first, monkeypatch):
    cfg = config("[scan]\ndensity = 2400.0\n")
    assert read_body(first / "params" / BODY_FILE, body_key(default_scan(), options(cfg))) is None
    n = Counter(monkeypatch)
    body = stage_context(cfg, first / "params").load_body()
    assert (n.built, n.read) == (1, 1) and body.mass.density == 2400.0
    assert_same(body, geometry_body.load_body(default_scan(), **options(cfg)))


def test_the_runs_scan_hash_gives_the_same_key():
    """The run hashes its scan once and hands the hash on: the key is the one read from the file."""
    opts = options(config())
    assert body_key(default_scan(), opts, file_hash(default_scan())) == body_key(default_scan(), opts)
    assert body_key(default_scan(), opts, "0" * 64) != body_key(default_scan(), opts)


def test_another_scan_is_another_key(tmp_path):
    other = tmp_path / default_scan().name
    other.write_bytes(default_scan().read_bytes() + b"\n")
    assert body_key(other, {}) != body_key(default_scan(), {})
    shutil.copy(default_scan(), other)
    assert body_key(other, {}) != body_key(default_scan(), {})      # the Body records where it was read from


def test_write_and_read_round_trip_keeps_every_field(tmp_path):
    fresh = geometry_body.load_body(default_scan(), density=2400.0, base_tol=0.004)
    path = write_body(tmp_path / "b.npz", fresh, key="k")
    assert_same(fresh, read_body(path, "k"))
    assert read_body(path, "other") is None and read_body(tmp_path / "missing.npz", "k") is None


def test_a_body_that_would_not_read_back_is_not_written(tmp_path):
    fresh = geometry_body.load_body(default_scan())
    for odd in (dataclasses.replace(fresh, scale=float("nan")), dataclasses.replace(fresh, scale=np.float32(1.0)),
                dataclasses.replace(fresh, vertices=np.full_like(fresh.vertices, np.inf))):
        assert write_body(tmp_path / "b.npz", odd, key="k") is None
        assert not (tmp_path / "b.npz").exists()

