"""Geometry-library (GEOS) failures in the fabrication code are recovered, or named.

Fixtures:
* real layers of the bundled scans (tests/fabrication_geos_fixtures.py, exact WKB) on which
  the tool check failed with "TopologyException: found non-noded intersection", the
  error of the Lucy scan at 1:2: GEOS's closing of the layer crosses itself;
* polygons GEOS itself cannot overlay: a ring that crosses itself (a bowtie: GEOS
  raises "TopologyException: found non-noded intersection" in the tool check,
  "side location conflict" in a difference) and a layer whose two parts overlap;
* a polygon whose make_valid is a collection holding a MultiPolygon next to a
  collapsed spike (the old layer code kept none of its area);
* the retry path and the unrecoverable path, by making one GEOS operation raise
  GEOSException once, or always, on one layer of a stepped body of revolution
  (a 0.3 m wide drum under a 0.1 m wide one: the layer where the step is, and its
  height, are known in closed form).
"""
import math

import numpy as np
import pytest
import shapely
import trimesh
from shapely.errors import GEOSException
from shapely.geometry import LineString, MultiPolygon, Point, Polygon, box

from statue2model.cli import main
from statue2model.errors import InputError
from statue2model.fabrication import layers, robust
from statue2model.fabrication.labels import place_label
from statue2model.fabrication.nesting import check_nesting, nest
from statue2model.fabrication.rods import check_holes, place_rods
from statue2model.fabrication.toolcheck import as_cut, check_layer, compensate, trim_layer

from fabrication_geos_fixtures import GEOS_FAILING_LAYERS

TOOL = 0.003
BOWTIE = Polygon([(0, 0), (0.1, 0.1), (0.1, 0), (0, 0.1)])          # two triangles of 0.0025 m^2
OVERLAP = MultiPolygon([box(0, 0, 0.1, 0.1), box(0.05, 0, 0.15, 0.1)])  # union 0.015 m^2


def _raise_on(monkeypatch, name, when, times=None):
    """Make shapely.<name> raise GEOSException when ``when(*args)`` holds, ``times``
    times (None: always); returns the list of calls that raised."""
    real = getattr(shapely, name)
    raised = []

    def fake(*args, **kwargs):
        if (times is None or len(raised) < times) and when(*args):
            raised.append(args)
            raise GEOSException("TopologyException: found non-noded intersection between LINESTRING (0 0, 1 1) "
                                "and LINESTRING (0 1, 1 0) [ (0.5, 0.5) ]")
        return real(*args, **kwargs)

    monkeypatch.setattr(shapely, name, fake)
    return raised


# --- the fixtures really break GEOS, and the wrapper recovers them --------------------------------

def test_fixtures_make_geos_raise():
    with pytest.raises(GEOSException, match="TopologyException"):
        shapely.difference(BOWTIE, box(0, 0, 0.04, 0.04))
    with pytest.raises(GEOSException, match="non-noded intersection"):
        MultiPolygon([BOWTIE]).difference(MultiPolygon([BOWTIE]).buffer(-0.0015).buffer(0.0015))
    with pytest.raises(GEOSException, match="TopologyException"):
        OVERLAP.union(box(0.01, 0.01, 0.02, 0.02))


@pytest.mark.parametrize("name", sorted(GEOS_FAILING_LAYERS))
def test_real_scan_layers_on_which_geos_failed(name):
    layer = shapely.from_wkb("".join(GEOS_FAILING_LAYERS[name]))
    assert layer.is_valid
    kept, rep, removed = trim_layer(layer, TOOL)
    # plain GEOS: the closing of what is kept crosses itself, and the difference fails
    r = TOOL / 2
    closed = kept.buffer(r, quad_segs=16).buffer(-r, quad_segs=16)
    assert not closed.is_valid
    with pytest.raises(GEOSException, match="non-noded intersection"):
        closed.difference(kept)
    # recovered: nothing lost, and the uncut wood obeys |C - K| = |C| - |K| + |K - C|
    assert kept.is_valid and removed.is_valid
    assert kept.area + removed.area == pytest.approx(layer.area, rel=1e-12)
    c = robust.as_multipolygon(closed)
    assert rep.uncut_area == pytest.approx(c.area - kept.area + kept.difference(c).area, rel=1e-9, abs=1e-15)
    assert 0 < rep.uncut_area < 1e-3 * layer.area
    assert as_cut(layer, TOOL).is_valid and compensate(layer, TOOL).area > layer.area
    assert check_layer(layer, TOOL).uncut_area > 0


