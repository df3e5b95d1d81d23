"""The ``props`` record: everything the scan stage hands to later stages, as JSON.

Top-level keys: the rocking parameters under their MODEL.md names (m, h, b_L,
b_R, I_G, d_L, d_R, delta_L, delta_R, I_L, I_R, p_L, p_R, a_L, a_R, e_L, e_R,
direction_deg, g, obliquity_L, obliquity_R), volume, mass, density, com, inertia, footprint, tipping
(the hull edges the body tips about toward -x and +x, with each ray's length and obliquity), base (contact
tolerance, base roughness and warp, and b_L, b_R, a_min at half and double the
tolerance), rose, and the
provenance (source, kind, units, up, scale, height, log, warnings). SI units.

Example
-------
>>> from statue2model.geometry.body import load_body
>>> from statue2model.io.paths import default_scan
>>> body = load_body(default_scan())
>>> d = props_dict(body, body.rocking(), body.rose())
>>> sorted(k for k in ("b_L", "b_R", "h", "I_G", "e_L", "footprint", "com") if k in d)
['I_G', 'b_L', 'b_R', 'com', 'e_L', 'footprint', 'h']
"""
from __future__ import annotations

from pathlib import Path

from ..version import __version__


def props_dict(body, params, rose) -> dict:
    out = {
        "schema": "statue2model.props/1",
        "version": __version__,
        "source": body.source,
        "kind": body.kind,
        "units": body.units,
        "up": body.up,
        "scale": body.scale,
        "height": body.height,
    }
    out.update(body.mass.to_dict())
    out.update(params.to_dict())
    out["footprint"] = body.footprint.to_dict()
    from .rocking_params import tipping_edges

    # the hull edges the body tips about toward +x and -x of the direction (the rays' exits, MODEL.md 1)
    out["tipping"] = tipping_edges(body.footprint.hull, body.mass.com[:2], params.direction_deg)
    if body.base is not None:
        out["base"] = body.base.to_dict(body.mass.com, params.direction_deg, params.g)
    out["rose"] = rose.to_dict()
    out["log"] = list(body.log)
    out["warnings"] = list(body.warnings)
    return out


def write_props(out: Path, body, params, rose) -> tuple[Path, Path]:
    """Write the props record to ``out`` (JSON) and the rose beside it (OUT_rose.csv), each
    atomically; returns the two paths. The footprint-and-rose figure (OUT.png) is drawn by
    :func:`statue2model.report.plots.plot_footprint_and_rose`."""
    from ..io.files import atomic_write, write_json

    out = Path(out)
    write_json(out, props_dict(body, params, rose))
    csv = atomic_write(out.with_name(out.stem + "_rose.csv"), lambda p: p.write_text(rose.to_csv()))
    return out, csv
