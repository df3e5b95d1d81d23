"""Closed primitives with known answers: volume, centre of mass, inertia and every
rocking parameter within 1e-9 relative (issue [1])."""
import math

import manifold3d
import numpy as np
import pytest
import shapely
import trimesh

from analytic import add, properties, prism, pyramid, rect, regular_polygon
from statue2model.geometry.body import body_from_mesh

RTOL = 1e-9
RHO = 2650.0


def _manifold(m):
    mesh = m.to_mesh64()
    return np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts)


def box():
    m = trimesh.creation.box(extents=(0.3, 0.2, 1.2))
    return m.vertices, m.faces, prism(rect(-0.15, -0.1, 0.15, 0.1), -0.6, 0.6), rect(-0.15, -0.1, 0.15, 0.1)


def cylinder():
    m = trimesh.creation.cylinder(radius=0.25, height=1.0, sections=64)
    P = regular_polygon(64, 0.25)
    return m.vertices, m.faces, prism(P, -0.5, 0.5), P


def cone():
    m = trimesh.creation.cone(radius=0.3, height=0.9, sections=64)
    P = regular_polygon(64, 0.3)
    return m.vertices, m.faces, pyramid(P, 0.9), P


def l_union():
    a = manifold3d.Manifold.cube((0.6, 0.2, 0.8))
    b = manifold3d.Manifold.cube((0.2, 0.4, 0.8)).translate((0.0, 0.2, 0.0))
    v, f = _manifold(a + b)
    L = np.array([[0, 0], [0.6, 0], [0.6, 0.2], [0.2, 0.2], [0.2, 0.6], [0, 0.6]])
    return v, f, add(prism(rect(0, 0, 0.6, 0.2), 0, 0.8), prism(rect(0, 0.2, 0.2, 0.6), 0, 0.8)), L


def asymmetric_prism():
    P = np.array([[0.0, 0.0], [0.5, 0.0], [0.625, 0.25], [0.25, 0.5], [-0.125, 0.25]])
    n = len(P)
    # side quads + fan caps around the (interior) first vertex: a closed, outward mesh
    v = np.vstack([np.column_stack([P, np.zeros(n)]), np.column_stack([P, np.full(n, 0.875)])])
    faces = []
    for i in range(n):
        j = (i + 1) % n
        faces += [[i, j, n + j], [i, n + j, n + i]]
    for i in range(1, n - 1):
        faces += [[0, i + 1, i], [n, n + i, n + i + 1]]
    return v, np.array(faces), prism(P, 0, 0.875), P


def block_on_plinth():
    plinth = manifold3d.Manifold.cube((0.3, 0.3, 0.1), center=True).translate((0.0, 0.0, 0.05))
    block = manifold3d.Manifold.cube((0.5, 0.4, 1.0), center=True).translate((0.05, 0.0, 0.6))
    v, f = _manifold(plinth + block)
    ref = add(prism(rect(-0.15, -0.15, 0.15, 0.15), 0, 0.1), prism(rect(-0.2, -0.2, 0.3, 0.2), 0.1, 1.1))
    return v, f, ref, rect(-0.15, -0.15, 0.15, 0.15)


CASES = {f.__name__: f for f in (box, cylinder, cone, l_union, asymmetric_prism, block_on_plinth)}


def reference(raw, footprint_polygon, direction_deg):
    """Every rocking parameter from the closed forms (independent of the package)."""
    V, c, I = properties(raw, RHO)
    hull = shapely.Polygon(footprint_polygon).convex_hull
    hx, hy = hull.centroid.x, hull.centroid.y
    com = np.array([c[0] - hx, c[1] - hy, c[2]])
    psi = math.radians(direction_deg)
    u = np.array([math.cos(psi), math.sin(psi)])
    # b_R, b_L: where the rays from G's projection along +u and -u leave the footprint's hull (MODEL.md 1)
    def ray(sign):
        line = shapely.LineString([tuple(c[:2]), tuple(c[:2] + sign * 100.0 * u)])
        hit = line.intersection(hull.exterior)
        pts = [hit] if hit.geom_type == "Point" else list(hit.geoms)
        return min(math.hypot(pt.x - c[0], pt.y - c[1]) for pt in pts)

    b_R, b_L = ray(1.0), ray(-1.0)
    n = np.array([-math.sin(psi), math.cos(psi), 0.0])
    m, h, g = RHO * V, com[2], 9.81
    I_G = n @ I @ n
    d_L, d_R = math.sqrt(b_L**2 + h**2), math.sqrt(b_R**2 + h**2)
    I_L, I_R = I_G + m * d_L**2, I_G + m * d_R**2
    return dict(
        volume=V, mass=m, com=com, inertia=I, h=h, b_L=b_L, b_R=b_R, I_G=I_G, d_L=d_L, d_R=d_R,
        delta_L=math.atan(b_L / h), delta_R=math.atan(b_R / h), I_L=I_L, I_R=I_R,
        p_L=math.sqrt(m * g * d_L / I_L), p_R=math.sqrt(m * g * d_R / I_R),
        a_L=g * b_L / h, a_R=g * b_R / h,
        e_L=(I_G + m * (h**2 - b_L * b_R)) / I_L, e_R=(I_G + m * (h**2 - b_L * b_R)) / I_R,
    )


