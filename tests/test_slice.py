"""`statue2model slice` end to end on the bundled default scan, and its parts on
shapes with known answers: DXF files (audit, units, read-back), rod holes (inside
every layer with the minimum wall), nesting (inside the sheet, no overlap), the
prototype as built (closed-form mass properties, STL volume, errors against the
scaled scan), section policies, compensation and bad input."""
import csv
import json
import math

import numpy as np
import pytest
import shapely
import trimesh
from shapely.geometry import MultiPolygon, Point, box

from statue2model.cli import main
from statue2model.errors import InputError
from statue2model.fabrication.dxf import audit, read_dxf, read_section_dxf
from statue2model.fabrication.layers import layer_bottoms, layer_sections
from statue2model.fabrication.prototype import (
    area_moments,
    stack_mass_properties,
    stack_mesh,
)
from statue2model.fabrication.rods import Rod, check_holes, place_rods
from statue2model.fabrication.spec import SliceSpec
from statue2model.fabrication.toolcheck import check_layer, compensate, trim_layer

WALL = 0.005


@pytest.fixture(scope="module")
def sliced(tmp_path_factory):
    out = tmp_path_factory.mktemp("slice") / "girl"
    assert main(["slice", "--scale", "1:2", "--out", str(out)]) == 0
    return out


@pytest.mark.slow
def test_output_folder_complete(sliced):
    names = {p.name for p in sliced.iterdir()}
    assert {"layers", "sheets", "bom.csv", "assembly.txt", "prototype.stl", "prototype.json", "slice.json"} <= names
    info = json.loads((sliced / "slice.json").read_text())
    assert info["n_layers"] == 95 == len(list((sliced / "layers").glob("layer_*.dxf")))
    assert info["pitch"] == pytest.approx(0.0095)
    n_sheets = info["sheets"]["n_sheets"]
    for ext in ("dxf", "png", "svg"):
        assert len(list((sliced / "sheets").glob(f"sheet_*.{ext}"))) == n_sheets
    assert not list(sliced.parent.glob(".*partial*"))


def test_layer_count_matches_height(sliced):
    """0.900 m at 1:2 over a 9.5 mm pitch: ceil(900 / 9.5) = 95 (the thesis: 87 cm, 9.56 mm -> 91)."""
    info = json.loads((sliced / "slice.json").read_text())
    assert info["height"] == pytest.approx(0.9, abs=1e-4)
    assert info["n_layers"] == math.ceil(info["height"] / info["pitch"])


@pytest.mark.slow
def test_every_dxf_audits_clean_in_mm(sliced):
    import ezdxf

    files = sorted((sliced / "layers").glob("*.dxf")) + sorted((sliced / "sheets").glob("*.dxf"))
    for path in files:
        assert audit(path) == [], path.name
        doc = ezdxf.readfile(str(path))
        assert doc.dxfversion == "AC1024"              # R2010
        assert doc.header["$INSUNITS"] == 4            # mm
        layers = {e.dxf.layer for e in doc.modelspace()}
        assert layers <= {"CUT_OUTSIDE", "CUT_INSIDE", "DRILL", "ENGRAVE"}
        for e in doc.modelspace().query("LWPOLYLINE"):
            assert e.closed == (e.dxf.layer in ("CUT_OUTSIDE", "CUT_INSIDE"))


@pytest.mark.slow
def test_layer_dxf_reads_back_to_the_sections(sliced):
    """Each layer file holds exactly that layer's section (in the statue frame)."""
    from statue2model.geometry.body import load_body
    from statue2model.io import paths

    body = load_body(paths.default_scan())
    v = body.vertices / 2
    secs = layer_sections(v, body.faces, layer_bottoms(v[:, 2].max(), 0.009, 0.0005), 0.009, "mid", 5e-5)
    secs = [trim_layer(s, 0.003)[0] for s in secs]      # less what the 3 mm cutter cannot make
    info = json.loads((sliced / "slice.json").read_text())
    for k in (0, 10, 40, 60, 94):
        back = read_dxf(sliced / "layers" / f"layer_{k + 1:03d}.dxf")
        assert back.outline.area == pytest.approx(secs[k].area, rel=1e-6, abs=1e-12)
        assert back.outline.symmetric_difference(secs[k]).area < 1e-6 * secs[k].area + 1e-12
        assert back.outline.area == pytest.approx(info["layers"][k]["area"], rel=1e-6)
        assert len(back.holes) == len(info["layers"][k]["holes"])
        assert back.hole == pytest.approx(0.0082) or len(back.holes) == 0


