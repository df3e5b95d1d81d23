"""True-shape nesting of flat parts on sheets: the layout is checked exactly with
shapely (spacing, margins, every part once), parts that cannot fit are refused
by name, and bad arguments are input errors."""
import math

import numpy as np
import pytest
import shapely
from shapely.geometry import MultiPolygon, Point, Polygon, box

from statue2model.errors import InputError
from statue2model.fabrication.nesting import Nesting, Placement, check_nesting, nest


def blob(rng, size):
    """Convex-ish blob: the hull of random points, rounded, about ``size`` across."""
    pts = rng.normal(size=(12, 2)) * [1.0, rng.uniform(0.3, 1.0)]
    hull = shapely.MultiPoint(pts).convex_hull
    p = hull.buffer(0.3 * math.sqrt(hull.area), quad_segs=6)
    x0, y0, x1, y1 = p.bounds
    p = shapely.affinity.scale(p, size / max(x1 - x0, y1 - y0), size / max(x1 - x0, y1 - y0))
    return shapely.affinity.translate(p, *rng.uniform(-0.5, 0.5, 2))   # not at the origin


def l_shape(a, b, t):
    return Polygon([(0, 0), (a, 0), (a, t), (t, t), (t, b), (0, b)])


def ring(r_out, r_in, c=(0.0, 0.0)):
    return Point(c).buffer(r_out).difference(Point(c).buffer(r_in))


def mixed_parts(n, seed, lo=0.05, hi=0.3):
    rng = np.random.default_rng(seed)
    parts = []
    for k in range(n):
        s = rng.uniform(lo, hi)
        if k % 7 == 3:
            parts.append(l_shape(s, s * rng.uniform(0.5, 1.0), 0.25 * s))
        elif k % 7 == 5:
            parts.append(ring(s / 2, s / 4, c=tuple(rng.uniform(-1, 1, 2))))
        else:
            parts.append(blob(rng, s))
    return parts


def test_random_parts_nest_exactly():
    parts = mixed_parts(40, seed=1)
    assert any(p.interiors for p in parts) and all(p.is_valid for p in parts)
    n = nest(parts, (0.9, 0.5), spacing=0.006, edge_margin=0.01, grid=0.005)
    assert isinstance(n, Nesting)
    assert check_nesting(parts, n, edge_margin=0.01) == []
    assert [p.part for p in n.placements] == list(range(len(parts)))
    assert sorted(i for s in range(n.n_sheets) for i in (p.part for p in n.parts_on(s))) == \
        list(range(len(parts)))
    assert all(n.parts_on(s) for s in range(n.n_sheets))          # no empty sheet
    lower = math.ceil(sum(p.area for p in parts) / (0.9 * 0.5))
    assert lower == 2
    assert lower <= n.n_sheets <= lower + 1
    assert n.material_use == pytest.approx(sum(p.area for p in parts) / (n.n_sheets * 0.9 * 0.5))
    assert len(n.utilisation) == n.n_sheets and all(0 < u < 1 for u in n.utilisation)
    # holes are cut with the part: the placed ring keeps its hole
    k = next(i for i, p in enumerate(parts) if p.interiors)
    placed = n.placements[k].apply(parts[k])
    assert len(placed.interiors) == 1 and placed.area == pytest.approx(parts[k].area)


def test_blobs_pack_densely():
    """First sheets of a run of blobs are well filled (bounding-box shelves reach
    about 0.5 on such parts)."""
    rng = np.random.default_rng(7)
    parts = [blob(rng, rng.uniform(0.05, 0.35)) for _ in range(60)]
    n = nest(parts, (1.25, 1.0), spacing=0.005, grid=0.005)
    assert check_nesting(parts, n) == []
    assert n.n_sheets >= 2
    assert min(n.utilisation[:-1]) > 0.65


def test_part_just_too_big_is_named():
    sheet, margin = (1.0, 0.5), 0.01
    ok = box(0, 0, 0.979, 0.1)
    n = nest([ok], sheet, spacing=0.01, edge_margin=margin)
    assert check_nesting([ok], n, edge_margin=margin) == []
    big = box(0, 0, 0.981, 0.1)
    with pytest.raises(InputError, match=r"^plank \(981 x 100 mm\) does not fit on a 1000 x 500 mm "
                                         r"sheet with 10 mm margins"):
        nest([ok, big], sheet, spacing=0.01, edge_margin=margin, names=["ok", "plank"])
    with pytest.raises(InputError, match=r"^part 1 \("):
        nest([ok, big], sheet, spacing=0.01, edge_margin=margin)


def test_part_that_fits_only_turned_is_turned():
    tall = box(0, 0, 0.2, 0.8)                          # 800 mm on a 500 mm high sheet
    n = nest([tall, Point(0, 0).buffer(0.1)], (1.0, 0.5), spacing=0.01, grid=0.01)
    assert n.placements[0].angle_deg in (90.0, 270.0)
    assert check_nesting([tall, Point(0, 0).buffer(0.1)], n) == []
    with pytest.raises(InputError, match="does not fit"):
        nest([tall], (1.0, 0.5), spacing=0.01, angles=(0, 180))


