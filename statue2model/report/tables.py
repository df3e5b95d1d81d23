"""Plain-text tables for the terminal.

Example
-------
>>> from statue2model.report.tables import format_table
>>> print(format_table([("m", "1.000", "kg")], title="Mass"))
Mass
  m  1.000  kg
"""
from __future__ import annotations


def format_table(rows, title: str | None = None) -> str:
    """Align rows of strings in columns, with an optional title line."""
    rows = [tuple(str(c) for c in r) for r in rows]
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
        rows.append((f"{r['tol'] * 1000:.2f} mm", f"{r['b_L']:.4f} m", f"{r['b_R']:.4f} m", f"{r['a_min_g']:.3f} g",
                     "used" if k == 1 else ""))
    verdict = (f"a_min moves {base.spread:.0%} (limit {10:.0f} %): " + ("UNCERTAIN" if base.uncertain else "ok"))
    s = base.surface
    return format_table(rows, title=f"Base contact (tolerance from {base.why}; base roughness "
                                     f"{s.roughness * 1000:.2f} mm rms, warp {s.warp * 1000:.2f} mm)") + "\n  " + verdict


def props_table(body, params, rose) -> str:
    """The readable summary printed by ``statue2model props``."""
    mp = body.mass
    g = params.g
    parts = [
        format_table(
            [
                ("source", body.source, ""),
                ("units / up", f"{body.units} / {body.up}", ""),
                ("height", f"{body.height:.4f}", "m"),
                ("volume", f"{mp.volume:.6g}", "m^3"),
                ("density", f"{mp.density:.1f}", "kg/m^3"),
                ("mass", f"{mp.mass:.4g}", "kg"),
                ("com", "(" + ", ".join(f"{c:.4f}" for c in mp.com) + ")", "m"),
                ("footprint", f"{body.footprint.area:.5f} (hull {body.footprint.hull_area:.5f})", "m^2"),
            ],
            title="Body",
        ),
        format_table(
            [
                ("direction", f"{params.direction_deg:.2f}", "deg", ""),
                ("h", f"{params.h:.4f}", "m", "height of G"),
                ("I_G", f"{params.I_G:.5g}", "kg m^2", "about G, across the direction"),
                ("", "left (L)", "right (R)", ""),
                ("b", f"{params.b_L:.4f}", f"{params.b_R:.4f}", "m"),
                ("d", f"{params.d_L:.4f}", f"{params.d_R:.4f}", "m"),
                ("delta", f"{params.delta_L:.4f}", f"{params.delta_R:.4f}", "rad"),
                ("I", f"{params.I_L:.5g}", f"{params.I_R:.5g}", "kg m^2"),
                ("p", f"{params.p_L:.4f}", f"{params.p_R:.4f}", "rad/s"),
                ("a", f"{params.a_L:.4f} ({params.a_L / g:.3f} g)", f"{params.a_R:.4f} ({params.a_R / g:.3f} g)", "m/s^2"),
                ("e", f"{params.e_L:.4f}", f"{params.e_R:.4f}", "-"),
            ],
            title="Rocking parameters",
        ),
        f"Weakest direction: {rose.weakest_deg:.2f} deg, uplift at {rose.a_min:.4f} m/s^2 ({rose.a_min / g:.3f} g)",
    ]
    if getattr(body, "base", None) is not None:
        parts.append(base_table(body, params))
    if body.log:
        parts.append("Done to the scan:\n" + "\n".join(f"  - {s}" for s in body.log))
    if body.warnings:
        parts.append("\n".join(f"warning: {w}" for w in body.warnings))
    return "\n\n".join(parts)