def test_safe_op_recovers_a_self_crossing_ring():
    # bowtie = left triangle (0,0)-(0.05,0.05)-(0,0.1) and right one; the box cuts 0.0002 m^2
    # out of the left one (the part of [0, 0.02]^2 above y = x, and below y = 0.1 - x)
    got = robust.difference(BOWTIE, box(0, 0, 0.02, 0.02), what="a test")
    assert got.is_valid
    assert got.area == pytest.approx(0.005 - 0.5 * 0.02 ** 2, abs=1e-15)


def test_as_multipolygon_keeps_a_multipolygon_nested_in_a_collection():
    spiky = Polygon([(0, 0), (1, 1), (1, 0), (0, 1), (0, 0.5), (-0.5, 0.5), (0, 0.5)])   # bowtie + spike
    fixed = shapely.make_valid(spiky)
    assert fixed.geom_type == "GeometryCollection"
    assert [g.geom_type for g in shapely.get_parts(fixed)] == ["MultiPolygon", "LineString"]
    mp = robust.as_multipolygon(spiky)
    assert mp.is_valid and len(mp.geoms) == 2 and mp.area == pytest.approx(0.5, abs=1e-15)
    assert layers._as_multipolygon(spiky).area == pytest.approx(0.5, abs=1e-15)    # was 0: all lost
    assert robust.as_multipolygon(OVERLAP).area == pytest.approx(0.015, abs=1e-15)  # overlap counted once


@pytest.mark.parametrize("layer, area", [(MultiPolygon([BOWTIE]), 0.005), (OVERLAP, 0.015)])
def test_tool_checks_on_layers_geos_cannot_overlay(layer, area):
    kept, rep, removed = trim_layer(layer, TOOL)
    assert kept.is_valid and removed.is_valid
    # what is kept and what is taken out make the (valid) layer again
    assert kept.area + removed.area == pytest.approx(area, rel=1e-9)
    assert kept.intersection(removed).area < 1e-12
    # the bowtie's tips are sharp corners, not slivers; nothing is narrower than the cutter
    assert rep.dropped_parts == 0
    check = check_layer(layer, TOOL)
    assert check.uncut_area >= 0 and math.isfinite(check.max_deviation)
    built = as_cut(layer, TOOL)
    assert built.is_valid and built.area >= area - 1e-12                   # the closing only adds wood
    path = compensate(layer, TOOL)
    # an outward offset by r of convex pieces: area + perimeter r + pi r^2 (polygonal arcs: a little less)
    valid = robust.as_multipolygon(layer)
    r = TOOL / 2
    bound = sum(p.area + p.length * r + math.pi * r * r for p in valid.geoms)
    assert area + sum(p.length for p in valid.geoms) * r * 0.99 < path.area <= bound


def test_rods_and_labels_on_layers_geos_cannot_overlay():
    stack = [OVERLAP] * 4
    plan = place_rods(stack, pitch=0.0095, board=0.009, hole=0.0082, wall=0.005)
    valid = [robust.as_multipolygon(s) for s in stack]
    assert all(len(h) >= 2 for h in plan.holes)
    assert check_holes(valid, plan, wall=0.005) == []
    hole = Point(0.015, 0.05).buffer(0.006)
    lab = place_label(BOWTIE, "7", 90.0, keep_out=hole, margin=0.002)
    assert lab is not None and lab.height >= 0.003
    room = robust.as_multipolygon(BOWTIE).difference(hole)
    assert room.contains(lab.bounds_polygon(0.002))


# --- the retry path: GEOS raises once ---------------------------------------------------------------

