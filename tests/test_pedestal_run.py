"""A statue on a pedestal in a run (issue [22], items 3-4): the stack's rows in dynamics/limit_states.json,
finite; a heavy wide pedestal leaves the statue's rows as without it; the verdict names the pedestal."""
from __future__ import annotations

import json
import math

import pytest

from statue2model.cli import main

FAST = "[prototype]\nenabled = false\n[isolator]\nenabled = false\n[dynamics]\nfragility = false\n"


def _run(tmp_path, name, text):
    (tmp_path / f"{name}.toml").write_text(FAST + text)
    out = tmp_path / name
    assert main(["run", "--config", str(tmp_path / f"{name}.toml"), "--out", str(out)]) == 0
    return json.loads((out / "dynamics" / "limit_states.json").read_text()), json.loads((out / "run.json").read_text())


def _rows(ls):
    return {(r["base"], r["name"]): r for r in ls["rows"]}


def test_the_default_scan_on_a_pedestal_gets_the_stack_rows(tmp_path):
    """Done-when of issue [22]: the default scan on a 0.6 x 0.6 x 1.0 m, 250 kg pedestal: rows for the statue
    sliding on the pedestal, the pedestal sliding and the pedestal overturning, finite demand and capacity."""
    ls, run = _run(tmp_path, "ped", "[pedestal]\nsize = [0.6, 0.6, 1.0]\nmass = 250\n")
    rows = _rows(ls)
    for name in ("sliding", "pedestal_sliding", "pedestal_overturning"):
        r = rows["fixed", name]
        assert math.isfinite(r["demand"]) and math.isfinite(r["capacity"]) and r["capacity"] > 0, r
        assert 0 <= r["n_exceeding"] <= ls["n_records"] and len(r["per_record"]) == ls["n_records"]
    assert "pedestal top's edge" in rows["fixed", "sliding"]["details"]["capacity_source"]
    # the scan's base is 0.633 m across: on a 0.6 m top it overhangs, and the run says so
    assert any("overhangs the pedestal's top by" in w for w in ls["warnings"])
    # the pedestal (0.6 m wide, 1 m tall, lighter than the statue) lifts: the stack is slender
    assert all(r["ped_uplift"] for r in ls["fixed_records"])
    n_ped = rows["fixed", "pedestal_overturning"]["n_exceeding"]
    v = run["verdict"]
    if n_ped:
        assert v["code"] == "PEDESTAL_OVERTURNS" and f"in {n_ped} of 7 design records" in v["headline"]
        # the statue falls with its pedestal: its own overturning row counts those records too
        assert rows["fixed", "overturning"]["n_exceeding"] >= n_ped
    json.dumps(ls, allow_nan=False)


@pytest.mark.slow
def test_a_heavy_wide_pedestal_leaves_the_statue_as_on_the_floor(tmp_path):
    """Done-when of issue [22]: on a 3 x 3 x 0.2 m, 10 t pedestal with friction 1.0 the statue's full-contact
    and overturning demands equal the run without a pedestal within 3 %; the pedestal stays down."""
    common = "[sliding]\nmu_statue = 1.0\nmu_pedestal = 1.0\n"
    floor, _ = _run(tmp_path, "floor", common)
    ped, _ = _run(tmp_path, "heavy", common + "[pedestal]\nsize = [3.0, 3.0, 0.2]\nmass = 10000\n")
    a, b = _rows(floor), _rows(ped)
    for name in ("full_contact", "rocking", "overturning"):
        assert b["fixed", name]["demand"] == pytest.approx(a["fixed", name]["demand"], rel=0.03, abs=1e-9), name
        assert b["fixed", name]["n_exceeding"] == a["fixed", name]["n_exceeding"]
    assert not any(r["ped_uplift"] for r in ped["fixed_records"])
    assert b["fixed", "pedestal_overturning"]["n_exceeding"] == 0 and b["fixed", "pedestal_sliding"]["demand"] == 0
    assert ("fixed", "pedestal_sliding") not in a and ("fixed", "sliding") in a


