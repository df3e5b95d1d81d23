"""Engraved part labels: the stroke table, text and arrow geometry, and labels
placed inside parts (exactly, around keep-out holes, toward the front, chiral)."""
import math
import time

import numpy as np
import pytest
from shapely.affinity import scale
from shapely.geometry import MultiLineString, Point, Polygon, box

from statue2model.errors import InputError
from statue2model.fabrication.labels import GLYPHS, Label, arrow_strokes, place_label, text_strokes


def width(strokes):
    pts = np.vstack(strokes)
    return pts[:, 0].max() - pts[:, 0].min()


def blob(rng, n=300, r0=0.1, centre=(0.0, 0.0)):
    """A star-shaped part with a few random harmonics, n vertices."""
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = np.ones(n)
    for k in range(2, 7):
        r += rng.uniform(0, 0.25 / k * 2) * np.cos(k * phi + rng.uniform(0, 2 * np.pi))
    r = r0 * np.maximum(r, 0.2)
    return Polygon(np.c_[centre[0] + r * np.cos(phi), centre[1] + r * np.sin(phi)])


def arrow_direction(label: Label):
    shaft = label.strokes[-2]                 # text strokes, then shaft (tail -> tip), then head
    v = shaft[-1] - shaft[0]
    return math.degrees(math.atan2(v[1], v[0]))


def inside(part, keep_out, label, pad):
    allowed = part if keep_out is None else part.difference(keep_out)
    return allowed.contains(label.bounds_polygon(pad))


# -- stroke table and text --------------------------------------------------

def test_glyph_table_covers_digits_letters_dash_and_stays_in_cell():
    assert set(GLYPHS) == set("0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ-")
    for c, strokes in GLYPHS.items():
        assert strokes, c
        for s in strokes:
            p = np.asarray(s)
            assert p.ndim == 2 and p.shape[1] == 2 and len(p) >= 2, c
            assert p[:, 0].min() >= 0 and p[:, 0].max() <= 0.6, c
            assert p[:, 1].min() >= 0 and p[:, 1].max() <= 1, c


def test_text_width_grows_with_length_and_scales_with_height():
    h = 0.01
    w1, w2, w3 = (width(text_strokes(t, h)) for t in ("1", "12", "123"))
    assert w1 < w2 < w3
    assert w3 - w2 == pytest.approx(0.8 * h, abs=0.25 * h)     # ~ one advance per character
    a, b = text_strokes("37B", 0.004), text_strokes("37B", 0.012)
    assert len(a) == len(b)
    for sa, sb in zip(a, b):
        np.testing.assert_allclose(sb, 3 * sa, atol=1e-15)
    pts = np.vstack(b)
    assert pts[:, 1].min() >= 0 and pts[:, 1].max() <= 0.012 + 1e-15   # baseline at 0, height h
    assert pts[:, 0].min() >= 0


@pytest.mark.parametrize("text", ["3a", "37?", "Ä1", "1.5"])
def test_unsupported_character_is_an_input_error(text):
    with pytest.raises(InputError):
        text_strokes(text, 0.01)
    with pytest.raises(InputError):
        place_label(box(0, 0, 1, 1), text, 0.0)


def test_arrow_runs_from_origin_to_length_with_a_head():
    s = arrow_strokes(0.02)
    pts = np.vstack(s)
    np.testing.assert_allclose(s[0], [[0, 0], [0.02, 0]])
    assert pts[:, 0].min() == 0 and pts[:, 0].max() == pytest.approx(0.02)
    assert pts[:, 1].max() > 0 > pts[:, 1].min()               # barbs on both sides
    assert all(np.allclose(si[np.argmax(si[:, 0])], [0.02, 0]) for si in s)   # all meet at the tip


# -- placement --------------------------------------------------------------

def test_big_square_gets_max_height_and_lies_inside():
    part = box(0, 0, 0.3, 0.3)
    lab = place_label(part, "37B", 0.0, max_height=0.012, tool_diameter=0.002)
    assert lab is not None and lab.height == pytest.approx(0.012)
    assert inside(part, None, lab, 0.002 + 0.001)
    assert lab.anchor == pytest.approx((0.15, 0.15), abs=1e-3)   # at the pole
    assert lab.length() > 0


def test_narrow_part_gets_a_smaller_height_or_none():
    strip = box(0, 0, 0.3, 0.012)                      # 12 mm wide, 300 mm long, along x
    along = place_label(strip, "37B", 0.0)             # text along the strip
    assert along is not None and 0.003 <= along.height < 0.012
    assert along.height == pytest.approx(0.012 - 2 * 0.002, rel=1e-3)   # fills the width exactly
    assert inside(strip, None, along, 0.002)
    across = place_label(strip, "37B", 90.0)           # text across: 4.2 h + 4 mm > 12 mm
    assert across is None
    sliver = box(0, 0, 0.3, 0.006)
    assert place_label(sliver, "37B", 0.0) is None     # 6 mm - 2 x 2 mm < 3 mm


