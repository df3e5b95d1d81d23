"""Isolator plates: cap formulas, the plate solids against the exact caps (depth, opening
radius, removed volume within the derived tessellation bound), the mirrored top plate,
the fuse, rejected geometry, and the written files (DXF audit, STL watertight)."""
import math
import warnings

import numpy as np
import pytest
import trimesh

from statue2model.errors import InputError
from statue2model.fabrication.dxf import CUT_OUTSIDE, DRILL, audit
from statue2model.isolator.plates import (
    MIN_BOTTOM,
    POCKET,
    PlateGeometry,
    cap_opening_radius,
    cap_volume,
    depth_for_opening,
    plate_solid,
    to_trimesh,
    volume_deficit_bound,
)
from statue2model.isolator.plates import write_3mf, write_plates
from statue2model.report.isolator_plots import plot_plates_figures


def write_plates_with_section(g, out, segments=256, design=None):
    """The plates' files, then their figures, as the isolator stage writes them."""
    return write_plates(g, out, segments=segments) | plot_plates_figures(g, out, design=design)


REALISTIC = {"side": 0.40, "thickness": 0.03, "R": 0.30, "depth": 0.012,
             "groove_centres": ((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)), "ball_radius": 0.0183}
FUSE = {"fuse_centres": ((0.0, 0.0),), "fuse_ball_radius": 0.009, "fuse_seat_depth": 1e-4,
        "fuse_hole_diameter": 0.022, "fuse_hole_depth": 0.02, "fuse_hole_offset": 0.03}


@pytest.fixture(scope="module")
def geom():
    return PlateGeometry(**REALISTIC)


@pytest.fixture(scope="module")
def bottom(geom):
    return plate_solid(geom, "bottom", segments=256)


@pytest.fixture(scope="module")
def top(geom):
    return plate_solid(geom, "top", segments=256)


def removed(geom, solid):
    return geom.side ** 2 * geom.thickness - solid.volume()


# --------------------------------------------------------------------------- formulas

@pytest.mark.parametrize("R,d", [(0.3, 0.012), (0.3, 1e-7), (0.05, 0.05), (1.0, 0.37), (0.009, 1e-4)])
def test_opening_radius_and_depth_are_inverse(R, d):
    a = cap_opening_radius(R, d)
    assert a == pytest.approx(math.sqrt(2 * R * d - d * d), rel=1e-12)
    assert depth_for_opening(R, a) == pytest.approx(d, rel=1e-12)
    assert cap_opening_radius(R, depth_for_opening(R, 0.3 * R)) == pytest.approx(0.3 * R, rel=1e-12)


@pytest.mark.parametrize("R,d", [(0.3, 0.012), (0.05, 0.05), (0.05, 0.09), (0.009, 1e-4)])
def test_cap_volume_against_integration(R, d):
    """Discs of radius^2 = R^2 - (R - s)^2 = 2 R s - s^2 stacked from the bottom of the
    cap (s = 0) to s = d; Gauss-Legendre is exact for this quadratic integrand."""
    s, w = np.polynomial.legendre.leggauss(8)
    s = 0.5 * d * (s + 1)
    numeric = 0.5 * d * np.sum(w * math.pi * (2 * R * s - s * s))
    assert cap_volume(R, d) == pytest.approx(numeric, rel=1e-13)
    # and against a plain midpoint rule, independent of the polynomial argument
    z = (np.arange(200000) + 0.5) * d / 200000
    assert cap_volume(R, d) == pytest.approx(np.sum(math.pi * (2 * R * z - z * z)) * d / 200000, rel=1e-9)
    assert cap_volume(R, 2 * R) == pytest.approx(4 / 3 * math.pi * R ** 3)


def test_cap_formulas_reject_bad_input():
    with pytest.raises(InputError):
        cap_opening_radius(0.3, 0.7)
    with pytest.raises(InputError):
        depth_for_opening(0.3, 0.31)
    with pytest.raises(InputError):
        cap_volume(-1.0, 0.1)


# --------------------------------------------------------------------------- bottom plate

def test_bottom_plate_is_a_valid_watertight_solid(bottom):
    import manifold3d as m3d

    assert bottom.status() == m3d.Error.NoError
    assert bottom.genus() == 0
    mesh = to_trimesh(bottom)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(bottom.volume(), rel=1e-12)


