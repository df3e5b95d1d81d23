"""The user's motion alone in 3D (crosscheck --only-motion), a record's two horizontal components,
and the 3D scene's 2D geometry taken from the rays as props takes it."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.errors import InputError
from statue2model.hazard import motions
from statue2model.io.paths import default_scan
from statue2model.quantities import G, G_STANDARD


def _xy_file(path, n=600, dt=0.01):
    t = np.arange(n) * dt
    ax = 0.30 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-((t - 2.5) / 1.5) ** 2)
    ay = 0.20 * np.cos(2 * np.pi * 0.9 * t) * np.exp(-((t - 3.0) / 1.2) ** 2)
    np.savetxt(path, np.column_stack([t, ax, ay]), delimiter=",", header="time,ax,ay", fmt="%.8f")
    return t, ax * G_STANDARD, ay * G_STANDARD


def test_two_components_resolved_along_and_across_the_direction(tmp_path):
    f = tmp_path / "xy.csv"
    _, ax, ay = _xy_file(f)
    (mx, my), _ = motions.parse_spec_components(f"file:path={f},units=g")
    assert mx.samples == pytest.approx(ax, abs=1e-7) and my.samples == pytest.approx(ay, abs=1e-7)
    par, perp = motions.along(mx, my, 30.0)
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert par.samples == pytest.approx(c * ax + s * ay, abs=1e-7)
    assert perp.samples == pytest.approx(-s * ax + c * ay, abs=1e-7)
    # energy is kept: |a|^2 is the same in both frames
    assert par.samples**2 + perp.samples**2 == pytest.approx(mx.samples**2 + my.samples**2, rel=1e-9, abs=1e-12)
    # pga= scales both by one factor: the larger component's peak is the PGA, the ratio is kept
    (sx, sy), _ = motions.parse_spec_components(f"file:path={f},units=g,pga=0.6g")
    assert max(sx.pga, sy.pga) == pytest.approx(0.6 * G)
    assert sy.pga / sx.pga == pytest.approx(my.pga / mx.pga)


def test_a_one_component_command_refuses_two_components_by_name(tmp_path):
    f = tmp_path / "xy.csv"
    _xy_file(f)
    with pytest.raises(InputError, match="3 columns .*two horizontal components.*--only-motion"):
        motions.parse_spec(f"file:path={f},units=g")


def test_only_motion_runs_the_users_motion_alone_with_both_components(tmp_path, capsys):
    f = tmp_path / "xy.csv"
    _xy_file(f)
    out = tmp_path / "cc"
    code = main(["crosscheck", str(default_scan()), "--motion", f"file:path={f},units=g,pga=0.7g", "--only-motion", "--quick",
                 "--direction", "90", "--out", str(out)])
    stdout, err = capsys.readouterr()
    assert code == 0, err
    data = json.loads((out / "crosscheck.json").read_text())
    names = [c["name"] for c in data["cases"]]
    # no standard case: no restitution, free rocking, pulses or boundaries
    assert not any(k in n for n in names for k in ("restitution", "free rocking", "one-sine", "boundary"))
    along = [n for n in names if "both components" not in n]
    both = [n for n in names if "both components" in n]
    assert along and both and any(n.endswith(": overturn") for n in both)
    assert data["only_motion"] is True and data["motion_across"]["pga_m_s2"] > 0
    # the record resolved along 90 deg: the along component is the file's a_y
    assert "along 90.0 deg" in names[0]


@pytest.mark.parametrize("argv, msg", [
    (["--motion", "free:theta0=0.01", "--only-motion"], "needs a ground motion"),
    (["--motion", "sine:amp=0.3g,freq=2", "--only-motion", "--records", "4"], "drop --imperfect and --records"),
])
def test_only_motion_refuses_what_it_cannot_run(tmp_path, capsys, argv, msg):
    code = main(["crosscheck", str(default_scan()), *argv, "--out", str(tmp_path / "o")])
    _, err = capsys.readouterr()
    assert code == 2 and msg in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_scene_geometry_is_the_rays_not_the_extreme_points():
    """Direction 30 deg of the default scan: the left tipping edge is oblique (~30 deg). The scene's
    2D parameters (what the cross-check's 2D side runs) are the rays' as props gives them, not the
    extreme base point's (0.405 m, 15 % longer: unconservative); the same in every direction."""
    from statue2model.crosscheck.statue_scene import StatueScene
    from statue2model.geometry.body import load_body

    body = load_body(default_scan())
    for d in (None, 0.0, 30.0, 200.0):
        p = body.rocking(d)
        sc = StatueScene.from_body(body, d)
        assert sc.params.b_L == pytest.approx(p.b_L, abs=1e-9) and sc.params.b_R == pytest.approx(p.b_R, abs=1e-9)
    sc = StatueScene.from_body(body, 30.0)
    assert sc.com[0] - sc.x_L > 1.1 * sc.params.b_L       # the extreme point lies well beyond the ray


def test_scene_stands_on_each_contact_of_the_band():
    """The scene at the band's tol / 2, tol and 2 tol stands on the same contact hull as the 2D model
    of that end (geometry/base.py ContactCase.b): the scan's points within tol on the floor."""
    from statue2model.crosscheck.statue_scene import StatueScene
    from statue2model.geometry.body import load_body

    body = load_body(default_scan())
    bs = []
    for case in body.base.cases:
        sc = StatueScene.from_body(body, 30.0, tol=case.tol)
        b_L, b_R = case.b(body.mass.com, 30.0)
        assert sc.params.b_L == pytest.approx(b_L, abs=1e-9) and sc.params.b_R == pytest.approx(b_R, abs=1e-9)
        bs.append(b_R)
    assert bs[2] > bs[0] + 1e-3          # the band's ends differ on this scan (2 tol reaches farther)
    with pytest.raises(InputError, match="cannot stand on its contact"):
        StatueScene.from_body(body, 30.0, tol=0.0)     # one point on the floor
