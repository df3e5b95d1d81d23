"""From a scan file to a Body: a closed solid in metres, standing on z = 0.

The pipeline (each step's record ends up in ``Body.log``):

    read (scan.py) -> repair (repair.py) -> units (units.py) -> up axis
    (orient.py) -> rest on the hull facet under G (base.py) -> optional rescale
    to a known height -> base on z = 0 -> contact tolerance from the base's
    resolution and roughness (base.py) -> footprint (footprint.py), hull centred
    on the z axis -> mass properties (massprops.py) -> stability check ->
    contact at half and double the tolerance (base.py)

Mass properties are integrated once, in file units, and carried through the
similarity transform exactly (volume x s^3, inertia x s^5, rotations R I R^T).

Example
-------
>>> from statue2model.geometry.body import load_body
>>> from statue2model.io.paths import default_scan
>>> body = load_body(default_scan())
>>> body.up, body.units, round(body.height, 3)
('+y', 'm', 1.8)
>>> p = body.rocking()              # weakest direction by default
>>> p.a_R <= p.a_L
True
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import InputError
from .footprint import Footprint, footprint
from .massprops import MassProperties, check_density_mass, density_warning, resolve_density, volume_integrals
from .base import BASE_TOL, BaseContact, base_contact, base_surface, contact_tolerance
from .orient import UP_ROTATIONS, choose_up, face_area_vectors, rest_plane
from .repair import repair_mesh
from .rocking_params import G, RockingParams, Rose, rocking_params, vulnerability_rose, weakest_direction
from .scan import read_scan
from .units import check_plausible, resolve_units

__all__ = ["BASE_TOL", "Body", "body_from_mesh", "load_body"]


@dataclass(frozen=True)
class Body:
    """A scanned object ready for analysis (SI units, base on z = 0, +z up).

    vertices, faces : the closed, outward-wound mesh, (n, 3) m and (f, 3)
    mass            : mass properties in this frame
    footprint       : contact region and its convex hull
    base            : contact tolerance, base surface and the contact at half and
                      double the tolerance (:class:`~statue2model.geometry.base.BaseContact`)
    units, up       : what the file was taken to be in ('m', '+y', ...)
    scale           : metres per file unit actually applied
    rotation        : (3, 3) and translation (3,): x_body = rotation @ (scale * x_file) + translation
    log, warnings   : what was done, and what the user should check
    """

    source: str
    kind: str
    vertices: np.ndarray
    faces: np.ndarray
    mass: MassProperties
    footprint: Footprint
    units: str
    up: str
    scale: float
    rotation: np.ndarray
    translation: np.ndarray
    log: tuple[str, ...]
    warnings: tuple[str, ...]
    base: BaseContact | None = None
    units_sure: bool = True

    @property
    def height(self) -> float:
        return float(self.vertices[:, 2].max())

    def rose(self, step_deg: float = 1.0, g: float = G) -> Rose:
        return vulnerability_rose(self.mass, self.footprint.hull, step_deg, g)

    def rocking(self, direction_deg: float | None = None, g: float = G) -> RockingParams:
        """Rocking parameters along ``direction_deg`` (default: the weakest direction)."""
        if direction_deg is None:
            direction_deg, _ = weakest_direction(self.mass, self.footprint.hull, g)
        if not np.isfinite(direction_deg):
            raise InputError(f"direction must be a finite angle in degrees, got {direction_deg}")
        return rocking_params(self.mass, self.footprint.hull, direction_deg, g)


def body_from_mesh(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    units: str = "auto",
    up: str = "auto",
    height: float | None = None,
    density: float | None = None,
    mass: float | None = None,
    base_tol: float | None = None,
    source: str = "<mesh>",
    kind: str = "mesh",
    log: tuple[str, ...] = (),
) -> Body:
    """Run the pipeline of the module docstring on raw arrays (file units and axes)."""
    if height is not None and not (np.isfinite(height) and height > 0):
        raise InputError(f"height must be a positive number of metres, got {height}")
    height_note = None if height is None else check_plausible("height", height)   # refuses a 1.8 km statue
    if base_tol is not None and not (np.isfinite(base_tol) and base_tol >= 0):
        raise InputError(f"base tolerance must be a non-negative number of metres, got {base_tol}")
    check_density_mass(density, mass)  # before the expensive steps
    steps = list(log)
    warnings: list[str] = [height_note] if height_note else []

    rep = repair_mesh(vertices, faces)
    steps.extend(rep.log)
    warnings.extend(rep.warnings)
    v, f = rep.vertices, rep.faces
    vol0, com0, inertia0 = volume_integrals(v, f)

    extent = float(np.ptp(v, axis=0).max())
    if height is not None:
        s = resolve_units("auto", extent, strict=False).scale   # provisional: --height sets the scale
        if units != "auto":
            steps.append(f"--units {units} not used: --height sets the scale")
    else:
        choice = resolve_units(units, extent)
        s = choice.scale
        (steps if choice.sure else warnings).append(choice.note)

    v1 = v * s
    com1 = com0 * s
    av = face_area_vectors(v1, f)
    cand, up_note = choose_up(v1, f, av, com1, up)
    steps.append(up_note)
    R = UP_ROTATIONS[cand.up]
    v2 = v1 @ R.T
    R_level, tilt = rest_plane(v2, f, R @ com1)
    if tilt > 0:
        v2 = v2 @ R_level.T
        R = R_level @ R
        steps.append(f"levelled onto the hull facet it rests on (tilt {np.degrees(tilt):.3f} deg)")
    if height is not None:
        k = height / float(np.ptp(v2[:, 2]))
        s *= k
        v2 = v2 * k
        steps.append(f"rescaled to a height of {height:g} m (x {s:.6g} m per file unit)")

    shift = np.array([0.0, 0.0, -v2[:, 2].min()])
    v2 = v2 + shift
    H = float(v2[:, 2].max())
    surface = base_surface(v2, f)
    if base_tol is None:
        tol, why = contact_tolerance(surface, H)
    else:
        tol, why = base_tol, "given (--base-tol)"
    steps.append(f"contact tolerance {tol * 1000:.3g} mm ({why}); base edge length {surface.edge * 1000:.3g} mm, "
                 f"roughness {surface.roughness * 1000:.3g} mm rms, warp {surface.warp * 1000:.3g} mm")
    fp = footprint(v2, f, tol)
    hull_centre = _polygon_centroid(fp.hull)
    v2[:, :2] -= hull_centre
    shift[:2] -= hull_centre
    fp = fp.shifted(-hull_centre)

    volume = vol0 * s**3
    rho = resolve_density(volume, density, mass)
    dw = density_warning(rho, mass=mass, volume=volume)
    if dw:
        warnings.append(dw)
    com = R @ (com0 * s) + shift
    inertia = rho * s**5 * (R @ inertia0 @ R.T)
    mp = MassProperties(volume=volume, mass=rho * volume, density=rho, com=com, inertia=inertia)

    margin = fp.contains(com[:2])
    if margin <= 0:
        raise InputError(
            f"the body would not stand on its base: its centre of mass lies {-margin * 1000:.1f} mm "
            "outside the footprint (check --up, or the scan's base)"
        )
    if fp.area < 0.02 * fp.hull_area:
        warnings.append(
            f"the base touches the floor over only {fp.area * 1e4:.2f} cm^2 "
            f"of a {fp.hull_area * 1e4:.1f} cm^2 hull; check the contact tolerance ({tol * 1000:.2f} mm)"
        )
    base = base_contact(v2, com, surface, tol, why, tilt)
    bw = base.warning()
    if bw:
        warnings.append(bw)
    return Body(
        source=source, kind=kind, vertices=v2, faces=f, mass=mp, footprint=fp,
        units=("scaled to height" if height is not None else choice.units), up=cand.up, scale=s,
        rotation=R, translation=shift, log=tuple(steps), warnings=tuple(warnings), base=base,
        units_sure=True if height is not None else bool(choice.sure),
    )


def _polygon_centroid(ring: np.ndarray) -> np.ndarray:
    x, y = ring[:, 0], ring[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    a = cross.sum() / 2
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * a)


def load_body(path: str | Path, **options) -> Body:
    """Read the scan at ``path`` and run the pipeline (options as :func:`body_from_mesh`)."""
    raw = read_scan(path)
    body = body_from_mesh(raw.vertices, raw.faces, source=str(path), kind=raw.kind, log=raw.log, **options)
    extra = tuple(w for w in getattr(raw, "warnings", ()) if w not in body.warnings)
    return replace(body, warnings=extra + body.warnings) if extra else body
