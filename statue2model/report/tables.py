"""Plain-text tables for the terminal.

Example
-------
>>> from statue2model.report.tables import format_table
>>> print(format_table([("m", "1.000", "kg")], title="Mass"))
Mass
  m  1.000  kg
"""
from __future__ import annotations

import math
import numbers


def _f(v, spec: str) -> str:
    """``format(v, spec)``, or '-' when v is None or not a finite number (never 'nan' or 'inf').

    >>> _f(0.25, ".3f"), _f(float("nan"), ".3f"), _f(None, ".0%")
    ('0.250', '-', '-')
    """
    if v is None or (isinstance(v, numbers.Real) and not math.isfinite(float(v))):
        return "-"
    return format(v, spec)


def _cell(c) -> str:
    """A cell as text: a non-finite number reads '-'."""
    return _f(c, "") if isinstance(c, numbers.Real) and not isinstance(c, numbers.Integral) else str(c)


def format_table(rows, title: str | None = None) -> str:
    """Align rows of strings in columns, with an optional title line (a non-finite number: '-')."""
    rows = [tuple(_cell(c) for c in r) for r in rows]
    width = [max(len(r[i]) for r in rows if i < len(r)) for i in range(max(len(r) for r in rows))]
    lines = [title] if title else []
    for r in rows:
        lines.append("  " + "  ".join(c.ljust(width[i]) if i < len(r) - 1 else c for i, c in enumerate(r)))
    return "\n".join(lines)


def base_table(body, params) -> str:
    """Contact at half, nominal and double tolerance: b_L, b_R along the direction, a_min."""
    base = body.base
    rows = [("tolerance", "b_L", "b_R", "a_min", "")]
    for k, r in enumerate(base.rows(body.mass.com, params.direction_deg, params.g)):
        rows.append((f"{_f(r['tol'] * 1000, '.2f')} mm", f"{_f(r['b_L'], '.4f')} m", f"{_f(r['b_R'], '.4f')} m",
                     f"{_f(r['a_min_g'], '.3f')} g", "used" if k == 1 else ""))
    verdict = f"a_min moves {_f(base.spread, '.0%')} (limit 10 %): " + ("UNCERTAIN" if base.uncertain else "ok")
    s = base.surface
    title = (f"Base contact (tolerance from {base.why}; base roughness {_f(s.roughness * 1000, '.2f')} mm rms, "
             f"warp {_f(s.warp * 1000, '.2f')} mm)")
    return format_table(rows, title=title) + "\n  " + verdict


def props_table(body, params, rose) -> str:
    """The readable summary printed by ``statue2model props``."""
    mp = body.mass
    g = params.g
    parts = [
        format_table(
            [
                ("source", body.source, ""),
                ("units / up", f"{body.units} / {body.up}", ""),
                ("height", _f(body.height, '.4f'), "m"),
                ("volume", _f(mp.volume, '.6g'), "m^3"),
                ("density", _f(mp.density, '.1f'), "kg/m^3"),
                ("mass", _f(mp.mass, '.4g'), "kg"),
                ("com", "(" + ", ".join(_f(c, '.4f') for c in mp.com) + ")", "m"),
                ("footprint", f"{_f(body.footprint.area, '.5f')} (hull {_f(body.footprint.hull_area, '.5f')})", "m^2"),
            ],
            title="Body",
        ),
        format_table(
            [
                ("direction", _f(params.direction_deg, '.2f'), "deg", ""),
                ("h", _f(params.h, '.4f'), "m", "height of G"),
                ("I_G", _f(params.I_G, '.5g'), "kg m^2", "about G, across the direction"),
                ("", "left (L)", "right (R)", ""),
                ("b", _f(params.b_L, '.4f'), _f(params.b_R, '.4f'), "m"),
                ("d", _f(params.d_L, '.4f'), _f(params.d_R, '.4f'), "m"),
                ("delta", _f(params.delta_L, '.4f'), _f(params.delta_R, '.4f'), "rad"),
                ("I", _f(params.I_L, '.5g'), _f(params.I_R, '.5g'), "kg m^2"),
                ("p", _f(params.p_L, '.4f'), _f(params.p_R, '.4f'), "rad/s"),
                ("a", f"{_f(params.a_L, '.4f')} ({_f(params.a_L / g, '.3f')} g)",
                 f"{_f(params.a_R, '.4f')} ({_f(params.a_R / g, '.3f')} g)", "m/s^2"),
                ("e", _f(params.e_L, '.4f'), _f(params.e_R, '.4f'), "-"),
            ],
            title="Rocking parameters",
        ),
        f"Weakest direction: {_f(rose.weakest_deg, '.2f')} deg, uplift at {_f(rose.a_min, '.4f')} m/s^2 "
        f"({_f(rose.a_min / g, '.3f')} g)",
    ]
    if getattr(body, "base", None) is not None:
        parts.append(base_table(body, params))
    if body.log:
        parts.append("Done to the scan:\n" + "\n".join(f"  - {s}" for s in body.log))
    if body.warnings:
        parts.append("\n".join(f"warning: {w}" for w in body.warnings))
    return "\n\n".join(parts)
