"""Sections that never lose area silently, parts the cutter cannot make, and the
prototype's errors with their likely causes.

Fixtures (built here, known answers):
* two closed boxes that overlap, concatenated without a union (overlapping shells):
  the section is their union (even-odd filling cuts a hole; polygonising the
  crossing segments without noding them returns nothing);
* a box whose left wall is pushed, over a band of heights, through the right wall
  by 0.5 mm (a fold: faces cross): the section there is the box minus the slot
  plus the 0.5 mm tip beyond the right wall (w = -1, non-zero);
* a triangle soup of a box with every vertex jittered by up to 0.1 um (segments
  with tiny gaps and near-duplicate points);
* two boxes stacked with a gap (a genuine gap, named with its heights);
* a box with 1 mm fins hanging from a top plate (parts narrower than the cutter)
  and a frustum standing on its narrow end (a first board wider than the base).
"""
import math

import numpy as np
import pytest
import trimesh
from shapely.geometry import MultiPolygon, Polygon, box

from statue2model.errors import InputError
from statue2model.fabrication import layers
from statue2model.fabrication.layers import (
    layer_bottoms,
    layer_sections_checked,
    plane_sections,
    section_at,
    sections,
)
from statue2model.fabrication.output import comparison_rows, slice_dict
from statue2model.fabrication.slicing import empty_layer_warnings, slice_body
from statue2model.fabrication.spec import SliceSpec
from statue2model.fabrication.toolcheck import summarise, trim_layer
from statue2model.geometry.body import body_from_mesh


def prism(rings, zs):
    """Closed, outward-wound mesh of rings ((n, 2) each, counter-clockwise, same n)
    at heights zs, capped by fans from the centres of the first and last rings."""
    rings = [np.asarray(r, float) for r in rings]
    n = len(rings[0])
    v = [np.column_stack([r, np.full(n, z)]) for r, z in zip(rings, zs)]
    v += [[[*rings[0].mean(axis=0), zs[0]]], [[*rings[-1].mean(axis=0), zs[-1]]]]
    v = np.vstack(v)
    j = np.arange(n)
    j1 = (j + 1) % n
    f = []
    for i in range(len(rings) - 1):
        a, b = i * n, (i + 1) * n
        f += [np.column_stack([a + j, a + j1, b + j1]), np.column_stack([a + j, b + j1, b + j])]
    cb, ct, top = len(v) - 2, len(v) - 1, (len(rings) - 1) * n
    f += [np.column_stack([np.full(n, cb), j1, j]), np.column_stack([np.full(n, ct), top + j, top + j1])]
    return v, np.vstack(f)


def square_ring(W, D, per_side=12):
    t = np.linspace(0, 1, per_side, endpoint=False)
    return np.vstack([np.column_stack([W * t, 0 * t]), np.column_stack([W + 0 * t, D * t]),
                      np.column_stack([W * (1 - t), D + 0 * t]), np.column_stack([0 * t, D * (1 - t)])])


W, D, H = 0.20, 0.12, 0.2845                  # 30 layers of 9.5 mm pitch, the top one flush
ZF, HALF, DZ = 0.147, 0.003, 0.0002            # fold band: ZF +- HALF, reached over DZ
SLOT = (0.0804, 0.0802, 0.0798, 0.0796)         # y of the slot's corners: at the left wall, then at the tip
E = 0.0005                                      # the tip pokes 0.5 mm through the right wall


def folded_box():
    """The box W x D x H whose left wall, over ZF +- HALF, is pushed through the right
    wall by E along a slot 0.8 mm (left) to 0.4 mm (tip) wide; returns the mesh and
    the exact section in the band (non-zero winding: box minus slot plus the tip)."""
    ring = square_ring(W, D)
    left = np.flatnonzero(ring[:, 0] == 0)[1:]          # (0, D) down to (0, D/12); (0, 0) is vertex 0
    pick = left[3:7]                                    # y 0.09 ... 0.06 -> the slot's four corners
    ring[pick] = np.column_stack([np.zeros(4), SLOT])
    dent = ring.copy()
    dent[pick[1:3], 0] = W + E
    v, f = prism([ring, ring, dent, dent, ring, ring], [0.0, ZF - HALF, ZF - HALF + DZ, ZF + HALF - DZ, ZF + HALF, H])
    notch = Polygon([(0, SLOT[0]), (W + E, SLOT[1]), (W + E, SLOT[2]), (0, SLOT[3])])
    return v, f, box(0, 0, W, D).symmetric_difference(notch)