def test_retry_once_in_each_module(monkeypatch):
    layer = MultiPolygon([box(0, 0, 0.2, 0.1).difference(box(0.09, 0.02, 0.092, 0.08))])   # a 2 mm slot
    want = trim_layer(layer, TOOL)
    raised = _raise_on(monkeypatch, "buffer", lambda g, d, *a: d < 0, times=1)
    got = trim_layer(layer, TOOL)
    assert len(raised) == 1
    # retried on coordinates snapped to 1e-9 m: the same answer within a nanometre
    assert got[0].symmetric_difference(want[0]).area < 1e-9 * want[0].length
    assert got[1].narrow_openings == want[1].narrow_openings == 1

    monkeypatch.undo()
    parts = [box(0, 0, 0.2, 0.1), Point(0, 0).buffer(0.05)]
    raised = _raise_on(monkeypatch, "buffer", lambda *a: True, times=1)
    res = nest(parts, (0.5, 0.3), 0.005, edge_margin=0.01)
    assert len(raised) == 1
    assert check_nesting(parts, res, edge_margin=0.01) == []

    monkeypatch.undo()
    stack = [MultiPolygon([Point(0, 0).buffer(0.10 - 0.002 * k)]) for k in range(6)]
    want = place_rods(stack, pitch=0.0095, board=0.009, hole=0.0082, wall=0.005)
    raised = _raise_on(monkeypatch, "intersection", lambda *a: True, times=1)
    got = place_rods(stack, pitch=0.0095, board=0.009, hole=0.0082, wall=0.005)
    assert len(raised) == 1
    assert [len(h) for h in got.holes] == [len(h) for h in want.holes]
    assert np.allclose(np.vstack(got.holes), np.vstack(want.holes), atol=1e-8)

    monkeypatch.undo()
    a, b = trimesh.creation.box((0.2, 0.1, 0.2)), trimesh.creation.box((0.1, 0.2, 0.2))
    v, f = np.vstack([a.vertices, b.vertices]), np.vstack([a.faces, b.faces + len(a.vertices)])
    raised = _raise_on(monkeypatch, "node", lambda *a: True, times=1)
    (sec,), (chk,) = layers.plane_sections(v, f, [0.05])        # crossing shells: the arrangement runs
    assert len(raised) == 1
    assert sec.area == pytest.approx(0.03, rel=1e-9) and chk.overlap == pytest.approx(0.01, rel=1e-6)


def test_cleaning_steps_in_order():
    """As is; make_valid (skipped: a valid polygon is unchanged); snapped to 1e-9 m; to 1e-6 m."""
    seen = []

    def picky(g):                  # "fails" until every coordinate is on the 1e-6 m grid
        xy = shapely.get_coordinates(g)
        seen.append(xy)
        if not np.allclose(xy * 1e6, np.round(xy * 1e6), rtol=0, atol=1e-6):
            raise GEOSException("TopologyException: found non-noded intersection")
        return g.area

    poly = Polygon([(0, 0), (0.1 + 1.3e-10, 0), (0.1, 0.05 + 7e-8), (0, 0.05)])
    area = robust.safe_op(picky, poly, what="a test")
    assert len(seen) == 3
    assert np.allclose(seen[1][:, 0].max(), 0.1, rtol=0, atol=1e-15)          # 1.3e-10 snapped away
    assert seen[1][:, 1].max() == pytest.approx(0.05 + 7e-8, abs=1e-15)         # on the 1e-9 grid still
    assert area == pytest.approx(0.1 * 0.05, abs=1e-15)


def test_unrecoverable_operation_is_one_named_line():
    def always(*_):
        raise GEOSException("TopologyException: side location conflict at 0.5 0.5. This can occur if ...")

    with pytest.raises(robust.GeometryError) as info:
        robust.safe_op(always, BOWTIE, what="the cutter check (closing)")
    msg = str(info.value)
    assert isinstance(info.value, InputError) and "\n" not in msg
    assert msg.startswith("the cutter check (closing): the geometry library (GEOS) failed "
                          "(TopologyException: side location conflict) even after")


# --- a whole slice: one layer's GEOS operation fails once, or always --------------------------------

STEP_Z, LAM, BOARD, GLUE = 0.2, 2.0, 0.009, 0.0005       # m: the drums meet at 0.2 m on the statue


@pytest.fixture(scope="module")
def stepped(tmp_path_factory):
    """A drum of radius 0.15 m up to 0.2 m under one of radius 0.05 m up to 0.4 m."""
    prof = np.column_stack([[0, 0.15, 0.15, 0.05, 0.05, 0], [0, 0, STEP_Z, STEP_Z, 0.4, 0.4]])
    mesh = trimesh.creation.revolve(prof, sections=32)
    path = tmp_path_factory.mktemp("stepped") / "stepped.stl"
    mesh.export(path)
    return mesh, path


def _narrow_inward_offset(g, d, *_):
    """An inward offset of a polygonal layer of the narrow drum (0.05 m wide at 1:2)."""
    if not (np.ndim(d) == 0 and d < 0 and shapely.get_dimensions(g) == 2):
        return False
    x0, _, x1, _ = g.bounds
    return 0.03 < x1 - x0 < 0.07


def _first_narrow_layer():
    """(1-based number, mid-board height in m on the prototype) of the first layer of the narrow drum."""
    pitch = BOARD + GLUE
    k = math.floor((STEP_Z / LAM - 0.5 * BOARD) / pitch) + 1
    return k + 1, k * pitch + 0.5 * BOARD


def test_first_narrow_layer_in_closed_form():
    n, z = _first_narrow_layer()
    assert (n, round(z * 1000, 1)) == (12, 109.0)


