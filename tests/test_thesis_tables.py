"""Thesis Tables 1, 3, 14, 15 (nine blocks) and the geometric part of Table 24,
reproduced from their stated inputs.

The thesis prints rounded inputs (b, h to 0.1 mm, m to 1 g) and rounded outputs,
and used g = 9.807 or 9.81. A printed value is *reproduced* when it lies in the
range our formulas give over the rounding box of the inputs (and both values of
g), widened by half a unit of its last printed digit. Two exceptions are pinned
rather than hidden: Table 15's I_G differs from m (b^2 + h^2) / 3 by up to 1.8 %
beyond rounding (A2, B1, C1: its I_G was not computed from these b, h, m), and
Table 24's I_L, I_R differ from I_G + m d^2 by 1.6 % and 1.2 % (MODEL.md section 1).
"""
import itertools
import math

import pytest
import trimesh

from statue2model.geometry.body import body_from_mesh
from statue2model.geometry.rocking_params import RockingParams

BLOCKS = ["A1", "A2", "A3", "B1", "B2", "B3", "C1", "C2", "C3"]
M = [1.286, 0.435, 0.113, 0.995, 0.300, 0.084, 0.641, 0.201, 0.059]
B = [0.0384, 0.0285, 0.0184, 0.0385, 0.0282, 0.0184, 0.0389, 0.0283, 0.0184]
H = [0.2000, 0.1423, 0.0920, 0.1500, 0.1065, 0.0695, 0.0998, 0.0710, 0.0485]
# Table 1 (= Table 14 for d, delta), Table 3 (e_T), Table 15 (I_G, I_G + m d^2, x 1e-3)
TABLE = {
    "d": ([0.2037, 0.1451, 0.0938, 0.1549, 0.1102, 0.0719, 0.1070, 0.0764, 0.0519], 4),
    "delta": ([0.1897, 0.1978, 0.1974, 0.2515, 0.2586, 0.2588, 0.3714, 0.3787, 0.3623], 4),
    "mu": ([0.1920, 0.2005, 0.2000, 0.2569, 0.2645, 0.2647, 0.3895, 0.3979, 0.3790], 4),
    "p": ([6.011, 7.121, 8.856, 6.893, 8.172, 10.116, 8.290, 9.813, 11.910], 3),
    "e_T": ([0.947, 0.942, 0.942, 0.907, 0.902, 0.902, 0.802, 0.795, 0.812], 3),
    "I_G": ([17.80e-3, 3.00e-3, 0.33e-3, 7.87e-3, 1.20e-3, 0.14e-3, 2.42e-3, 0.39e-3, 0.05e-3], 5),
    "I_O": ([71.14e-3, 12.16e-3, 1.32e-3, 31.73e-3, 4.84e-3, 0.57e-3, 9.78e-3, 1.56e-3, 0.21e-3], 5),
}
# Table 15 prints m in grams for all but A1: rounding of 0.5 g; A1 is 1,286 kg -> 0.5 g too.


def block_values(m, b, h, g):
    r = RockingParams(m=m, h=h, b_L=b, b_R=b, I_G=m * (b * b + h * h) / 3, g=g)
    return {"d": r.d_R, "delta": r.delta_R, "mu": r.a_R / g, "p": r.p_R, "e_T": r.e_L, "I_G": r.I_G, "I_O": r.I_R}


def reproduces(key, i, table_value, digits, extra_rel=0.0):
    corners = [
        block_values(M[i] + sm * 5e-4, B[i] + sb * 5e-5, H[i] + sh * 5e-5, g)[key]
        for sm, sb, sh in itertools.product((-1, 1), repeat=3)
        for g in (9.807, 9.81)
    ]
    half = 0.5 * 10.0**-digits
    lo, hi = min(corners), max(corners)
    slack = half + extra_rel * abs(table_value)
    return lo - slack <= table_value <= hi + slack, (lo, hi)


@pytest.mark.parametrize("key", ["d", "delta", "mu", "p", "e_T"])
@pytest.mark.parametrize("i", range(9), ids=BLOCKS)
def test_tables_1_3_14_reproduced(key, i):
    values, digits = TABLE[key]
    ok, (lo, hi) = reproduces(key, i, values[i], digits)
    assert ok, f"{BLOCKS[i]} {key}: table {values[i]}, ours {lo:.6g}..{hi:.6g}"


@pytest.mark.parametrize("key", ["I_G", "I_O"])
@pytest.mark.parametrize("i", range(9), ids=BLOCKS)
def test_table_15_within_its_known_inconsistency(key, i):
    values, digits = TABLE[key]
    ok, (lo, hi) = reproduces(key, i, values[i], digits, extra_rel=0.02)
    assert ok, f"{BLOCKS[i]} {key}: table {values[i]}, ours {lo:.6g}..{hi:.6g}"


@pytest.mark.parametrize("i", range(9), ids=BLOCKS)
def test_block_meshes_give_the_block_formulas(i):
    """The whole pipeline on a box mesh of the block equals the closed forms to 1e-9."""
    m, b, h = M[i], B[i], H[i]
    box = trimesh.creation.box(extents=(2 * b, 3 * b, 2 * h))
    body = body_from_mesh(box.vertices, box.faces, units="m", up="z", mass=m)
    p = body.rocking(0.0)
    ref = RockingParams(m=m, h=h, b_L=b, b_R=b, I_G=m * (b * b + h * h) / 3)
    for key in ("m", "h", "b_L", "b_R", "I_G", "d_L", "delta_R", "I_R", "p_R", "a_L", "e_L", "e_R"):
        assert getattr(p, key) == pytest.approx(getattr(ref, key), rel=1e-9), key
    assert p.e_L == pytest.approx(1 - 1.5 * math.sin(p.delta_L) ** 2, rel=1e-12)  # eq. 14


def test_table_24_geometry():
    """d, delta (Table 24) and the uplift accelerations a/g (Table 22) of the statue prototype."""
    h, b_L, b_R = 0.3523, 0.1995, 0.0805
    printed = {"d_L": (0.4049, 4), "d_R": (0.3614, 4), "delta_L": (0.5152, 4), "delta_R": (0.2247, 4),
               "a_L/g": (0.566, 3), "a_R/g": (0.229, 3)}

    def value(p, key):
        return getattr(p, key[0:3]) / p.g if key.endswith("/g") else getattr(p, key)

    for key, (table, digits) in printed.items():
        corners = [
            value(RockingParams(m=12.074, h=h + a * 5e-5, b_L=b_L + c * 5e-5, b_R=b_R + e * 5e-5, I_G=0.7994), key)
            for a, c, e in itertools.product((-1, 1), repeat=3)
        ]
        half = 0.5 * 10.0**-digits
        assert min(corners) - half <= table <= max(corners) + half, key
    p = RockingParams(m=12.074, h=h, b_L=b_L, b_R=b_R, I_G=0.7994)
    # Table 24 prints I_L = 2.7344, I_R = 2.3490: 1.6 % and 1.2 % below I_G + m d^2 (MODEL.md)
    assert p.I_L == pytest.approx(0.7994 + 12.074 * p.d_L**2, rel=1e-12)
    assert 0.015 < p.I_L / 2.7344 - 1 < 0.017
    assert 0.010 < p.I_R / 2.3490 - 1 < 0.013