def overlapping_boxes():
    a = trimesh.creation.box((0.20, 0.10, 0.30))
    a.apply_translation([0, 0, 0.15])
    b = trimesh.creation.box((0.10, 0.20, 0.20))
    b.apply_translation([0.05, 0, 0.10])
    v = np.vstack([a.vertices, b.vertices])
    f = np.vstack([a.faces, b.faces + len(a.vertices)])
    return v, f


# --- A. sections ---------------------------------------------------------------------------------
def test_overlapping_shells_give_their_union():
    v, f = overlapping_boxes()
    z = [0.02, 0.10, 0.19, 0.21, 0.29]
    secs, checks = plane_sections(v, f, z)
    union = 0.20 * 0.10 + 0.10 * 0.20 - 0.10 * 0.10
    want = [union, union, union, 0.02, 0.02]
    assert [s.area for s in secs] == pytest.approx(want, rel=1e-9)
    for s, c, zz in zip(secs, checks, z):
        assert s.is_valid and len(s.geoms) == 1
        if zz < 0.2:                                   # both shells: w = 2 where they overlap
            assert c.winding_area == pytest.approx(union + 0.01, rel=1e-9)
            assert c.overlap == pytest.approx(0.01, rel=1e-6) and c.method == "loops"
        else:
            assert c.overlap == 0 and c.note == ""


def test_a_fold_through_the_opposite_wall_keeps_the_layer():
    v, f, exact = folded_box()
    assert trimesh.Trimesh(v, f, process=False).is_watertight
    z = [0.05, ZF - HALF + 2 * DZ, ZF, ZF + HALF - 2 * DZ, 0.25]
    secs, checks = plane_sections(v, f, z)
    assert [s.area for s in secs] == pytest.approx([W * D, exact.area, exact.area, exact.area, W * D], rel=1e-9)
    for s, c in zip(secs[1:4], checks[1:4]):
        assert s.symmetric_difference(exact).area < 1e-10            # 1e-4 mm^2
        tip = exact.intersection(box(W, 0, W + E, D)).area   # beyond the right wall: w = -1
        assert c.inverted == pytest.approx(tip, rel=1e-6)
        assert c.winding_area == pytest.approx(exact.area - 2 * tip, rel=1e-9)


def test_segments_with_tiny_gaps_and_near_duplicate_points():
    m = trimesh.creation.box((0.3, 0.2, 0.4)).subdivide().subdivide()
    m.apply_translation([0, 0, 0.2])
    rng = np.random.default_rng(7)
    soup = m.vertices[m.faces].reshape(-1, 3) + rng.uniform(-1e-7, 1e-7, (3 * len(m.faces), 3))
    faces = np.arange(len(soup)).reshape(-1, 3)
    secs, checks = plane_sections(soup, faces, np.linspace(0.01, 0.39, 9) + 0.003)   # not through vertices
    assert [s.area for s in secs] == pytest.approx([0.06] * 9, rel=1e-5)
    assert all(c.merged > 0 and c.method == "loops" and len(s.geoms) == 1 for s, c in zip(secs, checks))


def test_a_wrong_fill_is_repaired_from_the_noded_segments(monkeypatch):
    """If the loops lost a part, the winding-integral check catches it and the
    arrangement rebuilds the section."""
    v, f = overlapping_boxes()
    monkeypatch.setattr(layers, "_fill_loops", lambda segs, nxt: MultiPolygon())
    geom, check = section_at(v, f, 0.10)
    assert check.method == "arrangement" and check.repaired and "filled loops 0.00 mm^2" in check.note
    assert geom.area == pytest.approx(0.03, rel=1e-9)


def test_an_open_surface_is_refused():
    m = trimesh.creation.box((0.3, 0.2, 0.4))
    m.apply_translation([0, 0, 0.2])
    side = np.flatnonzero(np.isclose(m.face_normals[:, 0], 1.0))
    faces = np.delete(m.faces, side, axis=0)
    with pytest.raises(InputError, match="the surface is open at z = 200.00 mm"):
        sections(m.vertices, faces, [0.2])


