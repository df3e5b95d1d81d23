"""Base contact: the rest plane from the convex hull, a tolerance from the scan, and the
contact at half and double the tolerance, on bases with known answers (flat, dished,
domed, saddle-warped, rough and chamfered)."""
import json
import math

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.geometry.base import SENSITIVITY_LIMIT
from statue2model.geometry.body import body_from_mesh

from scan_fixtures import SECTORS, G, H, R, column  # noqa: E402


def body(bottom, **kw):
    v, f = column(bottom, **{k: kw.pop(k) for k in list(kw) if k in ("chamfer", "radius", "height")})
    return body_from_mesh(v, f, units="m", up="z", **kw)


def a_min(b):
    return b.rose().a_min


def test_column_fixture_is_a_closed_solid_of_the_right_volume():
    b = body(lambda x, y: 0 * x)
    area = 0.5 * SECTORS * R**2 * math.sin(2 * math.pi / SECTORS)
    assert b.mass.volume == pytest.approx(area * H, rel=1e-9)


def test_flat_base_rests_on_its_whole_disc():
    b = body(lambda x, y: 0 * x)
    h = b.mass.com[2]
    assert a_min(b) == pytest.approx(G * R * math.cos(math.pi / SECTORS) / h, rel=1e-6)
    assert not b.base.uncertain and not b.warnings
    assert b.base.tol == pytest.approx(0.25 * b.base.surface.edge)    # 7.5 mm rings: 1.9 mm > 0.1 % of H
    assert b.base.surface.roughness < 1e-9 and b.base.surface.warp < 1e-9


def test_dished_base_rests_on_its_rim_whatever_the_tolerance():
    """The underside rises 3 mm towards the middle: the rim carries the body."""
    b = body(lambda x, y: 0.003 * (1 - (x * x + y * y) / R**2))
    h = b.mass.com[2]
    assert a_min(b) == pytest.approx(G * R * math.cos(math.pi / SECTORS) / h, rel=1e-6)
    assert b.base.surface.warp == pytest.approx(0.003, rel=0.05)
    assert not b.base.uncertain


@pytest.mark.parametrize("tilt_deg", [0.7, 2.0, 6.0])
def test_dished_base_scanned_off_level_is_put_back_on_its_rim(tilt_deg):
    """The same dished column turned by a few degrees (a scan on a sloping turntable):
    the hull facet it rests on undoes the turn, and every number comes back."""
    v, f = column(lambda x, y: 0.003 * (1 - (x * x + y * y) / R**2))
    ref = body_from_mesh(v, f, units="m", up="z")
    t = math.radians(tilt_deg)
    turn = np.array([[math.cos(t), 0, math.sin(t)], [0, 1, 0], [-math.sin(t), 0, math.cos(t)]])
    b = body_from_mesh(v @ turn.T, f, units="m", up="z")
    assert b.base.tilt == pytest.approx(t, abs=1e-9)
    assert a_min(b) == pytest.approx(a_min(ref), rel=1e-9)
    assert b.mass.com[2] == pytest.approx(ref.mass.com[2], rel=1e-9)
    p, q = b.rocking(0.0), ref.rocking(0.0)
    assert (p.b_L + p.b_R) == pytest.approx(q.b_L + q.b_R, rel=1e-9)


def test_domed_base_touches_a_small_disc_and_says_the_answer_is_uncertain():
    """Lowest in the middle, 4 mm higher at the rim: the contact is a disc of radius
    R sqrt(tol / 4 mm), so the answer scales with sqrt(tol) and must be flagged."""
    dome = 0.004
    b = body(lambda x, y: dome * (x * x + y * y) / R**2)
    h = b.mass.com[2]
    tol = b.base.tol
    expect = G * R * math.sqrt(tol / dome) / h
    assert a_min(b) == pytest.approx(expect, rel=0.1)     # polar grid: rings every 7.5 mm
    lo, mid, hi = b.base.cases
    assert lo.a_min < mid.a_min < hi.a_min
    assert b.base.uncertain and b.base.spread > SENSITIVITY_LIMIT
    w = next(w for w in b.warnings if w.startswith("uncertain base contact"))
    assert "smooth surface rises 4." in w and "--base-tol" in w


def test_saddle_warped_base_rocks_across_its_low_ridge():
    """z = 3 mm (x^2 - y^2) / R^2: the body rests near (0, +-R); across x the contact
    half-width is R sqrt(tol / (2 x 3 mm))."""
    warp = 0.003
    b = body(lambda x, y: warp * (x * x - y * y) / R**2)
    h = b.mass.com[2]
    tol = b.base.tol
    expect = G * R * math.sqrt(tol / (2 * warp)) / h
    assert a_min(b) == pytest.approx(expect, rel=0.15)
    assert b.rose().weakest_deg % 180 == pytest.approx(0.0, abs=3.0)   # tips about the y axis
    assert b.base.uncertain


def test_rough_base_widens_the_tolerance_to_six_sigma_and_keeps_the_disc():
    rng = np.random.default_rng(7)
    sigma = 0.0008
    v, f = column(lambda x, y: rng.normal(0, sigma, np.shape(x)) if np.ndim(x) else 0.0, rings=80)
    b = body_from_mesh(v, f, units="m", up="z")
    h = b.mass.com[2]
    assert b.base.surface.roughness == pytest.approx(sigma, rel=0.15)
    assert b.base.tol == pytest.approx(6 * sigma, rel=0.15)
    assert b.base.why == "6 x the base roughness"
    assert a_min(b) == pytest.approx(G * R / h, rel=0.08)
    assert not b.base.uncertain


def test_chamfered_base_pivots_at_the_foot_of_the_chamfer():
    c = 0.02
    b = body(lambda x, y: 0 * x, chamfer=c)
    h = b.mass.com[2]
    assert a_min(b) == pytest.approx(G * (R - c) * math.cos(math.pi / SECTORS) / h, rel=1e-6)
    assert not b.base.uncertain


def test_given_tolerance_is_used_and_reported():
    b = body(lambda x, y: 0.004 * (x * x + y * y) / R**2, base_tol=0.0045)
    assert b.base.tol == 0.0045 and b.base.why == "given (--base-tol)"
    h = b.mass.com[2]
    # it rests on a facet at the apex, 0.02 deg off level: G moves 0.2 mm
    assert a_min(b) == pytest.approx(G * R * math.cos(math.pi / SECTORS) / h, rel=1e-3)


def test_height_is_exact_after_levelling():
    tilt = math.radians(3.0)
    v, f = column(lambda x, y: math.tan(tilt) * x)
    b = body_from_mesh(v * 0.7, f, up="z", height=1.234)
    assert b.height == pytest.approx(1.234, rel=1e-12)


def test_props_json_and_console_carry_the_sensitivity(tmp_path, capsys):
    import trimesh

    v, f = column(lambda x, y: 0.004 * (x * x + y * y) / R**2)
    path = tmp_path / "dome.ply"
    trimesh.Trimesh(v, f, process=False).export(path)
    out = tmp_path / "p.json"
    assert main(["props", str(path), "--units", "m", "--up", "z", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "Base contact" in text and "uncertain base contact" in text
    data = json.loads(out.read_text())
    base = data["base"]
    assert base["uncertain"] is True
    assert [row["tol"] for row in base["sensitivity"]] == pytest.approx([base["tol"] / 2, base["tol"], 2 * base["tol"]])
    assert any(w.startswith("uncertain base contact") for w in data["warnings"])
