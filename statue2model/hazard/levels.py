"""The collapse level (SLC) the isolation device is checked at (MODEL.md section 9).

NTC 2018 / Circolare 2019 (C7.10.5.3, 7.10.6.2.2) verify isolation devices under the actions
of the collapse limit state SLC, whose return period is T_R = -V_R / ln(1 - P_VR) with
P_VR = 5 %; the statue (the structure) keeps its own limit state at the design level. EN 1998-1
has no SLC: it asks for the isolators' displacements to be increased by the reliability factor
gamma_x (10.3(2); recommended 1.2 for buildings). So:

* EC8 site: the collapse-level spectrum is the design spectrum times GAMMA_X (a_g x 1.2: every
  ordinate, displacements included, x 1.2);
* NTC site with the site's SLC parameters given (``slc``: a_g, F0, T_C* read off the hazard grid at
  the SLC return period, hazard/ntc_grid.py): that spectrum;
* NTC site without them: a_g and T_C* scaled by the hazard's growth between the two return periods,
  a_g,SLC = a_g (T_R,SLC / T_R,ls)^(1 / K_HAZARD) and T_C*,SLC = T_C* (T_R,SLC / T_R,ls)^TC_EXPONENT, F0
  kept (S_S, C_C and T_D recomputed); the ratio of the return periods does not depend on V_R:
  ln(1 - P_VR,ls) / ln(1 - 0.05). K_HAZARD = 1.6 and TC_EXPONENT = 0.2 are the conservative end of the
  growth at the one grid cell bundled here (the Paolo Orsi museum, Syracuse: a_g 975 / 475 years gives
  K 2.1, SLC / SLA at V_R 75 years 1.7; T_C* grows with exponents 0.14-0.19; EN 1998-1 2.1(4) Note: "of
  the order of 3" elsewhere). An approximation for the isolator's long periods (their displacement grows
  with a_g T_C T_D), said in the design: give the site's own SLC parameters. A limit state not named
  (no ``ls=``) is read as SLV.

>>> from statue2model.hazard.code_spectra import parse_spectrum
>>> text, why = collapse_spectrum_text("ec8:ag=0.25g,ground=C,type=1")
>>> text, round(parse_spectrum(text).a_g / parse_spectrum("ec8:ag=0.25g,ground=C").a_g, 6)
('ec8:ag=0.3g,ground=C,type=1', 1.2)
>>> text, why = collapse_spectrum_text("ntc2018:ag=0.0669g,F0=2.511,Tc=0.286,soil=C,topo=T1,ls=SLA")
>>> text                                      # (ln 0.37 / ln 0.95)^(1 / 1.6) = 6.38
'ntc2018:ag=0.426652g,F0=2.511,Tc=0.517432,soil=C,topo=T1,ls=SLC'
"""
from __future__ import annotations

import math

from ..errors import InputError

GAMMA_X = 1.2
"""EN 1998-1 10.3(2): the isolators' displacements x gamma_x (recommended 1.2 for buildings)."""
P_VR = {"SLO": 0.81, "SLD": 0.63, "SLV": 0.10, "SLC": 0.05, "SLA": 0.63}
"""NTC 2018 Tab. 3.2.I (SLA as SLD: Direttiva P.C.M. 9/2/2011 par. 2.3, docs/venere.md)."""
K_HAZARD = 1.6
"""a_g ~ T_R^(1 / K_HAZARD) between two return periods, only where the site's SLC parameters are not given."""
TC_EXPONENT = 0.2
"""T_C* ~ T_R^TC_EXPONENT, likewise."""


def _items(text: str) -> tuple[str, list[tuple[str, str]]]:
    code, _, rest = text.partition(":")
    items = []
    for item in rest.split(","):
        k, _, v = item.partition("=")
        items.append((k.strip(), v.strip()))
    return code.strip().lower(), items


def _fmt(x: float) -> str:
    return f"{float(f'{x:.6g}'):g}"


def collapse_spectrum_text(spectrum: str, slc: str | None = None) -> tuple[str, str]:
    """The collapse-level ground spectrum (command-line form) of the design spectrum ``spectrum``
    (command-line form) and the reason in one sentence (module docstring); ``slc``: the site's own
    SLC spectrum (NTC), taken as it is."""
    from .code_spectra import G, parse_spectrum

    design = parse_spectrum(spectrum)              # refuses a malformed text with its own line
    if slc is not None:
        given = parse_spectrum(slc)
        if given.code != design.code:
            raise InputError(f"[isolator] slc_spectrum is {given.code} but the design spectrum is {design.code}")
        if given.a_g < design.a_g:
            raise InputError(f"[isolator] slc_spectrum has a_g {given.a_g / G:.4g} g below the design spectrum's "
                             f"{design.a_g / G:.4g} g: the collapse level cannot be weaker")
        return slc, "the site's SLC spectrum as given ([isolator] slc_spectrum)"
    code, items = _items(spectrum)
    if code == "ec8":
        out = [(k, _fmt(design.a_g * GAMMA_X / G) + "g") if k.lower() == "ag" else (k, v) for k, v in items]
        return (f"{code}:" + ",".join(f"{k}={v}" for k, v in out),
                f"EN 1998-1 10.3(2): the isolators' displacements x gamma_x {GAMMA_X:g}, i.e. the design spectrum "
                f"x {GAMMA_X:g}")
    ls = design.limit_state or "SLV"
    if ls == "SLC":
        return spectrum, "the design spectrum is the SLC one (ls=SLC)"
    ratio = math.log(1 - P_VR[ls]) / math.log(1 - P_VR["SLC"])
    factor = ratio ** (1.0 / K_HAZARD)
    tc = ratio ** TC_EXPONENT

    def scaled(k, v):
        if k.lower() == "ag":
            return k, _fmt(design.a_g * factor / G) + "g"
        if k.lower() == "tc":
            return k, _fmt(float(v) * tc)
        return k, v

    out = [scaled(k, v) for k, v in items if k.lower() != "ls"]
    out.append(("ls", "SLC"))
    why = (f"NTC 2018 / Circolare C7.10.5.3: the device at SLC (P_VR 5 %); without the site's SLC parameters "
           f"([isolator] slc_spectrum) a_g is scaled from {ls} by (T_R ratio {ratio:.3g})^(1/{K_HAZARD:g}) = "
           f"{factor:.3g} and T_C* by its ^{TC_EXPONENT:g} = {tc:.3g} (hazard/levels.py: an approximation; F0 kept)")
    if design.limit_state is None:
        why += "; the design spectrum names no limit state (ls=): read as SLV"
    return f"{code}:" + ",".join(f"{k}={v}" for k, v in out), why


def collapse_site(site, slc: str | None = None):
    """(SiteHazard at the collapse level, reason): the site ``site`` (hazard.site.SiteHazard) with its
    ground spectrum at SLC (:func:`collapse_spectrum_text`), under the same building and floor."""
    from .site import SiteHazard, site_hazard

    text, why = collapse_spectrum_text(site.spectrum, slc)
    if site.building is None:
        return site_hazard(text), why
    b = site.building
    method = getattr(site.target, "method", None)
    hz = site_hazard(text, floor=site.floor, storeys=b.n, height=b.H, period=b.T1, structure=b.structure, damping=b.xi, isolated=b.isolated, method=method)
    assert isinstance(hz, SiteHazard)
    return hz, why