def test_slice_of_the_folded_box_has_every_layer():
    """Through slice_body: the layer at the fold (mid-plane 147 mm) keeps its area;
    no layer is empty or reported as a gap; the volume matches the scan's."""
    v, f, exact = folded_box()
    body = body_from_mesh(v, f, units="m", up="z", density=620.0)
    res = slice_body(body, SliceSpec(scale=1.0))
    x0, y0 = body.vertices[:, :2].min(axis=0)            # the body frame is centred on the hull
    mids = res.bottoms + 0.0045
    at_fold = np.flatnonzero(np.abs(mids - ZF) < HALF - DZ)
    assert len(at_fold) == 1
    for k, s in enumerate(res.sections):
        assert not s.is_empty
        want = exact.area if k in at_fold else W * D
        # the 0.5 mm tip is narrower than the cutter: it is dropped
        tip = exact.intersection(box(W, 0, W + E, D)).area if k in at_fold else 0.0
        assert s.area == pytest.approx(want - tip, rel=1e-6), k
    assert not any("no section" in w or "cut nothing" in w or "empty" in w for w in res.warnings)
    assert abs(res.comparison.volume) < 0.01
    info = slice_dict(res)
    assert info["layers"][at_fold[0]]["section"]["inverted"] > 0


def test_a_genuine_gap_is_named_with_its_heights():
    """Two boxes 30 mm apart (a Body refuses separate pieces; the sections and the
    warnings do not depend on it)."""
    lower = trimesh.creation.box((0.2, 0.2, 0.1))
    lower.apply_translation([0, 0, 0.05])
    upper = trimesh.creation.box((0.2, 0.2, 0.1))
    upper.apply_translation([0, 0, 0.15 + 0.03])
    v = np.vstack([lower.vertices, upper.vertices])
    f = np.vstack([lower.faces, upper.faces + len(lower.vertices)])
    spec = SliceSpec(scale=1.0)
    bottoms = layer_bottoms(0.23, spec.board, spec.glue)
    raw, checks = layer_sections_checked(v, f, bottoms, spec.board)
    mids = bottoms + 0.0045
    empty = [k + 1 for k, s in enumerate(raw) if s.is_empty]
    assert empty == [k + 1 for k, z in enumerate(mids) if 0.1 < z < 0.13] == [12, 13, 14]
    assert all(checks[k - 1][0].segments == 0 for k in empty)
    full = [s.area for k, s in enumerate(raw) if k + 1 not in empty]
    assert full == pytest.approx([0.04] * len(full), rel=1e-9)
    # layer 2 holds only a 1 mm wide part: the cutter cannot make it
    secs = list(raw)
    secs[1] = MultiPolygon()
    raw[1] = MultiPolygon([box(0, 0, 0.001, 0.05)])
    (gap, narrow) = empty_layer_warnings(raw, secs, checks, bottoms, spec, 2.0)
    assert gap.startswith("layers 12-14 (z = 109.0-128.0 mm on the prototype, 218-256 mm on the statue) cut "
                          "nothing: the scan has a gap there")
    assert narrow == "layer 2 holds only parts narrower than the 3 mm cutter: left empty"


# --- C. parts narrower than the cutter -----------------------------------------------------------
def test_narrow_parts_are_dropped_and_slivers_opened_with_one_summary():
    tool = 0.003
    square = box(0, 0, 0.1, 0.1)
    fin = box(0.1, 0.04, 0.13, 0.041)                         # 1 mm x 30 mm fin on the square
    chips = [box(0.2 + 0.01 * i, 0, 0.201 + 0.01 * i, 0.02) for i in range(8)]   # 1 x 20 mm, detached
    layer_list = [MultiPolygon([square.union(fin)] + chips)] * 3 + [MultiPolygon([square])]
    out = [trim_layer(layer, tool) for layer in layer_list]
    for kept, rep, removed in out[:3]:
        assert len(kept.geoms) == 1 and kept.area == pytest.approx(0.01, abs=1e-7)   # sharp corners kept
        assert rep.dropped_parts == 8 and rep.dropped_area == pytest.approx(8 * 0.02e-3, rel=1e-9)
        assert rep.thin_features == 1 and rep.thin_area == pytest.approx(0.03e-3, rel=0.05)
        assert removed.area == pytest.approx(8 * 0.02e-3 + rep.thin_area, rel=1e-9)
        assert rep.to_dict()["dropped_parts"] == 8
    assert out[3][1].clean and out[3][0].equals(layer_list[3])
    lines = summarise([r for _, r, _ in out], tool, sum(x.area for x in layer_list))
    assert len(lines) == 2
    assert lines[0].startswith("dropped 24 parts narrower than the 3 mm cutter (total area 480 mm^2, ")
    assert lines[0].endswith("on layers 1-3")
    assert lines[1].startswith("opened away 3 slivers thinner than the 3 mm cutter") and "layers 1-3" in lines[1]