def test_slice_retries_a_layer_and_keeps_its_answer(stepped, monkeypatch):
    from statue2model.fabrication.slicing import slice_body
    from statue2model.fabrication.spec import SliceSpec
    from statue2model.geometry.body import body_from_mesh

    mesh, _ = stepped
    body = body_from_mesh(mesh.vertices, mesh.faces, units="m", up="z", density=2650)
    spec = SliceSpec(scale=LAM, board=BOARD, glue=GLUE)
    want = slice_body(body, spec)
    raised = _raise_on(monkeypatch, "buffer", _narrow_inward_offset, times=1)
    got = slice_body(body, spec)
    assert len(raised) == 1
    assert [len(s.geoms) for s in got.sections] == [len(s.geoms) for s in want.sections]
    for a, b in zip(got.sections, want.sections):
        assert a.symmetric_difference(b).area < 1e-9 * max(b.length, 1e-3)
    assert got.proto_mass.mass == pytest.approx(want.proto_mass.mass, rel=1e-7)
    assert got.warnings == want.warnings


def test_slice_names_the_layer_geos_cannot_do(stepped, monkeypatch, tmp_path, capsys):
    _, path = stepped
    raised = _raise_on(monkeypatch, "buffer", _narrow_inward_offset)
    out = tmp_path / "out"
    code = main(["slice", str(path), "--units", "m", "--up", "z", "--scale", "1:2", "--board", "9mm",
                 "--glue", "0.5mm", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and raised
    assert err.count("\n") == 1 and "Traceback" not in err and "internal error" not in err
    n, z = _first_narrow_layer()
    assert err.startswith(f"statue2model: error: layer {n} (z = {z * 1000:.1f} mm on the prototype, "
                          f"{z * LAM * 1000:.0f} mm on the statue): the cutter check (inward offset): "
                          "the geometry library (GEOS) failed (TopologyException: found non-noded intersection)")
    assert "repair it near that height" in err
    assert not out.exists()


def test_label_failure_is_a_warning_not_an_error(stepped, monkeypatch):
    from statue2model.fabrication.slicing import slice_body
    from statue2model.fabrication.spec import SliceSpec
    from statue2model.geometry.body import body_from_mesh

    mesh, _ = stepped
    body = body_from_mesh(mesh.vertices, mesh.faces, units="m", up="z", density=2650)
    real = shapely.maximum_inscribed_circle

    def fake(p, *a, **k):
        if p.bounds[2] - p.bounds[0] < 0.07:      # the narrow drum's parts
            raise GEOSException("TopologyException: found non-noded intersection")
        return real(p, *a, **k)

    monkeypatch.setattr(shapely, "maximum_inscribed_circle", fake)
    res = slice_body(body, SliceSpec(scale=LAM, board=BOARD, glue=GLUE))
    n, _ = _first_narrow_layer()
    unlabelled = [p.name for p in res.parts if p.label is None]
    assert unlabelled == [str(k) for k in range(n, res.n_layers + 1)]
    line = next(w for w in res.warnings if w.startswith("no room for an engraved label"))
    assert "the geometry library failed" in line and line.endswith("mark them by hand")


def test_dxf_contours_that_touch_read_back(tmp_path):
    from statue2model.fabrication.dxf import Drawing, read_section_dxf, write_dxf

    # a hole that touches its outline at one point is a valid polygon; the DXF gives two
    # contours that read back as outline minus hole
    part = Polygon(box(0, 0, 0.1, 0.1).exterior.coords, [[(0, 0.05), (0.05, 0.02), (0.05, 0.08)]])
    assert part.is_valid
    write_dxf(tmp_path / "p.dxf", [Drawing(outline=MultiPolygon([part]))])
    back = read_section_dxf(tmp_path / "p.dxf")
    assert back.area == pytest.approx(part.area, rel=1e-6)
    assert LineString([(0.001, 0.05), (0.04, 0.05)]).intersection(back).length == pytest.approx(0.0, abs=1e-9)


@pytest.mark.slow
def test_bundled_scan_that_ended_in_an_internal_error(tmp_path, capsys):
    """meshes/nefertiti_bust.obj at 1:1 in 1.5 mm boards with 0.5 mm glue ended (before
    robust.py) with 'internal error: GEOSException: TopologyException: found non-noded
    intersection' in the tool check of layer 118: the whole slice now completes."""
    import json
    from pathlib import Path

    mesh = Path(__file__).resolve().parents[1] / "meshes" / "nefertiti_bust.obj"
    out = tmp_path / "slice"
    code = main(["slice", str(mesh), "--scale", "1:1", "--board", "1.5mm", "--glue", "0.5mm", "--no-previews",
                 "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 0, err
    s = json.loads((out / "slice.json").read_text())
    assert s["n_layers"] == 247
