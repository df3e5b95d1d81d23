"""The ``props`` command: output files, and one clear line for every kind of bad input."""
import json
import re
import subprocess
import sys

import numpy as np
import pytest
import trimesh

from statue2model.cli import main
from statue2model.geometry.rocking_params import PARAM_KEYS


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_props_default_scan_writes_json_and_plot(tmp_path, capsys):
    out = tmp_path / "res" / "props.json"
    code, stdout, err = run(["props", "--json", str(out)], capsys)
    assert code == 0, err
    assert "Rocking parameters" in stdout and "Weakest direction" in stdout
    data = json.loads(out.read_text())
    for key in PARAM_KEYS + ("volume", "mass", "com", "direction_deg", "footprint", "inertia", "rose"):
        assert key in data, key
    assert data["units"] == "m" and data["up"] == "+y"
    assert data["a_R"] <= data["a_L"]  # weakest direction puts the weak side on the right
    assert data["direction_deg"] == pytest.approx(data["rose"]["weakest_direction_deg"])
    rose = data["rose"]
    assert len(rose["a_tip"]) == 360 and len(rose["b_L"]) == 360 and len(rose["I_G"]) == 360
    i = int(round(data["direction_deg"])) % 360  # the sampled direction next to the weakest one
    assert rose["direction_deg"][i] == i and rose["h"][i] == pytest.approx(data["h"])
    assert rose["a_R"][i] == pytest.approx(data["a_R"], rel=1e-3) and rose["a_R"][i] >= data["a_R"]
    assert rose["a_L"][i] == pytest.approx(rose["a_R"][(i + 180) % 360], rel=1e-12)
    csv_lines = (out.parent / "props_rose.csv").read_text().splitlines()
    assert len(csv_lines) == 361 and csv_lines[0].startswith("direction_deg,m,h,b_L,b_R,I_G")
    assert data["mass"] == pytest.approx(2650.0 * data["volume"])
    png = out.with_suffix(".png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list(tmp_path.rglob("*.part"))


def test_props_options(tmp_path, capsys):
    box = trimesh.creation.box(extents=(0.3, 0.2, 1.0))
    path = tmp_path / "box_mm.stl"
    box.apply_scale(1000.0)
    box.export(path)
    out = tmp_path / "p.json"
    code, _, err = run(["props", str(path), "--units", "mm", "--up", "z", "--mass", "150",
                        "--direction", "30", "--json", str(out)], capsys)
    assert code == 0, err
    d = json.loads(out.read_text())
    assert d["mass"] == pytest.approx(150.0) and d["direction_deg"] == pytest.approx(30.0)
    assert d["h"] == pytest.approx(0.5, rel=1e-6)
    code, _, err = run(["props", str(path), "--height", "2.0", "--up", "z", "--json", str(out)], capsys)
    assert code == 0, err
    assert json.loads(out.read_text())["h"] == pytest.approx(1.0, rel=1e-6)


def _write(tmp_path, name, content):
    p = tmp_path / name
    p.write_bytes(content) if isinstance(content, bytes) else p.write_text(content)
    return p


def _export(mesh, path):
    mesh.export(path)
    return path


def _open_sphere(tmp_path):
    s = trimesh.creation.icosphere(3, radius=0.3)
    keep = np.linalg.norm(s.triangles_center - [0.3, 0, 0], axis=1) > 0.25
    p = tmp_path / "open.ply"
    trimesh.Trimesh(s.vertices, s.faces[keep]).export(p)
    return p


def _leaning(tmp_path):
    import manifold3d

    plinth = manifold3d.Manifold.cube((0.1, 0.1, 0.1))
    arm = manifold3d.Manifold.cube((1.0, 0.1, 0.1)).translate((0.0, 0.0, 0.1))  # long arm over one side
    mesh = (plinth + arm).to_mesh64()
    p = tmp_path / "leaning.obj"
    trimesh.Trimesh(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts)).export(p)
    return p


