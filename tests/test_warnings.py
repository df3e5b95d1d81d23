"""Warnings reach the user: every stage's warnings on the console (also from the cache),
in run.json and in the report; implausible densities; ``--up -y`` on the command line."""
from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from statue2model.cli import build_parser, main
from statue2model.errors import InputError
from statue2model.geometry.body import body_from_mesh
from statue2model.geometry.massprops import check_density_mass, density_warning, resolve_density
from statue2model.pipeline.run import run_project
from statue2model.report.html import render_html


@pytest.fixture(scope="module")
def cm_box(tmp_path_factory):
    """A 30 x 20 x 100 cm block written in centimetres: 100 units fits mm, cm and inches."""
    path = tmp_path_factory.mktemp("scan") / "block_cm.stl"
    trimesh.creation.box(extents=(30.0, 20.0, 100.0)).export(path)
    return path


def test_units_unsure_reaches_console_run_json_and_report_also_from_the_cache(cm_box, tmp_path):
    said = []
    out = tmp_path / "run"
    res = run_project(cm_box, out, stages=["params"], report=True, say=said.append)
    assert res.stages["params"]["status"] == "done"
    # the block was read as millimetres: 0.1 m tall, 0.159 kg, and the user is told
    assert res.stages["params"]["data"]["m"] == pytest.approx(2650 * 0.03 * 0.02 * 0.1 * 1e-3 * 1e3, rel=1e-9)
    warn = [m for m in said if m.startswith("        warning: units unsure")]
    assert len(warn) == 1 and "assumed mm" in warn[0] and "cm would give 1 m" in warn[0], said
    # after the params stage line, before anything else
    assert said.index(warn[0]) > next(i for i, m in enumerate(said) if "params" in m and "done" in m)

    run = json.loads((out / "run.json").read_text())
    assert run["stages"]["params"]["warnings"] == [warn[0].split("warning: ", 1)[1]]
    assert run["warnings"] == [{"stage": "params", "text": warn[0].split("warning: ", 1)[1]}]
    assert res.warnings == run["warnings"]

    page = (out / "report.html").read_text(encoding="utf-8")
    top, sections = page.split('<section id="params">', 1)
    assert 'class="warning warnings"' in top and "1 warning:" in top and "units unsure" in top
    assert top.index("units unsure") < top.index('<table class="summary">')   # above the numbers
    params_html = sections.split("</section>", 1)[0]
    assert '<p class="warning">warning: units unsure' in params_html
    assert page.count("units unsure") == 2                  # once at the top, once in its section

    said2 = []
    res2 = run_project(cm_box, out, stages=["params"], report=True, say=said2.append)
    assert res2.stages["params"]["status"] == "cached"
    assert [m for m in said2 if "warning:" in m] == warn
    assert json.loads((out / "run.json").read_text())["warnings"] == run["warnings"]
    assert "units unsure" in (out / "report.html").read_text(encoding="utf-8")


def test_a_clean_scan_has_no_warning_block(tmp_path):
    path = tmp_path / "block_m.stl"
    trimesh.creation.box(extents=(0.3, 0.2, 1.0)).export(path)
    said = []
    res = run_project(path, tmp_path / "run", stages=["params"], report=True, say=said.append)
    assert res.warnings == [] and not any("warning" in m for m in said)
    assert json.loads((tmp_path / "run" / "run.json").read_text())["warnings"] == []
    assert 'class="warning' not in (tmp_path / "run" / "report.html").read_text(encoding="utf-8")


def test_run_command_counts_the_warnings(cm_box, tmp_path, capsys):
    assert main(["run", str(cm_box), "--out", str(tmp_path / "c"), "--stages", "params", "--workers", "1"]) == 0
    out = capsys.readouterr().out
    assert "        warning: units unsure" in out
    assert "\n1 warning: see above / run.json" in out


def test_report_warnings_are_escaped_and_link_to_their_section():
    doc = {"title": "t", "warnings": [("params", "Rocking parameters", "a <b> & c"), "loose <i>"],
           "sections": [{"id": "params", "title": "Rocking parameters", "warnings": ["a <b> & c"]}]}
    page = render_html(doc)
    assert '<a href="#params">Rocking parameters</a>: a &lt;b&gt; &amp; c' in page
    assert "<li>loose &lt;i&gt;</li>" in page and "<b>" not in page
    assert '<p class="warning">warning: a &lt;b&gt; &amp; c</p>' in page
    with pytest.raises(ValueError, match="warning"):
        render_html({"title": "t", "warnings": [("params", "x")]})