def test_removed_volume_within_the_tessellation_bound(geom, bottom):
    """The cutters are inscribed (all vertices on the sphere): the removed volume is never
    more than the caps', and falls short by at most the bound of the module docstring,
    per cap  V(R, d) - V(R - delta, d - delta) with delta the largest face-to-sphere gap.
    The inscribed faces lie on average about half as deep as their worst point, so the
    deficit is close to half the bound."""
    exact = 4 * cap_volume(geom.R, geom.depth)
    assert geom.removed_volume == pytest.approx(exact, rel=1e-15)
    deficit = exact - removed(geom, bottom)
    bound = volume_deficit_bound(geom, 256)
    assert 0 < deficit <= bound
    assert deficit > 0.3 * bound                                  # the bound is not loose
    assert bound / exact < 6e-4                                   # 5.8e-4 at 256 segments


@pytest.mark.slow
def test_removed_volume_converges_to_the_cap():
    """One groove at high segment counts: the deficit falls as 1 / segments^2 (the faces'
    sagitta), is 4.7e-6 relative at 2048 segments, and the Richardson extrapolation of 1024
    and 2048 segments is the exact cap to 1e-6 (1e-6 directly needs ~4600 segments: 7e6
    triangles, ~18 s, 3 GB)."""
    g = PlateGeometry(side=0.20, thickness=0.03, R=0.30, depth=0.012, groove_centres=((0.0, 0.0),),
                      ball_radius=0.0183)
    exact = cap_volume(g.R, g.depth)
    v1 = removed(g, plate_solid(g, segments=1024))
    v2 = removed(g, plate_solid(g, segments=2048))
    assert 0 < exact - v2 <= volume_deficit_bound(g, 2048)
    assert (exact - v2) / exact < 5e-6
    assert (exact - v1) / (exact - v2) == pytest.approx(4.0, rel=0.02)
    assert abs((4 * v2 - v1) / 3 - exact) / exact < 1e-6


def test_groove_depth_and_opening_are_exact(geom, bottom):
    v = to_trimesh(bottom).vertices
    t, a = geom.thickness, geom.opening_radius
    for cx, cy in geom.groove_centres:
        rho = np.hypot(v[:, 0] - cx, v[:, 1] - cy)
        inside = rho < a + 1e-6
        assert abs(v[inside, 2].min() - (t - geom.depth)) < 1e-9
        deepest = inside & (v[:, 2] < t - geom.depth + 1e-9)
        assert deepest.sum() == 1 and rho[deepest][0] < 1e-12      # one vertex, on the axis
        rim = inside & (np.abs(v[:, 2] - t) < 1e-12)                # the top face's boundary ring
        assert rim.sum() == 256
        assert np.abs(rho[rim] - cap_opening_radius(geom.R, geom.depth)).max() < 1e-9
        # every vertex of the groove's surface lies on the sphere
        below = inside & (v[:, 2] < t - 1e-12)
        dist = np.linalg.norm(v[below] - (cx, cy, t - geom.depth + geom.R), axis=1)
        assert np.abs(dist - geom.R).max() < 1e-12


def test_top_plate_is_the_mirror(geom, bottom, top):
    import manifold3d as m3d

    assert top.status() == m3d.Error.NoError and top.genus() == 0
    assert top.volume() == pytest.approx(bottom.volume(), rel=1e-12)
    mesh = to_trimesh(top)
    assert mesh.is_watertight
    v = mesh.vertices
    assert np.allclose(mesh.bounds, [[-0.2, -0.2, 0.0], [0.2, 0.2, geom.thickness]], atol=1e-12)
    for cx, cy in geom.groove_centres:
        rho = np.hypot(v[:, 0] - cx, v[:, 1] - cy)
        inside = rho < geom.opening_radius + 1e-6
        # opens downward: the deepest point is `depth` above the lower face, the rim on z = 0
        assert abs(v[inside, 2].max() - geom.depth) < 1e-9
        rim = inside & (np.abs(v[:, 2]) < 1e-12)
        assert np.abs(rho[rim] - geom.opening_radius).max() < 1e-9
    # a ray up the axis of a groove enters the wood at z = depth, and the mirror of the bottom's
    eps = 1e-8                                                   # off the axis vertex, onto a face
    hits, _, _ = mesh.ray.intersects_location([[0.1 + eps, 0.1, -1.0]], [[0, 0, 1.0]])
    assert hits[:, 2].min() == pytest.approx(geom.depth, abs=1e-9)
    hits_b, _, _ = to_trimesh(bottom).ray.intersects_location([[0.1 + eps, 0.1, 1.0]], [[0, 0, -1.0]])
    assert hits_b[:, 2].max() == pytest.approx(geom.thickness - geom.depth, abs=1e-9)


