"""Closed-form mass properties of prisms and pyramids: test references that share
no code with the mesh integration in statue2model.geometry.massprops.

Raw moments (density 1) are accumulated as a dict
{V, x, y, z, xx, yy, zz, xy, yz, zx} = integrals of 1, x, ..., zx over the solid,
so that disjoint parts simply add up.
"""
import numpy as np


def polygon_moments(P):
    """Area, first and second moments of a CCW polygon (k, 2) about the origin."""
    x, y = P[:, 0], P[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    c = x * yn - xn * y
    A = c.sum() / 2
    Sx = ((x + xn) * c).sum() / 6  # integral of x dA
    Sy = ((y + yn) * c).sum() / 6
    Ixx = ((x * x + x * xn + xn * xn) * c).sum() / 12  # integral of x^2 dA
    Iyy = ((y * y + y * yn + yn * yn) * c).sum() / 12
    Ixy = ((x * yn + 2 * x * y + 2 * xn * yn + xn * y) * c).sum() / 24
    return A, Sx, Sy, Ixx, Iyy, Ixy


def prism(P, z0, z1):
    """Raw moments of the vertical prism of polygon P between z0 and z1."""
    A, Sx, Sy, Ixx, Iyy, Ixy = polygon_moments(np.asarray(P, float))
    L = z1 - z0
    return dict(
        V=A * L, x=Sx * L, y=Sy * L, z=A * (z1**2 - z0**2) / 2,
        xx=Ixx * L, yy=Iyy * L, zz=A * (z1**3 - z0**3) / 3,
        xy=Ixy * L, zx=Sx * (z1**2 - z0**2) / 2, yz=Sy * (z1**2 - z0**2) / 2,
    )


def pyramid(P, H):
    """Raw moments of the pyramid with base polygon P at z = 0 and apex (0, 0, H):
    the section at height z is P scaled by s = 1 - z/H about the origin."""
    A, Sx, Sy, Ixx, Iyy, Ixy = polygon_moments(np.asarray(P, float))
    return dict(
        V=A * H / 3, x=Sx * H / 4, y=Sy * H / 4, z=A * H**2 / 12,
        xx=Ixx * H / 5, yy=Iyy * H / 5, zz=A * H**3 / 30,
        xy=Ixy * H / 5, zx=Sx * H**2 / 20, yz=Sy * H**2 / 20,
    )


def add(*parts):
    return {k: sum(p[k] for p in parts) for k in parts[0]}


def properties(raw, density=1.0):
    """(volume, com (3,), inertia about com (3, 3)) from raw moments."""
    V = raw["V"]
    c = np.array([raw["x"], raw["y"], raw["z"]]) / V
    xx = raw["xx"] - V * c[0] ** 2
    yy = raw["yy"] - V * c[1] ** 2
    zz = raw["zz"] - V * c[2] ** 2
    xy = raw["xy"] - V * c[0] * c[1]
    yz = raw["yz"] - V * c[1] * c[2]
    zx = raw["zx"] - V * c[2] * c[0]
    inertia = density * np.array([[yy + zz, -xy, -zx], [-xy, xx + zz, -yz], [-zx, -yz, xx + yy]])
    return V, c, inertia


def regular_polygon(n, r):
    t = 2 * np.pi * np.arange(n) / n
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def rect(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)