def test_holes_inside_every_layer_with_the_wall(sliced):
    info = json.loads((sliced / "slice.json").read_text())
    hole = info["rods"]["hole_diameter"]
    for k in range(0, 95, 3):
        back = read_dxf(sliced / "layers" / f"layer_{k + 1:03d}.dxf")
        for c in back.holes:
            p = Point(c)
            holder = [g for g in back.outline.geoms if g.contains(p)]
            assert holder, (k, c)
            assert holder[0].boundary.distance(p) - hole / 2 >= WALL - 1e-6
    # each rod's holes are in every layer it passes through
    for rod in info["rods"]["rods"]:
        for k in range(rod["first_layer"], rod["last_layer"] + 1):
            holes = np.array(info["layers"][k - 1]["holes"])
            assert np.min(np.hypot(holes[:, 0] - rod["x"], holes[:, 1] - rod["y"])) < 1e-9


def test_sheets_hold_parts_without_overlap(sliced):
    info = json.loads((sliced / "slice.json").read_text())
    W, H = info["spec"]["sheet"]
    spacing = info["spec"]["spacing"]
    placed = 0
    for path in sorted((sliced / "sheets").glob("sheet_*.dxf")):
        back = read_section_dxf(path)
        parts = list(back.geoms)
        placed += len(parts)
        sheet = box(0, 0, W, H)
        for p in parts:
            assert sheet.contains(p)
        tree = shapely.STRtree(parts)
        for i, p in enumerate(parts):
            for j in tree.query(p.buffer(spacing * 0.999)):
                if j != i:
                    assert p.distance(parts[j]) >= spacing * (1 - 1e-6), (path.name, i, j)
    assert placed == len(info["sheets"]["placements"])


def test_bom_and_assembly(sliced):
    rows = list(csv.DictReader((sliced / "bom.csv").open()))
    info = json.loads((sliced / "slice.json").read_text())
    sheets = [r for r in rows if r["item"].startswith("sheet")]
    assert len(sheets) == info["sheets"]["n_sheets"]
    total = rows[-1]
    assert total["item"] == "total"
    assert float(total["machining_min"]) == pytest.approx(sum(float(r["machining_min"]) for r in sheets), abs=0.2)
    rods = sum(int(r["quantity"]) for r in rows if r["item"] == "alignment rod")
    assert rods == len(info["rods"]["rods"])
    text = (sliced / "assembly.txt").read_text()
    assert "95. Layer 95" in text and text.count("insert a") == rods


def test_prototype_json_has_props_keys_and_small_errors(sliced):
    proto = json.loads((sliced / "prototype.json").read_text())
    for key in ("m", "h", "b_L", "b_R", "I_G", "d_L", "delta_R", "a_L", "a_R", "volume", "com", "inertia",
                "footprint", "rose", "direction_deg"):
        assert key in proto
    err = proto["errors_vs_scaled_scan"]
    assert abs(err["volume"]) < 0.01
    assert abs(err["h"]) < 0.03 and abs(err["b_L"]) < 0.03 and abs(err["b_R"]) < 0.05
    assert abs(err["I_G_per_mass"]) < 0.03 and err["com_offset"] < 0.01
    stl = trimesh.load(sliced / "prototype.stl")
    info = json.loads((sliced / "slice.json").read_text())
    assert stl.bounds[1, 2] == pytest.approx(94 * 0.0095 + 0.009, abs=1e-6)
    # boards + glue films, no holes: a little more than the drilled volume of the properties
    assert proto["volume"] < stl.volume < proto["volume"] * 1.01
    assert info["prototype"]["mass"] == pytest.approx(proto["m"])


