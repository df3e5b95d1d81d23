"""Layer sections and per-layer DXF: volumes against the midpoint-rule bound,
islands and holes, and DXF files that audit clean and read back to the same parts."""
import math

import numpy as np
import pytest
import trimesh

from statue2model.fabrication.dxf import audit, read_section_dxf, write_section_dxf
from statue2model.fabrication.layers import section_heights, sections

BOARD, GLUE = 0.009, 0.0005
PITCH = BOARD + GLUE


def slab_volume(secs):
    return sum(s.area for s in secs) * PITCH


def test_sphere_volume_within_midpoint_bound():
    """Sections at mid-board, taken as prisms of height p: the error against the
    mesh volume is the midpoint-rule error (H p^2/24) |A''| = pi H p^2 / 12 for a
    sphere (A'' = -2 pi), plus the glue gap of each layer's own section policy."""
    R = 0.2
    m = trimesh.creation.icosphere(subdivisions=6, radius=R)
    v = m.vertices + [0, 0, R]
    H = 2 * R
    z = np.arange(int(round(H / PITCH))) * PITCH + 0.5 * PITCH  # mid-pitch: the pure midpoint rule
    vol = sum(s.area for s in sections(v, m.faces, z)) * PITCH
    covered = len(z) * PITCH
    # the slabs cover [0, covered]; the cap of the sphere above it is not in them
    cap = H - covered
    lost = math.pi * cap**2 * (3 * R - cap) / 3 if cap > 0 else 0.0
    bound = math.pi * H * PITCH**2 / 12
    error = vol - (m.volume - lost)
    assert abs(error) <= 1.05 * bound
    assert error == pytest.approx(bound, rel=0.2)  # the error has the predicted size and sign


def test_cone_volume_within_midpoint_bound():
    r0, H = 0.15, 0.38
    m = trimesh.creation.cone(radius=r0, height=H, sections=256)
    z = np.arange(40) * PITCH + 0.5 * PITCH
    vol = sum(s.area for s in sections(m.vertices, m.faces, z)) * PITCH
    # midpoint rule on A(z) = pi r0^2 (1 - z/H)^2 over [0, 40 p] (= 0.38 m = H)
    exact = m.volume
    bound = math.pi * r0**2 * PITCH**2 / (12 * H)
    assert abs(vol - exact) <= 1.05 * bound + 1e-6
    assert abs(vol - exact) >= 0.5 * bound  # the bound is tight, not vacuous


def test_islands_and_holes():
    tor = trimesh.creation.torus(0.1, 0.03)
    tor.apply_translation([0, 0, 0.05])
    (ring,) = sections(tor.vertices, tor.faces, [0.05])
    assert len(ring.geoms) == 1 and len(ring.geoms[0].interiors) == 1
    assert ring.area == pytest.approx(math.pi * (0.13**2 - 0.07**2), rel=2e-2)
    tor.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0], point=[0, 0, 0.05]))
    tor.apply_translation([0, 0, 0.13 - 0.05])
    (two,) = sections(tor.vertices, tor.faces, [0.13])
    assert len(two.geoms) == 2


def test_layer_count_of_the_thesis_prototype():
    """87 cm at 9 mm boards: 91 layers when the glue makes the pitch 9.56 mm (ch. 6.2.2)."""
    assert len(section_heights(0.87, 0.009, 0.00056)) == 91
    z = section_heights(0.87, BOARD, GLUE)
    assert len(z) == math.ceil(0.87 / PITCH) and z[0] == pytest.approx(BOARD / 2)


def test_default_scan_at_half_scale():
    from statue2model.geometry.body import load_body
    from statue2model.io.paths import default_scan

    body = load_body(default_scan())
    v = body.vertices * 0.5
    z = section_heights(v[:, 2].max(), BOARD, GLUE)
    secs = sections(v, body.faces, z)
    assert len(z) == 95                     # 0.900 m / 9.5 mm
    assert all(s.area > 0 for s in secs)
    assert max(len(s.geoms) for s in secs) >= 2   # the stack splits (legs, drapery)
    assert slab_volume(secs) == pytest.approx(body.mass.volume * 0.125, rel=0.02)


@pytest.mark.parametrize("shape", ["torus", "two_islands"])
def test_dxf_audits_clean_and_reads_back(tmp_path, shape):
    tor = trimesh.creation.torus(0.1, 0.03)
    if shape == "torus":
        tor.apply_translation([0, 0, 0.05])
        z = 0.05
    else:
        tor.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
        tor.apply_translation([0, 0, 0.13])
        z = 0.13
    (sec,) = sections(tor.vertices, tor.faces, [z])
    path = write_section_dxf(tmp_path / "layer_001.dxf", sec)
    assert audit(path) == []
    import ezdxf

    doc = ezdxf.readfile(str(path))
    assert doc.dxfversion == "AC1024" and doc.header["$INSUNITS"] == 4
    ents = doc.modelspace().query("LWPOLYLINE")
    assert all(e.closed for e in ents)
    assert {e.dxf.layer for e in ents} <= {"CUT_OUTSIDE", "CUT_INSIDE"}
    back = read_section_dxf(path)
    assert back.area == pytest.approx(sec.area, rel=1e-6)
    assert back.symmetric_difference(sec).area <= 1e-6 * sec.area