# --- densities -----------------------------------------------------------------------------------
@pytest.mark.parametrize("rho, unit, meant", [(2.65, "g/cm^3", "2650 kg/m^3"), (8.8, "g/cm^3", "8800 kg/m^3"),
                                              (2650000.0, "g/m^3", "2650 kg/m^3")])
def test_a_density_in_another_unit_is_refused_naming_the_unit(rho, unit, meant):
    with pytest.raises(InputError, match="not plausible for a solid object") as exc:
        check_density_mass(rho, None)
    assert unit in str(exc.value) and meant in str(exc.value)


@pytest.mark.parametrize("rho", [100.0, 400.0, 2650.0, 8800.0, 19300.0, 25000.0])
def test_plausible_densities_pass_silently(rho):
    check_density_mass(rho, None)
    assert density_warning(rho) is None


@pytest.mark.parametrize("rho", [30.0, 99.0, 25001.0, 29000.0])
def test_unusual_densities_warn_with_the_number(rho):
    check_density_mass(rho, None)                    # not refused ...
    w = density_warning(rho)                         # ... but warned
    assert w is not None and f"{rho:g} kg/m^3" in w and "100 to 25000" in w


def test_a_mass_implying_an_absurd_density_blames_units_or_mass():
    box = trimesh.creation.box(extents=(0.3, 0.2, 1.0))       # 0.06 m^3
    with pytest.raises(InputError, match=r"mass of 0.3 kg .* 0.06 m\^3 .* density of 5 kg/m\^3.*units"):
        body_from_mesh(box.vertices, box.faces, units="m", up="z", mass=0.3)
    with pytest.raises(InputError, match=r"density of 3.333e\+04 kg/m\^3"):
        body_from_mesh(box.vertices, box.faces, units="m", up="z", mass=2000.0)
    assert resolve_density(0.06, mass=159.0) == pytest.approx(2650.0)
    w = density_warning(60.0, mass=3.6, volume=0.06)
    assert "3.6 kg" in w and "0.06 m^3" in w and "60 kg/m^3" in w and "units" in w


def test_props_refuses_density_in_g_per_cm3(tmp_path, capsys):
    path = tmp_path / "box.stl"
    trimesh.creation.box(extents=(0.3, 0.2, 1.0)).export(path)
    code = main(["props", str(path), "--density", "2.65", "--json", str(tmp_path / "p.json")])
    err = capsys.readouterr().err
    assert code == 2 and "g/cm^3 (2650 kg/m^3)" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "p.json").exists()


# --- the command line ----------------------------------------------------------------------------
def _frustum(path):
    """A square frustum 1 m tall along y: 0.4 m square at y = 0, 0.2 m square at y = 1."""
    pts = [(sx * a, y, sz * a) for y, a in ((0.0, 0.2), (1.0, 0.1)) for sx in (-1, 1) for sz in (-1, 1)]
    trimesh.convex.convex_hull(np.array(pts)).export(path)
    return path


@pytest.mark.parametrize("up, h", [("-y", 1 - 0.44 / 1.12), ("y", 0.44 / 1.12)])
def test_up_minus_y_with_a_space(tmp_path, capsys, up, h):
    path = _frustum(tmp_path / "frustum.stl")
    out = tmp_path / f"p{up}.json"
    code = main(["props", str(path), "--units", "m", "--up", up, "--direction", "0", "--json", str(out)])
    assert code == 0, capsys.readouterr().err
    d = json.loads(out.read_text())
    assert d["up"] == ("-y" if up == "-y" else "+y")
    assert d["h"] == pytest.approx(h, rel=1e-9)           # centroid of a frustum from either end


def test_argparse_alone_would_take_minus_y_for_an_option():
    with pytest.raises(SystemExit):
        build_parser().parse_args(["props", "m.stl", "--up", "-y"])


def test_props_prints_body_warnings(cm_box, tmp_path, capsys):
    assert main(["props", str(cm_box), "--json", str(tmp_path / "p.json")]) == 0
    out = capsys.readouterr().out
    assert "\nwarning: units unsure: assumed mm" in out