def test_three_grooves(tmp_path):
    """n = 3 at 120 degrees: the section through groove 1 cuts the others off-centre."""
    import manifold3d as m3d

    centres = tuple((0.11 * math.cos(k * 2 * math.pi / 3), 0.11 * math.sin(k * 2 * math.pi / 3)) for k in range(3))
    g = PlateGeometry(**{**REALISTIC, "groove_centres": centres})
    solid = plate_solid(g, segments=128)
    assert solid.status() == m3d.Error.NoError and solid.genus() == 0
    assert 0 < g.removed_volume - removed(g, solid) <= volume_deficit_bound(g, 128)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                          # no lxml: no 3MF, a warning
        paths = write_plates_with_section(g, tmp_path, segments=32)
    assert paths["section_png"].stat().st_size > 0


# --------------------------------------------------------------------------- fuse

@pytest.mark.slow
def test_fuse_seats_and_holes():
    import manifold3d as m3d

    g = PlateGeometry(**REALISTIC, **FUSE)
    assert g.fuse_hole_centres == ((0.03, 0.0),)            # radially outward; +x for a seat at the centre
    seat = cap_volume(0.009, 1e-4)
    hole = math.pi * 0.011 ** 2 * 0.02
    assert g.removed_volume == pytest.approx(4 * cap_volume(0.3, 0.012) + seat + hole, rel=1e-14)
    assert g.top_removed_volume == pytest.approx(4 * cap_volume(0.3, 0.012) + seat, rel=1e-14)
    for which, exact in (("bottom", g.removed_volume), ("top", g.top_removed_volume)):
        solid = plate_solid(g, which, segments=256)
        assert solid.status() == m3d.Error.NoError and solid.genus() == 0
        assert to_trimesh(solid).is_watertight
        deficit = exact - removed(g, solid)
        assert 0 < deficit <= volume_deficit_bound(g, 256, which)
    # the hole is really there: 20 mm deep under the bottom plate's upper face, flat-bottomed
    mesh = to_trimesh(plate_solid(g, "bottom", segments=256))
    hits, _, _ = mesh.ray.intersects_location([[0.03 + 1e-3, 0.0, 1.0]], [[0, 0, -1.0]])
    assert hits[:, 2].max() == pytest.approx(0.03 - 0.02, abs=1e-12)
    hits, _, _ = mesh.ray.intersects_location([[1e-8, 0.0, 1.0]], [[0, 0, -1.0]])     # seat bottom
    assert hits[:, 2].max() == pytest.approx(0.03 - 1e-4, abs=1e-9)


# --------------------------------------------------------------------------- bad geometry

@pytest.mark.parametrize("change,match", [
    ({"depth": 0.03 - MIN_BOTTOM + 1e-4}, "leaves less than 5 mm"),
    ({"depth": 0.026, "R": 1.0, "ball_radius": 0.03}, "leaves less than 5 mm"),
    ({"depth": 0.012, "liner": 0.0131}, "groove depth 25.1 mm leaves less than 5 mm"),       # the liner's cut
    ({"liner": -0.001}, "liner"),
    ({"depth": 0.3}, "less than its radius"),
    ({"depth": 0.0125, "R": 0.012, "thickness": 0.05, "ball_radius": 0.0121, "groove_centres": ((0, 0),)},
     "less than its radius"),
    ({"groove_centres": ((-0.05, 0.0), (0.05, 0.0))}, "overlap"),
    ({"groove_centres": ((-0.1, 0.0), (0.1, 0.0), (0.08, 0.1))}, "overlap"),
    ({"groove_centres": ((0.17, 0.0),)}, "outside the plate"),
    ({"groove_centres": ((0.113, 0.0),)}, "mm from the plate's edge"),
    ({"side": -0.4}, "must be"),
    ({"ball_radius": 0.01}, "ball radius"),
    ({"groove_centres": ()}, "at least one groove"),
])
def test_bad_geometry_is_refused(change, match):
    with pytest.raises(InputError, match=match):
        PlateGeometry(**{**REALISTIC, **change})