def test_objects_give_each_object_its_pedestal():
    """[objects] (issue [22], item 7): an object's inline table gives it its own pedestal (or none), read and
    checked as [pedestal]; the resolved file reads back the same."""
    from statue2model.errors import InputError
    from statue2model.pipeline.config import load_config_text
    from statue2model.pipeline.rooms import config_for

    cfg = load_config_text('[pedestal]\nsize = [1.0, 1.0, 0.5]\nmass = 800\n[objects]\n'
                           '"maria_*" = { pedestal = { size = [0.6, 0.6, 1.0], mass = 250, position = [0.05, 0] } }\n'
                           '"vase.ply" = { floor = 0, pedestal = false }\n')
    assert config_for(cfg, "maria_b.ply").pedestal.size == (0.6, 0.6, 1.0)
    assert config_for(cfg, "maria_b.ply").pedestal.position == (0.05, 0.0)
    assert config_for(cfg, "vase.ply").pedestal.size is None                  # on the floor
    assert config_for(cfg, "nefertiti.ply").pedestal.size == (1.0, 1.0, 0.5)  # [pedestal]
    again = load_config_text(cfg.to_toml(), "resolved")
    assert again.objects == cfg.objects and again.pedestal == cfg.pedestal
    for bad, msg in (('{ pedestal = { size = [0.6, 0.6, 1.0] } }', "both size"),
                     ('{ pedestal = { size = [0.6, 0.6, 1.0], mass = 250, colour = 1 } }', "unknown key 'colour'"),
                     ('{ pedestal = 3 }', "a table")):
        with pytest.raises(InputError, match=msg):
            load_config_text(f'[objects]\n"a.ply" = {bad}\n', "t.toml")


@pytest.mark.slow
def test_a_pedestal_scan_loads_like_a_statue_scan(tmp_path):
    """[pedestal] file (issue [22]): a scan of a 1.2 x 1.2 x 0.5 m pedestal, read by the statue's loader (units,
    up, density), gives the same rows as the box of the same size and mass (a squat pedestal that stays down: a
    rocking one is chaotic, and the scan's sizes are the box's to 1e-8 only); a missing file is one line."""
    import trimesh

    from statue2model.errors import InputError
    from statue2model.pipeline.config import load_config_text

    trimesh.creation.box(extents=[1200.0, 1200.0, 500.0]).export(tmp_path / "plinth.stl")   # in mm
    box, _ = _run(tmp_path, "box", "[pedestal]\nsize = [1.2, 1.2, 0.5]\nmass = 1500\n")
    scan, _ = _run(tmp_path, "scan", '[pedestal]\nfile = "plinth.stl"\nunits = "mm"\nup = "z"\n'
                   f"density = {1500 / 0.72!r}\n")
    a, b = _rows(box), _rows(scan)
    assert set(a) == set(b)
    for key in a:
        for f in ("demand", "capacity", "ratio"):
            assert b[key][f] == pytest.approx(a[key][f], rel=1e-6, abs=1e-9), (key, f)
    with pytest.raises(InputError, match="file .* is not a readable file"):
        load_config_text('[pedestal]\nfile = "nowhere.stl"\n', str(tmp_path / "p.toml"), base_dir=tmp_path)
    with pytest.raises(InputError, match="either size .* or file"):
        load_config_text('[pedestal]\nfile = "plinth.stl"\nsize = [1, 1, 1]\nmass = 3\n', "p.toml", base_dir=tmp_path)


@pytest.mark.slow
def test_the_isolator_under_the_pedestal_carries_the_stack(tmp_path):
    """[isolator] under = "pedestal" (issue [22], item 6): the device is designed for the statue and its pedestal
    (their mass on the balls), its top plate carries the pedestal's base, and the felt acceleration is held
    against the smaller of the statue's and the stack's uplift; without a pedestal the key is refused."""
    from statue2model.errors import InputError
    from statue2model.pipeline.config import load_config_text

    with pytest.raises(InputError, match='under = "pedestal" needs a \\[pedestal\\]'):
        load_config_text('[isolator]\nunder = "pedestal"\n', "p.toml")
    text = ("[prototype]\nenabled = false\n[dynamics]\nfragility = false\n[pedestal]\nsize = [1.3, 1.3, 0.5]\n"
            "mass = 1500\n")
    (tmp_path / "p.toml").write_text(text + '[isolator]\nunder = "pedestal"\n')
    assert main(["run", "--config", str(tmp_path / "p.toml"), "--out", str(tmp_path / "o"),
                 "--stages", "params,isolator"]) == 0
    d = json.loads((tmp_path / "o" / "isolator" / "design.json").read_text())
    statue = json.loads((tmp_path / "o" / "params" / "props.json").read_text())["m"]
    assert d["carries"]["under"] == "pedestal" and d["carries"]["mass"] == pytest.approx(statue + 1500)
    assert d["M"] > statue + 1500 and d["side"] >= 1.3
    assert d["a_lim"] <= min(9.81 * 0.3094 / 0.7316, 9.81 * 0.2026 / 0.7316) + 1e-3   # the statue's own uplift