def finned_box(n_fins=40):
    """A 100 x 100 x 190 mm box under a 130 x 130 x 9 mm plate, with n fins 2.5 x 7 mm
    hanging from the plate 2 mm off the box: one solid (manifold3d union)."""
    import manifold3d as m3d

    def cube(ext, centre):
        return m3d.Manifold.cube(ext, center=True).translate(centre)

    solids = [cube((0.1, 0.1, 0.19), (0, 0, 0.095)), cube((0.13, 0.13, 0.009), (0, 0, 0.1945))]
    per = n_fins // 4
    for i in range(n_fins):
        side, j = divmod(i, per)
        t = -0.045 + 0.09 * j / (per - 1)
        ext = (0.0025, 0.007, 0.195) if side < 2 else (0.007, 0.0025, 0.195)
        c = [(0.05325, t), (-0.05325, t), (t, 0.05325), (t, -0.05325)][side]
        solids.append(cube(ext, (c[0], c[1], 0.0975)))
    mesh = m3d.Manifold.batch_boolean(solids, m3d.OpType.Add).to_mesh()
    return np.asarray(mesh.vert_properties)[:, :3].astype(float), np.asarray(mesh.tri_verts).astype(np.int64)


# --- B. the prototype against the scan -----------------------------------------------------------
def test_dropped_parts_fail_the_volume_with_their_cause():
    v, f = finned_box()
    body = body_from_mesh(v, f, units="m", up="z", density=620.0)
    res = slice_body(body, SliceSpec(scale=1.0, glue_density=620.0))
    fins = 40 * 0.0025 * 0.007 * 0.19
    assert res.n_layers == 21
    assert res.comparison.volume == pytest.approx(-fins / body.mass.volume, abs=0.005)
    assert "volume" in res.comparison.failing()
    (drop,) = [w for w in res.warnings if w.startswith("dropped")]
    assert drop.startswith(f"dropped {40 * 20} parts narrower than the 3 mm cutter") and drop.endswith("on layers 1-20")
    cause = res.causes["volume"]
    assert cause.startswith(f"mostly {40 * 20} part(s) narrower than the cutter dropped (-")
    explained = float(cause.split("dropped (")[1].split(" %")[0]) / 100
    assert explained == pytest.approx(-fins / body.mass.volume, rel=0.05)
    assert res.warnings[0].startswith("the prototype's volume is -") and "likely cause: mostly" in res.warnings[0]
    row = {r["quantity"]: r for r in comparison_rows(res)}["volume, dm^3"]
    assert row["status"] == "fail" and row["cause"] == cause
    assert len(res.warnings) < 10                            # summarised, not one line per part
    info = slice_dict(res)
    assert [x["tool"]["dropped_parts"] for x in info["layers"]] == [40] * 20 + [0]
    assert info["prototype"]["failing"][0] == "volume"


def test_a_first_board_wider_than_the_base_fails_b_with_its_cause():
    """A frustum on its narrow end (60 mm at the base, widening 1 mm per mm of
    height): the first board, at 4.5 mm, is 9 mm wider than the contact footprint."""
    ring0 = square_ring(0.06, 0.06, 4) - 0.03
    ring1 = ring0 * (0.06 + 2 * 0.104) / 0.06
    v, f = prism([ring0, ring1], [0.0, 0.104])               # 11 layers: the top board ends at 104 mm
    res = slice_body(body_from_mesh(v, f, units="m", up="z", density=620.0),
                     SliceSpec(scale=1.0, rod_density=0.0, glue_density=620.0), direction_deg=0.0)
    c = res.comparison
    assert c.b_R == pytest.approx(0.0045 / 0.03, rel=0.05) and c.b_L == pytest.approx(0.0045 / 0.03, rel=0.05)
    assert {"b_L", "b_R", "a_min"} <= set(c.failing()) and abs(c.volume) < 0.01
    assert res.causes["b_R"].startswith("the first board's outline (its section 4.5 mm up) reaches 4.5 mm further "
                                        "toward the right pivot than the scan's base footprint; it is 15.0 % wider")
    rows = {r["quantity"]: r for r in comparison_rows(res)}
    assert rows["b_R, m"]["status"] == "fail" and rows["volume, dm^3"]["status"] == "pass"
    assert rows["b_R, m"]["cause"] == res.causes["b_R"] and rows["volume, dm^3"]["cause"] == ""
    assert sum(w.startswith("the prototype's") for w in res.warnings) == len(c.failing())
    from pathlib import Path

    from statue2model.cli.fabrication import summary

    text = summary(res, Path("out"))
    assert "FAIL" in next(line for line in text.splitlines() if line.startswith("b_R, m"))
    assert next(line for line in text.splitlines() if line.startswith("volume, dm^3")).endswith("ok")
    assert math.isclose(res.a_min[1], 9.81 * 0.03 / body_from_mesh(v, f, units="m", up="z").mass.com[2], rel_tol=1e-6)
