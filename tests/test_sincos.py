"""rocking/sincos.py: the rocking kernel's inline sin and cos are the C library's, to the bit.

The kernel's numbers (tests/test_fragility_speed.py pins them to the bit) were made with the
library's sincos; the inline copy must give the same double for every argument: random ones over
the range of the written-out branch and beyond, small ones down to 1e-300, and those at each edge
of a branch (2**-27, 0.126, 0.85546875, the table's points i/128 and the midpoints between them,
a few ulps either side), signed zeros, nan and inf.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from statue2model.rocking.sincos import TABLE, sincos


@njit(cache=False)
def _inline(xs, s, c):
    for i in range(xs.size):
        s[i], c[i] = sincos(xs[i])


@njit(cache=False)
def _library(xs, s, c):
    for i in range(xs.size):
        s[i] = math.sin(xs[i])
        c[i] = math.cos(xs[i])


def _arguments() -> np.ndarray:
    rng = np.random.default_rng(7)
    edges = []
    for b in [2.0 ** -27, 0.126, 0.85546875] + [i / 128 for i in range(111)] + [(i + 0.5) / 128 for i in range(110)]:
        for direction in (0.0, 1.0):
            v = b
            for _ in range(6):
                edges += [v, -v]
                v = float(np.nextafter(v, direction))
    edges += [0.0, -0.0, math.nan, math.inf, -math.inf, 1.0, -2.5, 3.0, 1e-300, 5e-324, 2.0 ** -28]
    n = 1_000_000
    small = np.exp(rng.uniform(math.log(1e-12), math.log(0.9), n)) * rng.choice([-1.0, 1.0], n)
    return np.concatenate([rng.uniform(-0.9, 0.9, n), rng.uniform(-0.13, 0.13, n), small, rng.uniform(-4.0, 4.0, 1000),
                           np.array(edges)])


def _same(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return (a.view(np.int64) == b.view(np.int64)) | (np.isnan(a) & np.isnan(b))


def test_inline_sincos_equals_the_library_bit_for_bit():
    xs = _arguments()
    s1, c1, s2, c2 = (np.empty_like(xs) for _ in range(4))
    _inline(xs, s1, c1)
    _library(xs, s2, c2)
    bad_s, bad_c = ~_same(s1, s2), ~_same(c1, c2)
    assert not bad_s.any(), xs[bad_s][:5]
    assert not bad_c.any(), xs[bad_c][:5]
    # and against CPython's math (the library called from C, not through numba) on a subset
    sub = xs[::97]
    assert _same(s1[::97], np.array([math.sin(x) for x in sub])).all()
    assert _same(c1[::97], np.array([math.cos(x) for x in sub])).all()


def test_table_holds_sin_and_cos_of_the_points():
    """Each row of the table: sin(i/128) and cos(i/128), each as a double plus a remainder far below its ulp."""
    rows = TABLE.reshape(-1, 4)
    x = np.arange(rows.shape[0]) / 128.0
    assert rows.shape == (110, 4)
    assert np.all(np.abs(rows[:, 0] - np.sin(x)) <= 1e-16) and np.all(np.abs(rows[:, 2] - np.cos(x)) <= 2e-16)
    assert np.all(np.abs(rows[:, 1]) <= np.spacing(np.abs(rows[:, 0])) + 1e-300)
    assert np.all(np.abs(rows[:, 3]) <= np.spacing(rows[:, 2]))
