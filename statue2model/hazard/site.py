"""Where the object stands: the site's ground spectrum and, for an object on an upper floor, the
floor spectrum of its building; the one design target every analysis of a run uses.

:func:`site_hazard` takes the project's ground spectrum (its command-line form,
``ec8:ag=0.25g,ground=C``) and the building (floor, storeys, height, period, structure,
damping, isolated; :class:`statue2model.hazard.building.Building`) and gives a
:class:`SiteHazard`: ``ground`` (the ElasticSpectrum), ``target`` (the ground spectrum itself
on the ground floor of a building that is not isolated, else the floor spectrum of
:mod:`statue2model.hazard.floor`), ``pga`` (the target's Se(0), m/s^2: the design PGA on the
ground, the peak floor acceleration on a floor) and ``text``, the hazard in one line.

Example
-------
>>> hz = site_hazard("ntc2018:ag=0.2g,F0=2.4,Tc=0.3,soil=C", floor=2, storeys=3, height=12.0)
>>> hz.on_floor, hz.building.structure, round(hz.pga / 9.80665, 3) > round(hz.ground_pga / 9.80665, 3)
(True, 'masonry', True)
>>> site_hazard("ec8:ag=0.25g,ground=C").on_floor
False
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..quantities import G


@dataclass(frozen=True)
class SiteHazard:
    """The design target of a run (module docstring). ``building`` None: on the ground."""

    spectrum: str
    ground: object
    target: object
    floor: int = 0
    building: object = None

    @property
    def on_floor(self) -> bool:
        """True when the target is a floor spectrum."""
        return self.target is not self.ground

    @property
    def pga(self) -> float:
        """Se(0) of the target, m/s^2: the design PGA on the ground, the peak floor acceleration on a floor."""
        return float(np.asarray(self.target.Se(np.array([0.0])))[0])

    @property
    def ground_pga(self) -> float:
        """a_g S of the site, m/s^2."""
        return self.ground.a_g * self.ground.S

    @property
    def building_period(self) -> float | None:
        """T1 of the building (s), None on the ground."""
        return None if self.building is None else self.building.period

    @property
    def text(self) -> str:
        """The hazard in one line: the ground spectrum, and the floor with its building and formula."""
        sp = self.ground
        # "design PGA" names one number per object: the ground's on the ground, the floor's on a floor
        pga_name = "ground PGA" if self.on_floor else "design PGA"
        line = (f"{sp.code} spectrum {self.spectrum!r}: a_g {sp.a_g / G:.3f} g, S {sp.S:.2f}, {pga_name} "
                f"{self.ground_pga / G:.3f} g" + (f", limit state {sp.limit_state}" if sp.limit_state else ""))
        if self.building is None:
            return line + "; the object stands on the ground"
        b = self.building
        where = (f"floor {self.floor} of a {b.n}-storey {b.structure} building, H {b.H:g} m, T1 {b.period:.3g} s"
                 + (" (estimated C_t H^3/4)" if b.period_estimated else "") + (", base-isolated" if b.isolated else ""))
        if not self.on_floor:
            return line + f"; {where}: the ground floor moves with the ground"
        from .floor import NAMES

        return (line + f"; {where}: {NAMES[self.target.method]}, peak floor acceleration "
                f"{self.pga / G:.3f} g, the design PGA at the object")

    def to_dict(self) -> dict:
        return {"spectrum": self.spectrum, "ground": self.ground.to_dict(), "floor": self.floor,
                "building": None if self.building is None else self.building.to_dict(),
                "target": self.target.to_dict(), "on_floor": self.on_floor, "pga_m_s2": self.pga,
                "ground_pga_m_s2": self.ground_pga, "text": self.text}


def site_hazard(spectrum: str, floor: int = 0, storeys: int | None = None, height: float | None = None,
                period: float | None = None, structure: str = "masonry", damping: float = 5.0,
                isolated: bool = False, method: str | None = None) -> SiteHazard:
    """The :class:`SiteHazard` of a ground spectrum (command-line form) and a building; with
    ``floor`` 0 and no building the ground spectrum is the target. ``method``: the floor
    spectrum's formula (None: the general formulation C7.2.5-10 on an NTC site, EC8 eq. 4.25
    on an EC8 one; statue2model.hazard.floor.METHODS)."""
    from .building import Building
    from .code_spectra import parse_spectrum
    from .floor import floor_spectrum_for

    ground = parse_spectrum(spectrum)
    if storeys is None and height is None:
        if floor not in (0, None):
            raise InputError(f"[building] floor = {floor}: give the building's storeys and height (and its period, "
                             "or leave it to the estimate C_t H^3/4)")
        return SiteHazard(spectrum, ground, ground)
    if storeys is None or height is None:
        raise InputError("[building] needs both storeys and height (m) to place the object on a floor")
    b = Building(storeys, height, period, structure, damping, isolated)
    target = floor_spectrum_for(ground, b, floor, method)
    return SiteHazard(spectrum, ground, target, int(floor), b)


def site_of(cfg, default_spectrum: str) -> SiteHazard:
    """The :class:`SiteHazard` of a project configuration ``cfg`` (any object with ``isolator.spectrum``
    and ``building``: floor, storeys, height, period, structure, damping, isolated, floor_spectrum;
    either may be missing, and ``cfg`` None): its ground spectrum, or ``default_spectrum`` when it
    names none, under its building."""
    iso = getattr(cfg, "isolator", None)
    text = getattr(iso, "spectrum", None) or default_spectrum
    b = getattr(cfg, "building", None)
    if b is None:
        return site_hazard(text)
    return site_hazard(text, floor=b.floor, storeys=b.storeys, height=b.height, period=b.period,
                       structure=b.structure, damping=b.damping, isolated=b.isolated,
                       method=None if b.floor_spectrum == "auto" else b.floor_spectrum)
