"""Synthetic scans with one defect each, and the exact answers they must give.

Every fixture is the same kind of object, a column on a disc base (a regular
SECTORS-gon prism, radius R, height H, in metres), so the reference values are
closed-form: volume, h, b (= R cos(pi / SECTORS) along an edge normal), a_min; I_G
comes from trimesh's integration of the clean mesh (an independent code). The
defects are the classes found on real scans (twin faces, pinched edges and
vertices, messy scans, loose pieces, cavities, overlapping shells) and the base
shapes that make contact doubtful (dished, domed, saddle, rough, chamfered).

Used by tests/test_scan_fixtures.py (every case must give its answer or be
refused) and by benchmarks/accuracy_scans.py (the table of the closing note).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

R, H = 0.3, 1.0          # disc radius and column height, m
RINGS, SECTORS = 40, 120
G = 9.81


def column(bottom=lambda x, y: 0 * x, radius=R, height=H, chamfer=0.0, rings=RINGS, sectors=SECTORS,
           wall_levels=0):
    """A closed column: bottom surface z = bottom(x, y) on a polar grid (rings x sectors),
    vertical wall (with ``wall_levels`` intermediate rings), flat top; optional 45 deg
    chamfer at the foot. Returns vertices (n, 3) m and outward faces (f, 3)."""
    t = np.linspace(0, 2 * np.pi, sectors, endpoint=False)
    r_in = radius - chamfer
    verts = [[0.0, 0.0, bottom(0.0, 0.0)]]
    for i in range(1, rings + 1):
        r = r_in * i / rings
        x, y = r * np.cos(t), r * np.sin(t)
        verts.extend(np.column_stack([x, y, bottom(x, y)]))
    z0 = chamfer
    levels = ([chamfer] if chamfer else []) + list(np.linspace(z0, height, wall_levels + 2)[1:])
    for z in levels:
        verts.extend(np.column_stack([radius * np.cos(t), radius * np.sin(t), np.full(sectors, z)]))
    verts.append([0.0, 0.0, height])
    v = np.array(verts, dtype=float)
    faces = []
    def ring(i):
        return 1 + (i - 1) * sectors + np.arange(sectors)   # i = 1..rings (+ wall levels)
    def nxt(a):
        return np.roll(a, -1)
    a = ring(1)
    faces.extend(np.column_stack([np.zeros(sectors, int), nxt(a), a]))   # facing down
    for i in range(1, rings + len(levels)):
        a, b = ring(i), ring(i + 1)
        faces.extend(np.column_stack([a, nxt(a), nxt(b)]))
        faces.extend(np.column_stack([a, nxt(b), b]))
    top = ring(rings + len(levels))
    faces.extend(np.column_stack([np.full(sectors, len(v) - 1), top, nxt(top)]))
    return v, np.array(faces)


def prism_reference(radius=R, height=H, sectors=SECTORS, density=2650.0) -> dict:
    """Closed-form volume, h, b (along an edge normal) and a_min of the regular-polygon prism,
    with I_G about a horizontal axis through G from trimesh (independent integration)."""
    import trimesh

    area = 0.5 * sectors * radius**2 * math.sin(2 * math.pi / sectors)
    b = radius * math.cos(math.pi / sectors)
    v, f = column(radius=radius, height=height, sectors=sectors, rings=1)
    mesh = trimesh.Trimesh(v, f, process=False)
    mesh.density = density
    I_G = float(mesh.moment_inertia[0, 0])
    return {"volume": area * height, "h": height / 2, "b_L": b, "b_R": b, "I_G": I_G,
            "a_min": G * b / (height / 2)}


@dataclass
class Case:
    """A fixture: its defect, the mesh, what must happen ('repaired' or 'refused'), the
    reference values (for 'repaired') or the words the refusal must hold, and the
    options of body_from_mesh."""

    defect: str
    vertices: np.ndarray
    faces: np.ndarray
    expect: str
    reference: dict = field(default_factory=dict)
    refusal: str = ""
    options: dict = field(default_factory=dict)
    tolerance: float = 1e-6          # largest relative error accepted on each reference value
    warns: str = ""                  # a warning that must be given


def _wall_faces(v, f):
    c = v[f].mean(axis=1)
    return np.flatnonzero((np.hypot(c[:, 0], c[:, 1]) > 0.99 * R * math.cos(math.pi / SECTORS)) &
                          (c[:, 2] > 0.1 * H) & (c[:, 2] < 0.9 * H))


def _wall_edges(v, f, rng, n):
    wall = f[_wall_faces(v, f)]
    edges = np.unique(np.sort(wall[:, [0, 1]], axis=1), axis=0)
    return edges[rng.choice(len(edges), n, replace=False)]


def _flaps(v, f, edges, fourth=True):
    """A triangle on each edge (3 faces on it), and on every other edge a fourth."""
    v, f = [v], [f]
    n = len(v[0])
    for k, (a, b) in enumerate(edges):
        v.append((v[0][a] * [1.02, 1.02, 1.0])[None])
        f.append([[a, b, n + k]])
    if fourth:
        m = n + len(edges)
        for k, (a, b) in enumerate(edges[::2]):
            v.append((v[0][b] * [1.03, 1.03, 1.0])[None])
            f.append([[b, a, m + k]])
    return np.vstack(v), np.vstack(f)


def _box(lo, hi):
    import trimesh

    b = trimesh.creation.box(extents=np.subtract(hi, lo))
    b.apply_translation(0.5 * (np.add(lo, hi)))
    return np.asarray(b.vertices), np.asarray(b.faces)


def _join(*parts):
    vs, fs, off = [], [], 0
    for v, f in parts:
        vs.append(v)
        fs.append(f + off)
        off += len(v)
    return np.vstack(vs), np.vstack(fs)


def defect_cases() -> list[Case]:
    """Every fixture of the module docstring, with its expected outcome."""
    ref = prism_reference()
    opts = {"units": "m", "up": "z"}
    rng = np.random.default_rng(11)
    cases = []
    v0, f0 = column(wall_levels=20)
    cases.append(Case("clean column (reference)", v0, f0, "repaired", ref, options=opts))

    a, b = _wall_edges(v0, f0, rng, 1)[0]
    v = np.vstack([v0, v0[a] * [1.3, 1.3, 1.0]])
    f = np.vstack([f0, [[a, b, len(v0)], [b, a, len(v0)]]])
    cases.append(Case("twin faces: a zero-thickness fin", v, f, "repaired", ref, options=opts))

    k = _wall_faces(v0, f0)[5]
    cases.append(Case("twin faces: a surface triangle twice, opposite winding",
                      v0, np.vstack([f0, f0[[k]][:, ::-1]]), "repaired", ref, options=opts))

    v, f = _flaps(v0, f0, _wall_edges(v0, f0, rng, 6))
    cases.append(Case("non-manifold edges: 6 edges on 3-4 faces", v, f, "repaired", ref, options=opts,
                      tolerance=1e-3))

    vid = f0[_wall_faces(v0, f0)[40], 0]
    fan = np.flatnonzero((f0 == vid).any(axis=1))
    keep = np.ones(len(f0), bool)
    keep[fan[[0, 3]]] = False
    cases.append(Case("pinched vertex: two holes meeting at one vertex", v0, f0[keep], "repaired", ref,
                      options=opts, tolerance=1e-3))

    v, f = _flaps(v0, f0, _wall_edges(v0, f0, rng, 30), fourth=False)
    wall = _wall_faces(v0, f0)
    holes = rng.choice(wall, 40, replace=False)
    keep = np.ones(len(f), bool)
    keep[holes] = False
    flipped = rng.choice(np.setdiff1d(wall, holes), 25, replace=False)
    f = f.copy()
    f[flipped] = f[flipped][:, ::-1]
    f = f[keep]
    scraps = [_box((0.5 + 0.03 * i, 0, 0.5), (0.51 + 0.03 * i, 0.01, 0.51)) for i in range(4)]
    v, f = _join((v, f), *scraps, (np.array([[0.0, 0.6, 0.5], [0.01, 0.6, 0.5], [0.0, 0.61, 0.5]]), np.array([[0, 1, 2]])))
    cases.append(Case("messy scan: 30 non-manifold edges, 120 boundary edges, 25 flipped faces, 5 loose scraps",
                      v, f, "repaired", ref, options=opts, tolerance=2e-3))

    cases.append(Case("loose piece: a 3 cm cube 0.2 m away (0.05 % of the volume)",
                      *_join((v0, f0), _box((0.5, -0.015, 0.3), (0.53, 0.015, 0.33))), "repaired", ref,
                      options=opts))
    vt = v0 + [0, 0, 1.7]
    cases.append(Case("separate pieces: a second column 0.7 m above the first", *_join((v0, f0), (vt, f0)),
                      "refused", refusal="not joined to the main body", options=opts))

    plinth = _box((-0.3, -0.3, 0.0), (0.3, 0.3, 0.2))
    figure = _box((-0.1, -0.1, 0.2), (0.1, 0.1, 1.2))
    arm = _box((0.0, -0.05, 0.9), (0.4, 0.05, 1.0))      # through the figure, sticking out
    m_p, m_f, m_a = 0.072, 0.04, 0.4 * 0.1 * 0.1 - 0.1 * 0.1 * 0.1
    vol = m_p + m_f + m_a
    h = (m_p * 0.1 + m_f * 0.7 + m_a * 0.95) / vol
    com_x = m_a * 0.25 / vol
    cases.append(Case("overlapping shells: plinth, figure and an arm through it", *_join(plinth, figure, arm),
                      "repaired", {"volume": vol, "h": h, "a_min": G * (0.3 - com_x) / h}, options=opts,
                      tolerance=1e-9))

    inner = _box((-0.1, -0.1, 0.4), (0.1, 0.1, 0.6))
    cav = {"volume": ref["volume"] - 0.008, "h": ref["h"], "a_min": ref["a_min"]}
    cases.append(Case("cavity: a closed shell inside the body", *_join((v0, f0), (inner[0], inner[1][:, ::-1])),
                      "repaired", cav, options=opts))

    keep = np.ones(len(f0), bool)
    side = np.flatnonzero((v0[f0].mean(axis=1)[:, 0] > 0.25) & (np.abs(v0[f0].mean(axis=1)[:, 2] - 0.5) < 0.2))
    keep[side] = False
    cases.append(Case("large curved opening in the wall", v0, f0[keep], "refused", refusal="could not be closed",
                      options=opts))

    for name, bottom, kw, expect_a, warns in (
        ("base: dished 3 mm (rests on its rim)", lambda x, y: 0.003 * (1 - (x * x + y * y) / R**2), {},
         ref["a_min"], ""),
        ("base: chamfered 20 mm at 45 deg", lambda x, y: 0 * x, {"chamfer": 0.02},
         G * (R - 0.02) * math.cos(math.pi / SECTORS) / (H / 2), ""),
    ):
        v, f = column(bottom, **kw)
        cases.append(Case(name, v, f, "repaired", {"a_min": expect_a}, options=opts, tolerance=2e-3, warns=warns))
    v, f = column(lambda x, y: 0.004 * (x * x + y * y) / R**2)
    cases.append(Case("base: domed 4 mm (rests on a small disc)", v, f, "repaired", {}, options=opts,
                      warns="uncertain base contact"))
    v, f = column(lambda x, y: 0.003 * (x * x - y * y) / R**2)
    cases.append(Case("base: saddle-warped 3 mm", v, f, "repaired", {}, options=opts,
                      warns="uncertain base contact"))
    noise = np.random.default_rng(7)
    v, f = column(lambda x, y: noise.normal(0, 0.0008, np.shape(x)) if np.ndim(x) else 0.0, rings=80)
    cases.append(Case("base: rough, 0.8 mm rms noise", v, f, "repaired", {"a_min": ref["a_min"]}, options=opts,
                      tolerance=0.08))
    t = math.radians(2.0)
    turn = np.array([[math.cos(t), 0, math.sin(t)], [0, 1, 0], [-math.sin(t), 0, math.cos(t)]])
    cases.append(Case("base: scanned 2 deg off level", v0 @ turn.T, f0, "repaired", ref, options=opts,
                      tolerance=1e-6))
    return cases


def expected_a_min(case: Case, body) -> float | None:
    """The closed-form a_min of the domed and saddle bases at the tolerance the body used."""
    tol = body.base.tol
    h = body.mass.com[2]
    if case.defect.startswith("base: domed"):
        return G * R * math.sqrt(tol / 0.004) / h
    if case.defect.startswith("base: saddle"):
        return G * R * math.sqrt(tol / (2 * 0.003)) / h
    return None