def test_stack_mass_properties_closed_form():
    """Two boards with a glue film and a steel rod, against hand-computed moments."""
    a, b, t, g = 0.2, 0.1, 0.01, 0.002
    layer = MultiPolygon([box(0, 0, a, b)])
    rod = Rod(x=0.05, y=0.05, first=0, last=1, z_bottom=0.0, z_top=2 * t + g)
    hole, d = 0.0082, 0.008
    holes = [np.array([[0.05, 0.05]])] * 2
    mp = stack_mass_properties([layer, layer], pitch=t + g, board=t, glue=g, holes=holes, hole=hole,
                               rods=[rod], densities=(600.0, 1000.0, 7800.0), rod=d)
    A_hole = math.pi * hole**2 / 4 * (1 - 1e-3)   # polygonised circle: area within 0.1 %
    m_board = 600 * (a * b - math.pi * hole**2 / 4) * t
    m_glue = 1000 * (a * b - math.pi * hole**2 / 4) * g
    m_rod = 7800 * math.pi * d**2 / 4 * (2 * t + g)
    assert mp.mass == pytest.approx(2 * m_board + m_glue + m_rod, rel=1e-4)
    assert A_hole > 0
    # without the hole and rod: the box's inertia exactly
    plain = stack_mass_properties([layer, layer], pitch=t, board=t, glue=0.0, holes=[np.zeros((0, 2))] * 2,
                                  hole=0.0, rods=[], densities=(600.0, 0.0, 0.0))
    m = 600 * a * b * 2 * t
    c = 2 * t
    assert plain.mass == pytest.approx(m, rel=1e-12)
    np.testing.assert_allclose(plain.com, [a / 2, b / 2, t], rtol=1e-12)
    np.testing.assert_allclose(np.diag(plain.inertia), [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12,
                                                        m * (a * a + b * b) / 12], rtol=1e-12)
    np.testing.assert_allclose(plain.inertia - np.diag(np.diag(plain.inertia)), 0, atol=1e-15)


def test_area_moments_of_a_ring_and_mesh_volume():
    ring = Point(0.3, -0.2).buffer(0.1, quad_segs=256).difference(Point(0.3, -0.2).buffer(0.05, quad_segs=256))
    A, Sx, Sy, Ixx, Iyy, Ixy = area_moments(ring)
    exact = math.pi * (0.1**2 - 0.05**2)
    assert A == pytest.approx(exact, rel=1e-4)
    assert Sx / A == pytest.approx(0.3, rel=1e-12) and Sy / A == pytest.approx(-0.2, rel=1e-12)
    assert Ixx - A * 0.09 == pytest.approx(math.pi / 4 * (0.1**4 - 0.05**4), rel=1e-4)
    v, f = stack_mesh([MultiPolygon([ring])] * 3, pitch=0.01, board=0.009, glue=0.001)
    mesh = trimesh.Trimesh(v, f)
    assert mesh.volume == pytest.approx(A * (3 * 0.009 + 2 * 0.001), rel=1e-9)


def _legs_and_torso():
    """Two legs (layers 0-9) under one torso (layers 10-19)."""
    legs = MultiPolygon([box(-0.10, -0.04, -0.02, 0.04), box(0.02, -0.04, 0.10, 0.04)])
    torso = MultiPolygon([box(-0.11, -0.05, 0.11, 0.05)])
    return [legs] * 10 + [torso] * 10


def test_rods_per_island_group_where_the_stack_splits():
    stack = _legs_and_torso()
    plan = place_rods(stack, pitch=0.0095, board=0.009, hole=0.0082, wall=WALL)
    assert check_holes(stack, plan, WALL) == []
    assert plan.unaligned == ()
    for k in range(10):                                  # two holes in each leg
        for leg in stack[k].geoms:
            inside = [c for c in plan.holes[k] if leg.contains(Point(c))]
            assert len(inside) >= 2
            assert max(np.hypot(*(p - q)) for p in inside for q in inside) > 0.05   # far apart
    # every glue joint is crossed by rods
    for k in range(19):
        crossing = [r for r in plan.rods if r.first <= k and r.last >= k + 1]
        assert len(crossing) >= 2


