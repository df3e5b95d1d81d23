"""Mass properties of a closed triangle mesh: volume, centre of mass, inertia.

Exact integration of polynomials over the polyhedron by the divergence theorem
(D. Eberly, "Polygonal mass properties", 2002), vectorised over all faces. The
vertices are shifted to the middle of their bounding box first, which keeps the
result accurate to ~1e-13 relative even for scans placed far from the origin.

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.massprops import mass_properties
>>> import trimesh
>>> box = trimesh.creation.box(extents=(0.2, 0.3, 1.0))
>>> mp = mass_properties(box.vertices, box.faces, density=2650.0)
>>> round(mp.mass, 6), mp.com.round(12).tolist()
(159.0, [0.0, 0.0, 0.0])
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

MARBLE_DENSITY = 2650.0
"""Default density, kg/m^3 (Carrara marble)."""


@dataclass(frozen=True)
class MassProperties:
    """Rigid-body properties of a homogeneous solid (SI units).

    volume  : m^3
    mass    : kg
    density : kg/m^3 (mass / volume when a measured mass was given)
    com     : (3,) centre of mass, m
    inertia : (3, 3) inertia tensor about the centre of mass, kg m^2
              (I_xx = integral of rho (y^2 + z^2) dV, products with a minus sign)
    """

    volume: float
    mass: float
    density: float
    com: np.ndarray
    inertia: np.ndarray

    def inertia_about_axis(self, axis: np.ndarray) -> float:
        """Moment of inertia about the line through the centre of mass along ``axis``."""
        n = np.asarray(axis, dtype=float)
        n = n / np.linalg.norm(n)
        return float(n @ self.inertia @ n)

    def to_dict(self) -> dict:
        return {
            "volume": self.volume,
            "mass": self.mass,
            "density": self.density,
            "com": self.com.tolist(),
            "inertia": self.inertia.tolist(),
        }


def volume_integrals(vertices: np.ndarray, faces: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Volume, centre of mass and unit-density inertia tensor about the centre of mass.

    vertices : (n, 3) float, any length unit L
    faces    : (f, 3) int, outward (counter-clockwise seen from outside) winding
    returns  : volume (L^3), com (3,) (L), inertia (3, 3) per unit density (L^5)
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    ref = 0.5 * (v.min(axis=0) + v.max(axis=0))
    # Gather one coordinate column at a time: contiguous 1-D arrays are several
    # times faster than a (f, 3, 3) fancy-index gather on million-face scans.
    cols = [np.ascontiguousarray(v[:, k] - ref[k]) for k in range(3)]
    corner = [np.ascontiguousarray(f[:, j]) for j in range(3)]
    w0, w1, w2 = ([cols[k][corner[j]] for k in range(3)] for j in range(3))  # w_j[k]
    e1 = [w1[k] - w0[k] for k in range(3)]
    e2 = [w2[k] - w0[k] for k in range(3)]
    dx = e1[1] * e2[2] - e1[2] * e2[1]
    dy = e1[2] * e2[0] - e1[0] * e2[2]
    dz = e1[0] * e2[1] - e1[1] * e2[0]

    f1, f2, f3, g0, g1, g2 = [], [], [], [], [], []
    for k in range(3):
        a, b, c = w0[k], w1[k], w2[k]
        t0 = a + b
        s1 = t0 + c
        t1 = a * a
        t2 = t1 + b * t0
        s2 = t2 + c * s1
        f1.append(s1)
        f2.append(s2)
        f3.append(a * t1 + b * t2 + c * s2)
        g0.append(s2 + a * (s1 + a))
        g1.append(s2 + b * (s1 + b))
        g2.append(s2 + c * (s1 + c))

    vol = float(dx @ f1[0]) / 6.0
    first = np.array([dx @ f2[0], dy @ f2[1], dz @ f2[2]]) / 24.0
    second = np.array([dx @ f3[0], dy @ f3[1], dz @ f3[2]]) / 60.0  # x^2, y^2, z^2
    xy = (dx @ (w0[1] * g0[0] + w1[1] * g1[0] + w2[1] * g2[0])) / 120.0
    yz = (dy @ (w0[2] * g0[1] + w1[2] * g1[1] + w2[2] * g2[1])) / 120.0
    zx = (dz @ (w0[0] * g0[2] + w1[0] * g1[2] + w2[0] * g2[2])) / 120.0

    if not np.isfinite(vol) or abs(vol) == 0.0:
        return vol, np.full(3, np.nan), np.full((3, 3), np.nan)
    c = first / vol
    sxx, syy, szz = second - vol * c**2
    pxy = xy - vol * c[0] * c[1]
    pyz = yz - vol * c[1] * c[2]
    pzx = zx - vol * c[2] * c[0]
    inertia = np.array(
        [
            [syy + szz, -pxy, -pzx],
            [-pxy, sxx + szz, -pyz],
            [-pzx, -pyz, sxx + syy],
        ]
    )
    return vol, c + ref, inertia


PLAUSIBLE_DENSITY = (100.0, 25000.0)
"""Densities (kg/m^3) of solid museum objects: light wood ~400, plaster ~1000, marble 2650,
bronze 8800, gold 19300. Outside it: a warning (:func:`density_warning`)."""

POSSIBLE_DENSITY = (10.0, 30000.0)
"""Densities (kg/m^3) beyond which the number is taken to be in the wrong unit: an error."""

# other units a density is often given in: name, kg/m^3 per unit
_DENSITY_UNITS = (("g/cm^3", 1000.0), ("g/m^3 (or mg/cm^3)", 1e-3), ("lb/ft^3", 16.0185))


def _likely_unit(rho: float) -> str:
    """' was it g/cm^3 (2650 kg/m^3)?' when another unit makes ``rho`` plausible, else ''."""
    lo, hi = PLAUSIBLE_DENSITY
    fits = [f"{name} ({rho * k:.0f} kg/m^3)" for name, k in _DENSITY_UNITS if lo <= rho * k <= hi]
    return f": was it {' or '.join(fits)}?" if fits else ""


def check_density_mass(density: float | None, mass: float | None) -> None:
    """Refuse both at once, a value that is not a positive finite number, or a density
    outside :data:`POSSIBLE_DENSITY` (a number in another unit, e.g. 2.65 g/cm^3).

    >>> check_density_mass(2.65, None)
    Traceback (most recent call last):
    ...
    statue2model.errors.InputError: density 2.65 kg/m^3 is not plausible for a solid object: was it g/cm^3 (2650 kg/m^3)?
    """
    if density is not None and mass is not None:
        raise InputError("give either a density or a mass, not both")
    if density is not None and not (np.isfinite(density) and density > 0):
        raise InputError(f"density must be a positive number of kg/m^3, got {density}")
    if mass is not None and not (np.isfinite(mass) and mass > 0):
        raise InputError(f"mass must be a positive number of kg, got {mass}")
    if density is not None and not POSSIBLE_DENSITY[0] <= density <= POSSIBLE_DENSITY[1]:
        raise InputError(f"density {density:.6g} kg/m^3 is not plausible for a solid object"
                         + (_likely_unit(density) or f" (expected {PLAUSIBLE_DENSITY[0]:g} to "
                                                     f"{PLAUSIBLE_DENSITY[1]:g} kg/m^3)"))


def _mass_over_volume(mass: float, volume: float, rho: float) -> str:
    return (f"a mass of {mass:g} kg in the scan's volume of {volume:.4g} m^3 means a density of {rho:.4g} kg/m^3"
            f" (solid objects: {PLAUSIBLE_DENSITY[0]:g} to {PLAUSIBLE_DENSITY[1]:g})")


def density_warning(rho: float, mass: float | None = None, volume: float | None = None) -> str | None:
    """A warning when the density ``rho`` (kg/m^3; given, or ``mass / volume`` when a
    measured ``mass`` in kg was given for ``volume`` m^3) is outside :data:`PLAUSIBLE_DENSITY`,
    else None.

    >>> density_warning(2650.0) is None, density_warning(50.0)
    (True, 'density 50 kg/m^3 is unusual for a solid object (100 to 25000 kg/m^3): was it lb/ft^3 (801 kg/m^3)?')
    >>> density_warning(60.0, mass=3.0, volume=0.05)
    "a mass of 3 kg in the scan's volume of 0.05 m^3 means a density of 60 kg/m^3 (solid objects: 100 to 25000): check the scan's units (--units, --height) and the mass"
    """
    lo, hi = PLAUSIBLE_DENSITY
    if lo <= rho <= hi:
        return None
    if mass is not None and volume is not None:
        return _mass_over_volume(mass, volume, rho) + ": check the scan's units (--units, --height) and the mass"
    return f"density {rho:.6g} kg/m^3 is unusual for a solid object ({lo:g} to {hi:g} kg/m^3){_likely_unit(rho)}"


def resolve_density(volume: float, density: float | None = None, mass: float | None = None) -> float:
    """Density (kg/m^3) from a measured mass, a given density, or marble by default.
    A mass that puts the density outside :data:`POSSIBLE_DENSITY` is an error: the
    scan's units or the mass are wrong."""
    check_density_mass(density, mass)
    if mass is not None:
        rho = mass / volume
        if not POSSIBLE_DENSITY[0] <= rho <= POSSIBLE_DENSITY[1]:
            raise InputError(_mass_over_volume(mass, volume, rho) + ", which no solid object has: the scan's units "
                             "or the mass are wrong (check --units or --height, and --mass)")
        return rho
    return MARBLE_DENSITY if density is None else density


def mass_properties(
    vertices: np.ndarray,
    faces: np.ndarray,
    density: float | None = None,
    mass: float | None = None,
) -> MassProperties:
    """Mass properties of the closed mesh (vertices in metres).

    Give ``density`` (kg/m^3, default marble 2650) or a measured ``mass`` (kg),
    which overrides it (the density is then mass / volume).
    """
    vol, com, unit_inertia = volume_integrals(vertices, faces)
    if not np.isfinite(vol) or vol <= 0:
        raise InputError(f"the mesh encloses no volume (volume = {vol:.3g} m^3)")
    rho = resolve_density(vol, density, mass)
    return MassProperties(
        volume=vol,
        mass=rho * vol,
        density=rho,
        com=com,
        inertia=rho * unit_inertia,
    )