def _shift_to_base(v):
    """The reference solids are given with their base at z = z_min; put it on z = 0."""
    return v - np.array([0.0, 0.0, v[:, 2].min()])


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("direction", [0.0, 30.0, 90.0, 137.0, 251.5])
def test_primitive_matches_closed_form(name, direction):
    v, f, raw, P = CASES[name]()
    zmin = v[:, 2].min()
    raw = add(raw)  # copy
    # move the closed form with the mesh: the pipeline puts the base on z = 0
    V = raw["V"]
    raw["zz"] += -2 * zmin * raw["z"] + V * zmin**2
    raw["yz"] += -zmin * raw["y"]
    raw["zx"] += -zmin * raw["x"]
    raw["z"] += -zmin * V
    body = body_from_mesh(_shift_to_base(v), f, units="m", up="z")
    ref = reference(raw, P, direction)
    assert body.mass.volume == pytest.approx(ref["volume"], rel=RTOL)
    assert body.mass.mass == pytest.approx(ref["mass"], rel=RTOL)
    scale = np.abs(ref["com"]).max()
    np.testing.assert_allclose(body.mass.com, ref["com"], rtol=0, atol=RTOL * scale)
    np.testing.assert_allclose(body.mass.inertia, ref["inertia"], rtol=0, atol=RTOL * np.abs(ref["inertia"]).max())
    params = body.rocking(direction)
    for key in ("h", "b_L", "b_R", "I_G", "d_L", "d_R", "delta_L", "delta_R", "I_L", "I_R",
                "p_L", "p_R", "a_L", "a_R", "e_L", "e_R"):
        assert getattr(params, key) == pytest.approx(ref[key], rel=RTOL), key


def test_weakest_direction_of_a_box_is_its_short_side():
    m = trimesh.creation.box(extents=(0.4, 0.2, 1.0))
    body = body_from_mesh(m.vertices, m.faces, units="m", up="z")
    rose = body.rose()
    assert rose.weakest_deg == pytest.approx(90.0, abs=1e-9)
    assert rose.a_min == pytest.approx(9.81 * 0.1 / 0.5, rel=1e-12)
    p = body.rocking()
    assert p.b_R == pytest.approx(0.1, rel=1e-12) and p.b_L == pytest.approx(0.1, rel=1e-12)
    # the rose's sampled minimum never undercuts the exact one
    assert rose.a_tip.min() >= rose.a_min * (1 - 1e-12)


def test_weakest_direction_of_an_eccentric_body_points_to_its_near_edge():
    v, f, _, _ = block_on_plinth()  # block overhangs toward +x: G is 0.047 m right of the plinth centre
    body = body_from_mesh(v, f, units="m", up="z")
    p = body.rocking()
    assert body.rose().weakest_deg == pytest.approx(0.0, abs=1e-9)
    assert p.b_R < p.b_L and p.a_R < p.a_L


def test_footprint_of_a_tube_has_a_hole():
    """A hollow column stands on a ring: contact area excludes the hole, the hull does not."""
    n, R, r = 48, 0.3, 0.2
    outer = manifold3d.Manifold.cylinder(1.0, R, R, n)
    inner = manifold3d.Manifold.cylinder(1.2, r, r, n).translate((0.0, 0.0, -0.1))
    v, f = _manifold(outer - inner)
    body = body_from_mesh(v, f, units="m", up="z")
    ngon = 0.5 * n * math.sin(2 * math.pi / n)
    assert body.footprint.area == pytest.approx(ngon * (R * R - r * r), rel=1e-9)
    assert body.footprint.hull_area == pytest.approx(ngon * R * R, rel=1e-9)
    (exterior, holes), = body.footprint.polygons
    assert len(holes) == 1 and len(exterior) == n and len(holes[0]) == n