def test_rods_report_what_cannot_be_drilled():
    thin = MultiPolygon([box(0, 0, 0.012, 0.2)])         # 12 mm wide: no 8.2 mm hole with 5 mm walls
    wide = MultiPolygon([box(0, 0, 0.2, 0.2)])
    plan = place_rods([wide, wide, thin, wide], pitch=0.0095, board=0.009, hole=0.0082, wall=WALL)
    assert any("layer 3 part A is too small" in w for w in plan.warnings)
    assert 1 in plan.unaligned and 2 in plan.unaligned
    with pytest.raises(InputError, match="does not fit through any two neighbouring layers"):
        place_rods([thin] * 4, pitch=0.0095, board=0.009, hole=0.0082, wall=WALL)


def test_section_policies_bracket_the_solid():
    """On a sphere: core <= mid <= envelope per layer, and the envelope's slabs
    contain the sphere's slab volume while the core's are contained in it."""
    R = 0.1
    m = trimesh.creation.icosphere(subdivisions=5, radius=R)
    v = m.vertices + [0, 0, R]
    z0 = layer_bottoms(2 * R, 0.009, 0.0, "mid")
    areas = {p: np.array([s.area for s in layer_sections(v, m.faces, z0, 0.009, p)]) for p in ("core", "mid", "envelope")}
    assert np.all(areas["core"] <= areas["mid"] + 1e-12) and np.all(areas["mid"] <= areas["envelope"] + 1e-12)
    true = m.volume - 0.0                                    # slabs tile [0, 0.198]; the cap above is tiny
    assert areas["envelope"].sum() * 0.009 > true * 0.98
    assert areas["core"].sum() * 0.009 < true
    assert areas["envelope"].sum() > areas["core"].sum() * 1.05


def test_tool_check_and_compensation():
    square = box(0, 0, 0.1, 0.1)
    notch = square.difference(box(0.05, 0.05, 0.1, 0.1))      # a 90 deg inside corner
    rep = check_layer(MultiPolygon([notch]), tool=0.003)
    assert rep.corners == 1 and rep.narrow_openings == 0
    assert rep.max_deviation == pytest.approx(0.0015 * (math.sqrt(2) - 1), rel=0.02)
    slot = square.difference(box(0.02, 0.02, 0.022, 0.08))    # 2 mm slot: the 3 mm cutter cannot enter
    assert check_layer(MultiPolygon([slot]), tool=0.003).narrow_openings == 1
    assert check_layer(MultiPolygon([slot]), tool=0.001).narrow_openings == 0
    comp = compensate(MultiPolygon([square]), 0.003)
    assert comp.area == pytest.approx(0.1 * 0.1 + 4 * 0.1 * 0.0015 + math.pi * 0.0015**2, rel=1e-4)
    assert len(compensate(MultiPolygon([slot]), 0.003).geoms[0].interiors) == 0   # the slot closes


@pytest.mark.slow
@pytest.mark.parametrize("argv, message", [
    (["--scale", "2:1"], "scale 1:0.5 is out of range"),
    (["--board", "0.009"], "board thickness 0.009 mm is out of range"),
    (["--glue", "9cm"], "glue thickness 90 mm is out of range"),
    (["--sheet", "300x200mm"], "does not fit on a 300 x 200 mm sheet"),
    (["--scale", "1:10", "--rod", "60mm"], "does not fit through any two neighbouring layers"),
    (["--board", "9furlongs"], "unknown length unit"),
])
def test_bad_input_is_one_line_and_writes_nothing(tmp_path, capsys, argv, message):
    out = tmp_path / "out"
    with pytest.raises(SystemExit) if "unit" in message else _no_raise():
        code = main(["slice", "--out", str(out), *argv])
        assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert message in err[-1]
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_refuses_a_foreign_folder_and_an_unwritable_one(tmp_path, capsys):
    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("keep me")
    assert main(["slice", "--out", str(foreign)]) == 2
    assert "holds files statue2model did not write (notes.txt)" in capsys.readouterr().err
    assert (foreign / "notes.txt").read_text() == "keep me"
    blocked = tmp_path / "file"
    blocked.write_text("x")
    assert main(["slice", "--out", str(blocked / "sub")]) == 2
    assert "statue2model: error:" in capsys.readouterr().err


class _no_raise:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def test_spec_ranges():
    with pytest.raises(InputError, match="tool diameter"):
        SliceSpec(tool=0.0)
    with pytest.raises(InputError, match="section policy"):
        SliceSpec(policy="top")
    assert SliceSpec(board=0.018, pass_depth=0.006).passes == 3