def test_first_part_sits_on_the_margin():
    part = box(0.3, 0.2, 0.5, 0.3)                      # away from its own origin
    n = nest([part], (1.0, 0.5), spacing=0.0, edge_margin=0.02, grid=0.01, angles=(0,))
    x0, y0, _, _ = n.placements[0].apply(part).bounds
    assert x0 == pytest.approx(0.02, abs=1e-8) and y0 == pytest.approx(0.02, abs=1e-8)
    assert x0 >= 0.02 and y0 >= 0.02


def test_large_spacing_is_respected():
    parts = [box(0, 0, 0.1, 0.1) for _ in range(6)] + mixed_parts(10, seed=3, hi=0.15)
    spacing = 0.05
    n = nest(parts, (1.0, 0.5), spacing=spacing, grid=0.005)
    assert check_nesting(parts, n) == []
    placed = [pl.apply(p) for p, pl in zip(parts, n.placements)]
    d = [placed[i].distance(placed[j]) for i in range(len(parts)) for j in range(i)
         if n.placements[i].sheet == n.placements[j].sheet]
    assert min(d) >= spacing
    assert min(d) < spacing + 3 * 0.005                 # and not much more: the raster is tight


def test_zero_spacing_parts_do_not_overlap():
    parts = [box(0, 0, 0.2, 0.1)] * 12
    n = nest(parts, (0.6, 0.4), spacing=0.0, grid=0.01)
    assert check_nesting(parts, n) == []
    placed = [pl.apply(p) for p, pl in zip(parts, n.placements)]
    for i in range(len(parts)):
        for j in range(i):
            if n.placements[i].sheet == n.placements[j].sheet:
                assert placed[i].intersection(placed[j]).area == 0


def test_fixed_angles_are_kept():
    parts = mixed_parts(12, seed=5)
    for angles in [(0,), (0, 180)]:
        n = nest(parts, (1.0, 0.6), spacing=0.01, angles=angles)
        assert {p.angle_deg for p in n.placements} <= {float(a) for a in angles}
        assert check_nesting(parts, n) == []


def test_check_nesting_finds_problems():
    parts = [box(0, 0, 0.2, 0.2), box(0, 0, 0.2, 0.2)]
    good = nest(parts, (1.0, 0.5), spacing=0.02, edge_margin=0.01, grid=0.01)
    assert check_nesting(parts, good, edge_margin=0.01) == []
    same = Placement(0, 0, 0.0, 0.1, 0.1), Placement(1, 0, 0.0, 0.15, 0.1)
    bad = Nesting(same, 1, (1.0, 0.5), 0.02, (0.16,))
    assert any("apart" in s for s in check_nesting(parts, bad))
    near = Placement(0, 0, 0.0, 0.005, 0.1), Placement(1, 0, 0.0, 0.5, 0.1)
    problems = check_nesting(parts, Nesting(near, 1, (1.0, 0.5), 0.02, (0.16,)), edge_margin=0.01)
    assert len(problems) == 1 and "edge" in problems[0]
    assert check_nesting(parts[:1], good) == ["2 placements for 1 parts"]


def test_transform_agrees_with_apply():
    rng = np.random.default_rng(11)
    part = mixed_parts(4, seed=2)[3]                     # the L-shape
    xy = np.asarray(part.exterior.coords)
    for angle in [0.0, 90.0, 180.0, 270.0, 33.3, -71.0]:
        pl = Placement(0, 0, angle, *rng.uniform(-2, 2, 2))
        moved = np.asarray(pl.apply(part).exterior.coords)
        np.testing.assert_allclose(pl.transform(xy), moved, atol=1e-12)
        np.testing.assert_allclose(pl.transform(xy[0]), moved[0], atol=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    ({"sheet_size": (0.0, 1.0)}, "sheet size"),
    ({"sheet_size": (1.0, -1.0)}, "sheet size"),
    ({"sheet_size": (1.0,)}, "sheet size"),
    ({"spacing": -0.01}, "spacing"),
    ({"spacing": float("nan")}, "spacing"),
    ({"edge_margin": -0.001}, "edge margin"),
    ({"grid": 0.0}, "grid"),
    ({"grid": -0.005}, "grid"),
    ({"grid": 1e-6}, "grid"),
    ({"angles": ()}, "angles"),
    ({"angles": ("up",)}, "angles"),
    ({"names": ["a"]}, "names"),
    ({"parts": []}, "no parts"),
    ({"parts": [Polygon()]}, "part 0 is empty"),
    ({"parts": [box(0, 0, 0.1, 0.1), Polygon([(0, 0), (1, 1), (1, 0), (0, 1)])]},
     "part 1 is not a valid"),
    ({"parts": [MultiPolygon([box(0, 0, 0.1, 0.1), box(0.2, 0, 0.3, 0.1)])], "names": ["layer 3"]},
     "layer 3 is a MultiPolygon"),
    ({"parts": ["square"]}, "part 0 is a str"),
])
def test_bad_arguments(kwargs, match):
    args = {"parts": [box(0, 0, 0.1, 0.1), box(0, 0, 0.2, 0.1)], "sheet_size": (1.0, 0.5),
                "spacing": 0.01}
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        nest(**args)