BAD = {
    "missing": (lambda t: t / "nope.ply", [], "file not found"),
    "empty": (lambda t: _write(t, "empty.stl", b""), [], "file is empty"),
    "unreadable": (lambda t: _write(t, "junk.ply", b"this is not a ply file\n" * 5), [], "cannot read"),
    "unsupported": (lambda t: _write(t, "model.txt", "1 2 3\n"), [], "unsupported file type"),
    "nan": (lambda t: _write(t, "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n"),
            [], "NaN"),
    "zero_volume": (lambda t: _write(t, "flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"),
                    [], "encloses no volume"),
    "open": (_open_sphere, [], "not a closed volume"),
    "would_not_stand": (_leaning, ["--up", "z"], "would not stand"),
    "no_base_found": (lambda t: _export(trimesh.creation.icosphere(3, radius=0.3), t / "ball.stl"), [], "no flat base"),
    "wrong_units": (lambda t: t, ["--units", "mm"], "not plausible"),
    "bad_direction": (lambda t: t, ["--direction", "nan"], "finite"),
    "negative_density": (lambda t: t, ["--density", "-3"], "positive"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_one_line_nonzero_exit(tmp_path, capsys, case):
    make, extra, message = BAD[case]
    target = make(tmp_path)
    argv = ["props"] + ([] if target == tmp_path else [str(target)]) + extra + ["--json", str(tmp_path / "o.json")]
    if case in ("bad_direction", "negative_density"):  # argparse refuses these with status 2
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 2
        err = capsys.readouterr().err
        assert "Traceback" not in err and err.strip().splitlines()[-1].count("error") == 1
        assert message in err
        return
    code, out, err = run(argv, capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("statue2model: error: "), err
    assert re.search(message, lines[0]), lines[0]
    assert not (tmp_path / "o.json").exists()


def test_unwritable_output_folder(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    code, _, err = run(["props", "--json", str(blocker / "sub" / "p.json")], capsys)
    assert code == 2 and "cannot create output folder" in err


def test_console_entry_point_exit_code(tmp_path):
    r = subprocess.run([sys.executable, "-m", "statue2model", "props", str(tmp_path / "x.stl")],
                       capture_output=True, text=True, cwd=tmp_path)   # the default outputs/x/ is under tmp_path
    assert r.returncode == 2
    assert r.stderr.strip() == f"statue2model: error: file not found: {tmp_path / 'x.stl'}"


def test_run_pauses_the_cyclic_collector_and_restores_it(tmp_path, capsys, monkeypatch):
    """`statue2model run` works with the automatic cyclic garbage collection off and puts it back as it
    was, whether the command succeeds or fails (one-line error)."""
    import gc

    from statue2model.pipeline import run as prun

    seen = []

    def fake_run_project(*a, **k):
        seen.append(gc.isenabled())
        raise prun.InputError("stop here")

    monkeypatch.setattr(prun, "run_project", fake_run_project)
    assert gc.isenabled()
    code, _, err = run(["run", "--out", str(tmp_path / "o"), "--workers", "1"], capsys)
    assert code == 2 and err.strip().splitlines()[-1] == "statue2model: error: stop here"
    assert seen == [False] and gc.isenabled()
    gc.disable()
    try:
        run(["run", "--out", str(tmp_path / "o2"), "--workers", "1"], capsys)
        assert seen == [False, False] and not gc.isenabled()     # left off when it was off
    finally:
        gc.enable()
    # a folder of scans keeps the collector on (its scans run on the workers)
    folder = tmp_path / "scans"
    folder.mkdir()

    def fake_run_collection(*a, **k):
        seen.append(gc.isenabled())
        raise prun.InputError("stop here")

    monkeypatch.setattr(prun, "run_collection", fake_run_collection)
    code, _, err = run(["run", str(folder), "--out", str(tmp_path / "o3"), "--workers", "1"], capsys)
    assert code == 2 and seen == [False, False, True] and gc.isenabled()


def test_run_executor_keeps_one_scans_short_sweeps_here_and_a_folders_scans_on_the_pool(tmp_path):
    """`statue2model run` on one scan: local processes that take short sweeps in this process first
    (inline_first); on a folder (each task a whole scan) every task goes to the processes."""
    from types import SimpleNamespace

    from statue2model.cli.run import INLINE_FIRST, _executor
    from statue2model.pipeline.config import load_config

    cfg = load_config(None)
    (tmp_path / "scans").mkdir()
    for mesh, want in ((None, INLINE_FIRST), (str(tmp_path / "a.ply"), INLINE_FIRST), (str(tmp_path / "scans"), 0.0)):
        for workers in (None, 1):
            with _executor(SimpleNamespace(mesh=mesh, workers=workers, scheduler=None), cfg) as ex:
                assert ex.inline_first == want and ex._pool is None