def test_exactly_min_bottom_left_is_accepted():
    """The design's depth check passes at cut depth = thickness - MIN_BOTTOM: the plate takes it."""
    g = PlateGeometry(side=0.6, thickness=0.03, R=1.0, depth=0.03 - MIN_BOTTOM, groove_centres=((0.0, 0.0),),
                      ball_radius=0.03)
    assert g.cut_depth == pytest.approx(0.025)
    lined = PlateGeometry(side=0.6, thickness=0.03, R=1.0, depth=0.03 - MIN_BOTTOM - 0.0032, liner=0.0032,
                          groove_centres=((0.0, 0.0),), ball_radius=0.03)
    assert lined.cut_depth == pytest.approx(0.025)


@pytest.mark.parametrize("change,match", [
    ({"fuse_centres": ((0.1, 0.1),)}, "overlap"),                    # a seat in a groove
    ({"fuse_hole_offset": 0.005}, "overlap"),                        # the hole over its own seat
    ({"fuse_hole_offset": 0.19}, "outside the plate"),
    ({"fuse_hole_diameter": 0.017}, "must exceed"),
    ({"fuse_hole_depth": 0.026}, "fuse hole depth"),
    ({"fuse_seat_depth": 0.0}, "seat depth"),
])
def test_bad_fuse_is_refused(change, match):
    with pytest.raises(InputError, match=match):
        PlateGeometry(**REALISTIC, **{**FUSE, **change})


def test_bad_arguments_are_refused(geom):
    with pytest.raises(InputError, match="'bottom' or 'top'"):
        plate_solid(geom, "middle")
    with pytest.raises(InputError, match="segments"):
        plate_solid(geom, segments=4)


# --------------------------------------------------------------------------- files

@pytest.mark.slow
def test_write_plates(tmp_path):
    import ezdxf

    g = PlateGeometry(**REALISTIC, **FUSE)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        paths = write_plates_with_section(g, tmp_path / "plates", segments=128)
    names = {"bottom_stl": "bottom_plate.stl", "top_stl": "top_plate.stl", "bottom_dxf": "bottom_plate.dxf",
             "top_dxf": "top_plate.dxf", "section_png": "plates_section.png", "section_svg": "plates_section.svg",
             "bottom_3mf": "bottom_plate.3mf", "top_3mf": "top_plate.3mf"}
    assert not [w for w in caught if "3MF" in str(w.message)]     # written directly: lxml not needed
    assert {k: p.name for k, p in paths.items()} == names
    for p in paths.values():
        assert p.is_file() and p.stat().st_size > 0
    assert not list((tmp_path / "plates").glob(".*.part"))       # nothing half-written left
    assert paths["section_png"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"<svg" in paths["section_svg"].read_bytes()[:2000]

    for which in ("bottom", "top"):
        mesh = trimesh.load(paths[f"{which}_stl"])
        assert mesh.is_watertight
        assert np.allclose(mesh.bounds, [[-200, -200, 0], [200, 200, 30]], atol=1e-3)  # mm
        exact = g.removed_volume if which == "bottom" else g.top_removed_volume
        deficit = exact * 1e9 - (400 * 400 * 30 - mesh.volume)                       # mm^3
        assert -20 <= deficit <= volume_deficit_bound(g, 128, which) * 1e9 + 20     # float32 STL: ~1e-5 mm

        path = paths[f"{which}_dxf"]
        assert audit(path) == []
        doc = ezdxf.readfile(str(path))
        assert doc.header["$INSUNITS"] == 4
        msp = doc.modelspace()
        outline = [e for e in msp.query("LWPOLYLINE") if e.dxf.layer == CUT_OUTSIDE]
        assert len(outline) == 1 and outline[0].closed
        assert np.allclose(sorted(map(tuple, np.array(outline[0].get_points("xy")))),
                           [(-200, -200), (-200, 200), (200, -200), (200, 200)])
        pockets = [e for e in msp.query("CIRCLE") if e.dxf.layer == POCKET]
        radii = sorted(round(c.dxf.radius, 6) for c in pockets)
        assert radii == [round(g.fuse_seat_radius * 1e3, 6)] + [round(g.opening_radius * 1e3, 6)] * 4
        points = [e for e in msp.query("POINT") if e.dxf.layer == DRILL]
        flip = -1 if which == "top" else 1                   # the top plate seen from its carved face
        assert np.array(sorted((p.dxf.location.x, p.dxf.location.y) for p in points)) == pytest.approx(
            np.array(sorted((flip * x * 1e3, y * 1e3) for x, y in g.groove_centres)))
        holes = [e for e in msp.query("CIRCLE") if e.dxf.layer == DRILL]
        if which == "bottom":
            assert len(holes) == 1 and holes[0].dxf.radius == pytest.approx(11.0)
            assert (holes[0].dxf.center.x, holes[0].dxf.center.y) == pytest.approx((30.0, 0.0))
        else:
            assert holes == []


# --------------------------------------------------------------------------- plates of a design

DESIGN_CASES = {"ring3": 3, "ring5": 5, "grid3x4": 12}


@pytest.fixture(scope="module")
def designs():
    """Designs of the Venere restricted to one layout each (and one with the thesis' rubber liner)."""
    from statue2model.geometry.rocking_params import RockingParams
    from statue2model.hazard.code_spectra import G as G0
    from statue2model.hazard.code_spectra import ec8
    from statue2model.isolator.design import design

    venere = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.7994})
    kw = dict(spectrum=ec8(0.25 * G0, "C"), mu=0.0073, R_grid=(0.8, 1.2, 1.6), balls=(0.02, 0.025))
    out = {lay: design(venere, layouts=lay, surfaces="beech", **kw) for lay in DESIGN_CASES}
    out["beech_rubber"] = design(venere, layouts="ring4", surfaces="beech_rubber", **kw)
    for d in out.values():          # each can be made (passing or the nearest makeable one)
        assert all(c.passed for c in d.checks if c.key in ("depth", "proud", "plate_size")), d.failure
    return out


