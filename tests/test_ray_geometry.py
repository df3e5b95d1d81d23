"""The rocking geometry of a given direction: b_R and b_L are where the rays from the centre of mass's projection
along +x and -x leave the footprint's hull (MODEL.md section 1), not the extreme vertex's projection; the
weakest direction over all angles is unchanged (it lies on an edge's normal, where the two agree)."""
from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from statue2model.geometry.massprops import MassProperties
from statue2model.geometry.rocking_params import (
    ray_exit,
    rocking_params,
    tipping_edges,
    vulnerability_rose,
    weakest_direction,
)


def _mass(com, m=100.0):
    I = np.diag([10.0, 12.0, 8.0])
    return MassProperties(volume=m / 2650.0, mass=m, density=2650.0, com=np.asarray(com, float), inertia=I)


def _ccw(points):
    p = shapely.Polygon(points).convex_hull
    return np.asarray(shapely.geometry.polygon.orient(p, 1.0).exterior.coords)[:-1]


TRIANGLE = _ccw([(0.0, 1.0), (-math.sqrt(3) / 2, -0.5), (math.sqrt(3) / 2, -0.5)])   # circumradius 1, inradius 0.5


def test_a_triangle_tips_about_its_oblique_edge():
    """Along +x from the centroid the ray leaves through the edge whose normal points at 30 deg: t = r_in / cos 30
    = 1 / sqrt(3), not the vertex's projection sqrt(3) / 2 (1.5 x more); the same toward -x."""
    p = rocking_params(_mass([0.0, 0.0, 0.5]), TRIANGLE, 0.0)
    assert p.b_R == pytest.approx(1 / math.sqrt(3), rel=1e-12) and p.b_L == pytest.approx(1 / math.sqrt(3), rel=1e-12)
    assert p.obliquity_R == pytest.approx(30.0, abs=1e-9) and p.obliquity_L == pytest.approx(30.0, abs=1e-9)
    assert p.a_R == pytest.approx(p.g * (1 / math.sqrt(3)) / 0.5, rel=1e-12)
    edges = tipping_edges(TRIANGLE, np.zeros(2), 0.0)
    right = sorted(map(tuple, np.round(edges["R"]["edge"], 12)))
    assert right == sorted([(0.0, 1.0), (round(math.sqrt(3) / 2, 12), -0.5)])
    # along an edge's normal (-90 deg: the bottom edge) the ray meets it square: the inradius, obliquity 0
    q = rocking_params(_mass([0.0, 0.0, 0.5]), TRIANGLE, 270.0)
    assert q.b_R == pytest.approx(0.5, rel=1e-12) and q.obliquity_R == pytest.approx(0.0, abs=1e-6)
    assert q.b_L == pytest.approx(1.0, rel=1e-12)            # toward the apex: the vertex itself


def test_a_square_turned_30_degrees():
    """A 2 x 2 square turned 30 deg: along x the ray meets the edge whose normal is at 30 deg, t = 1 / cos 30 =
    1.1547; the extreme vertex would say sqrt(2) cos 15 = 1.366 (18 % more)."""
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    sq = _ccw([(c * x - s * y, s * x + c * y) for x, y in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
    p = rocking_params(_mass([0.0, 0.0, 1.0]), sq, 0.0)
    assert p.b_R == pytest.approx(1 / c, rel=1e-12) and p.b_L == pytest.approx(1 / c, rel=1e-12)
    assert p.obliquity_R == pytest.approx(30.0, abs=1e-9)
    assert p.b_R < math.sqrt(2) * math.cos(math.radians(15))
    # the weakest direction is an edge normal (30 deg), where the ray and the vertex agree: 1 m
    deg, a_min = weakest_direction(_mass([0.0, 0.0, 1.0]), sq)
    assert deg == pytest.approx(30.0, abs=1e-9) and a_min == pytest.approx(9.81 * 1.0 / 1.0, rel=1e-12)


@pytest.mark.parametrize("com", [(0.0, 0.0), (0.12, -0.05), (-0.2, 0.1)])
def test_an_irregular_polygon_against_shapely_rays(com):
    """Seven points, hull computed by shapely; every 7 degrees the package's b_R, b_L equal the distance to where
    a shapely line from G' along +-x crosses the hull's boundary."""
    pts = [(0.55, 0.05), (0.3, 0.42), (-0.1, 0.5), (-0.48, 0.2), (-0.4, -0.3), (0.05, -0.45), (0.45, -0.25)]
    hull = _ccw(pts)
    poly = shapely.Polygon(hull)
    mass = _mass([com[0], com[1], 0.6])
    for deg in np.arange(0.0, 360.0, 7.0):
        u = np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])

        def ray(sign):
            line = shapely.LineString([com, tuple(np.asarray(com) + sign * 10.0 * u)])
            hit = line.intersection(poly.exterior)
            hits = [hit] if hit.geom_type == "Point" else list(hit.geoms)
            return min(math.hypot(h.x - com[0], h.y - com[1]) for h in hits)

        p = rocking_params(mass, hull, float(deg))
        assert p.b_R == pytest.approx(ray(1.0), rel=1e-9, abs=1e-12), deg
        assert p.b_L == pytest.approx(ray(-1.0), rel=1e-9, abs=1e-12), deg
        proj = (hull - np.asarray(com)) @ u
        assert p.b_R <= proj.max() + 1e-12 and p.b_L <= -proj.min() + 1e-12      # never beyond the vertex


def test_the_weakest_direction_is_the_same_minimum():
    """Over all directions the ray's minimum is the nearest edge's distance: the rose's minimum, sampled finely,
    does not go below the exact weakest uplift, and reaches it within the sampling."""
    pts = [(0.55, 0.05), (0.3, 0.42), (-0.1, 0.5), (-0.48, 0.2), (-0.4, -0.3), (0.05, -0.45), (0.45, -0.25)]
    hull = _ccw(pts)
    mass = _mass([0.05, 0.02, 0.6])
    rose = vulnerability_rose(mass, hull, step_deg=0.25)
    assert rose.a_tip.min() >= rose.a_min * (1 - 1e-12)
    assert rose.a_tip.min() == pytest.approx(rose.a_min, rel=1e-3)
    deg, a = weakest_direction(mass, hull)
    p = rocking_params(mass, hull, deg)
    assert p.a_R == pytest.approx(a, rel=1e-12) and p.obliquity_R == pytest.approx(0.0, abs=1e-6)


def test_ray_exit_of_a_point_outside_is_refused():
    from statue2model.errors import InputError

    with pytest.raises(InputError, match="outside the base"):
        rocking_params(_mass([2.0, 0.0, 0.5]), TRIANGLE, 0.0)
    t, k, c = ray_exit(TRIANGLE, np.zeros(2), np.array([0.0, 1.0]))
    assert t == pytest.approx(1.0) and c == pytest.approx(math.cos(math.radians(60)), abs=1e-12)