def test_keep_out_disk_at_the_pole_is_avoided():
    part = box(0, 0, 0.1, 0.1)
    hole = Point(0.05, 0.05).buffer(0.01)
    lab = place_label(part, "12", 45.0, keep_out=hole)
    assert lab is not None and lab.height == pytest.approx(0.012)
    assert inside(part, hole, lab, 0.002)
    assert lab.bounds_polygon(0.002).distance(hole) > 0
    # a ring: the label must sit in the band between the outline and the hole
    ring_part, ring_hole = Point(0, 0).buffer(0.045, 64), Point(0, 0).buffer(0.03, 64)   # 15 mm band
    lab = place_label(ring_part, "7", 0.0, keep_out=ring_hole)
    assert lab is not None and lab.height < 0.012
    assert inside(ring_part, ring_hole, lab, 0.002)


@pytest.mark.parametrize("front", [0.0, 90.0, 210.0, -30.0])
def test_arrow_points_to_the_front(front):
    part = box(-0.2, -0.2, 0.2, 0.2)
    lab = place_label(part, "37", front)
    d = (arrow_direction(lab) - front + 180) % 360 - 180
    assert abs(d) < 1e-9
    # the text reads along the arrow: the first glyph is behind the arrow's tail
    u = np.array([math.cos(math.radians(front)), math.sin(math.radians(front))])
    text_pts = np.vstack(lab.strokes[:-2]) @ u
    assert text_pts.max() < lab.strokes[-2][0] @ u


def test_label_is_chiral():
    h = 0.01
    s = text_strokes("37", h)
    orig = MultiLineString(s)
    w = width(s)
    for mirror in (lambda p: np.c_[w - p[:, 0], p[:, 1]], lambda p: np.c_[p[:, 0], h - p[:, 1]]):
        assert orig.hausdorff_distance(MultiLineString([mirror(p) for p in s])) > 0.1 * h
    # the one reflection that keeps the arrow is across its axis (the text's mid-line):
    # every digit must change under it, so every layer number reveals a flipped board
    for c in "0123456789":
        g = MultiLineString([np.asarray(p) for p in GLYPHS[c]])
        m = MultiLineString([np.c_[np.asarray(p)[:, 0], 1 - np.asarray(p)[:, 1]] for p in GLYPHS[c]])
        assert g.hausdorff_distance(m) > 0.02, c
    # and so does a placed label, seen in the part's coordinates
    lab = place_label(box(0, 0, 0.2, 0.2), "88", 30.0)
    a, (ax, ay) = math.radians(30.0), lab.anchor
    _u, v = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
    flip = [p - 2 * np.outer((p - (ax, ay)) @ v, v) for p in lab.strokes]
    assert MultiLineString(list(lab.strokes)).hausdorff_distance(MultiLineString(flip)) > 0.05 * lab.height


def test_scaled_part_and_tool_clearance():
    rng = np.random.default_rng(3)
    part = blob(rng, r0=0.03)
    for tool in (0.0, 0.003):
        lab = place_label(part, "105C", 120.0, tool_diameter=tool, max_height=0.05)
        assert lab is not None
        assert inside(part, None, lab, 0.002 + tool / 2)
    big = place_label(scale(part, 2, 2), "105C", 120.0, max_height=0.05)
    assert big.height == pytest.approx(2 * place_label(part, "105C", 120.0, max_height=0.05, margin=0.001).height,
                                       rel=0.05)


def test_bad_parameters_are_input_errors():
    sq = box(0, 0, 1, 1)
    with pytest.raises(InputError):
        place_label(sq, "1", 0.0, min_height=0.02, max_height=0.01)
    with pytest.raises(InputError):
        place_label(sq, "1", 0.0, margin=-1e-3)
    with pytest.raises(InputError):
        place_label(sq, "1", float("nan"))
    with pytest.raises(InputError):
        text_strokes("1", 0.0)
    assert place_label(Polygon(), "1", 0.0) is None
    assert place_label(sq, "1", 0.0, keep_out=sq.buffer(0.1)) is None


def test_label_is_immutable():
    lab = place_label(box(0, 0, 0.1, 0.1), "1", 0.0)
    with pytest.raises(Exception):
        lab.height = 1.0
    with pytest.raises(ValueError):
        lab.strokes[0][0, 0] = 1.0


@pytest.mark.slow
def test_300_random_parts_are_fast_and_every_label_is_inside():
    rng = np.random.default_rng(7)
    parts, holes = [], []
    for i in range(300):
        r0 = rng.uniform(0.01, 0.25)
        p = blob(rng, n=int(rng.integers(150, 400)), r0=r0)
        parts.append(p)
        k = [Point(rng.uniform(-0.3, 0.3) * r0, rng.uniform(-0.3, 0.3) * r0).buffer(0.004) for _ in range(2)]
        holes.append(k[0].union(k[1]))
    fronts = rng.uniform(0, 360, 300)
    t0 = time.perf_counter()
    labels = [place_label(p, f"{i}{'AB'[i % 2]}", f, keep_out=k, tool_diameter=0.002)
              for i, (p, k, f) in enumerate(zip(parts, holes, fronts))]
    dt = time.perf_counter() - t0
    placed = [lab for lab in labels if lab is not None]
    print(f"\n300 parts: {dt:.3f} s ({dt / 300 * 1e3:.2f} ms/part), {len(placed)} labelled, "
          f"{sum(lab.height == pytest.approx(0.012) for lab in placed)} at max height")
    assert len(placed) > 200
    for p, k, lab in zip(parts, holes, labels):
        if lab is not None:
            assert 0.003 <= lab.height <= 0.012
            assert inside(p, k, lab, 0.002)