def _pockets(path, radius_mm):
    import ezdxf

    msp = ezdxf.readfile(str(path)).modelspace()
    circles = [e for e in msp.query("CIRCLE") if e.dxf.layer == POCKET]
    grooves = [e for e in circles if abs(e.dxf.radius - radius_mm) < 1e-6]
    points = [e for e in msp.query("POINT") if e.dxf.layer == DRILL]
    return circles, grooves, points


@pytest.mark.parametrize("layout", sorted(DESIGN_CASES))
def test_the_dxf_of_a_design_has_one_groove_opening_per_ball(designs, layout, tmp_path):
    from statue2model.isolator.layout import LAYOUTS
    from statue2model.isolator.plates import write_plates

    d = designs[layout]
    n = DESIGN_CASES[layout]
    assert d.n_grooves == n == len(d.groove_centres) and d.layout == layout
    g = PlateGeometry.from_design(d.to_dict())
    assert g.liner == 0.0 and g.opening_radius == pytest.approx(d.opening_radius, abs=1e-12)
    # the centres are the layout's, scaled by the design's spacing
    assert np.allclose(g.groove_centres, LAYOUTS[layout].centres(d.spacing), atol=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                          # no lxml: no 3MF, a warning
        paths = write_plates(g, tmp_path, segments=16)
    for which in ("bottom", "top"):
        assert audit(paths[f"{which}_dxf"]) == []
        circles, grooves, points = _pockets(paths[f"{which}_dxf"], g.opening_radius * 1e3)
        assert len(grooves) == n == len(circles)                  # no fuse: every pocket circle is a groove's
        assert len(points) == n
        flip = -1 if which == "top" else 1
        got = sorted((round(p.dxf.location.x, 6), round(p.dxf.location.y, 6)) for p in points)
        assert np.allclose(got, sorted((round(flip * x * 1e3, 6), round(y * 1e3, 6)) for x, y in g.groove_centres))
        centres = sorted((round(c.dxf.center.x, 6), round(c.dxf.center.y, 6)) for c in grooves)
        assert centres == got


def test_the_hand_built_layouts_match(tmp_path):
    """The same count from the layouts alone, by hand: 3, 5 and 12 grooves of a 30 mm-deep board."""
    from statue2model.isolator.layout import LAYOUTS
    from statue2model.isolator.plates import write_plates

    for key, n in DESIGN_CASES.items():
        lay = LAYOUTS[key]
        s = 0.2
        side = 2 * (lay.extent(s) + 0.08 + 0.02)
        g = PlateGeometry(side=side, thickness=0.03, R=0.30, depth=0.012, groove_centres=lay.centres(s),
                          ball_radius=0.0183)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            paths = write_plates(g, tmp_path / key, segments=8)
        _, grooves, points = _pockets(paths["bottom_dxf"], g.opening_radius * 1e3)
        assert len(grooves) == len(points) == n


def test_a_liner_is_carved_R_plus_liner_and_the_drawing_is_written(designs, tmp_path):
    """Beech with the thesis' 3.2 mm rubber layer: the rolling surface is the design's (R, depth); the plate
    is carved with a sphere of radius R + liner, liner deeper, so its opening circle is the carved one."""
    d = designs["beech_rubber"]
    dev = d.device
    assert dev.layer == 0.0032 and dev.surface == "beech_rubber"
    dd = d.to_dict()
    assert dd["liner"] == 0.0032 and dd["cut_depth"] == pytest.approx(d.depth + 0.0032)
    g = PlateGeometry.from_design(dd)
    assert g.liner == 0.0032 and g.cut_R == pytest.approx(d.R + 0.0032) and g.cut_depth == pytest.approx(dev.cut_depth)
    assert g.opening_radius == pytest.approx(cap_opening_radius(d.R + 0.0032, d.depth + 0.0032), rel=1e-12)
    assert g.opening_radius == pytest.approx(dev.carved_opening, rel=1e-12) and g.opening_radius > d.opening_radius
    assert g.removed_volume == pytest.approx(4 * cap_volume(d.R + 0.0032, d.depth + 0.0032), rel=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        paths = write_plates_with_section(g, tmp_path / "plates", segments=32, design=dd)
    circles, grooves, points = _pockets(paths["bottom_dxf"], g.opening_radius * 1e3)
    assert len(grooves) == len(points) == 4 == len(circles)
    # the carved groove's deepest point: cut_depth below the face, on the axis
    v = to_trimesh(plate_solid(g, "bottom", segments=32)).vertices
    x0, y0 = g.groove_centres[0]
    near = np.hypot(v[:, 0] - x0, v[:, 1] - y0) < 1e-9
    assert v[near, 2].min() == pytest.approx(g.thickness - g.cut_depth, abs=1e-9)
    # the carpenter's drawing, with a design
    assert paths["drawing_png"].name == "drawing.png" and paths["drawing_svg"].name == "drawing.svg"
    assert paths["drawing_png"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    svg = paths["drawing_svg"].read_text()
    assert "<svg" in svg[:2000]
    assert not list((tmp_path / "plates").glob(".*.part"))


def test_write_3mf_is_trimesh_3mf_export(tmp_path):
    """write_3mf writes the package trimesh's 3MF export writes (member for member, character for
    character once the fresh UUIDs are masked), and trimesh reads the same vertices and faces back."""
    import re
    import zipfile

    pytest.importorskip("lxml")                  # trimesh's 3MF export needs it
    g = PlateGeometry(**REALISTIC, **FUSE)
    mesh = to_trimesh(plate_solid(g, "top", 32))
    mesh.apply_scale(1000.0)
    ours, theirs = tmp_path / "ours.3mf", tmp_path / "theirs.3mf"
    write_3mf(mesh.vertices, mesh.faces, ours)
    mesh.export(theirs, file_type="3mf")
    uuid_re = re.compile(rb"[0-9a-f]{8}(-[0-9a-f]{4}){3}-[0-9a-f]{12}")
    a, b = zipfile.ZipFile(ours), zipfile.ZipFile(theirs)
    assert a.namelist() == b.namelist() == ["3D/3dmodel.model", "_rels/.rels", "[Content_Types].xml"]
    for name in a.namelist():
        assert uuid_re.sub(b"~", a.read(name)) == uuid_re.sub(b"~", b.read(name)), name
    back = trimesh.load(ours, force="mesh", process=False)
    assert np.array_equal(back.vertices, mesh.vertices) and np.array_equal(back.faces, mesh.faces)
