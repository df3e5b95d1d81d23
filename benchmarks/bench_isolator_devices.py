"""The isolator device the verified search (isolator/verify.py) finds for five bodies at two sites, in one
table: layout, balls, surface, plate, period, cost, the time-history margins at the design level and at
the collapse level (SLC), the reserve margin, the reason when nothing passes, and the wall time per case.

Bodies
    the three bundled scans (meshes/dancing_girl.ply, maria_barjatinskaja.ply, nefertiti_bust.obj): their
    RockingParams from ``statue2model props MESH --json OUT`` (the CLI, into a temporary folder; marble
    2650 kg/m^3, the weakest direction), with the base's uplift band when props flags the contact
    uncertain, as the pipeline's isolator stage reads it (_uplift_band);
    two synthetic statues, homogeneous blocks (RockingParams.rectangular_block, I_G = m (b^2 + h^2) / 3)
    with the proportions of real marble statues:
      "statuette 50 kg"   m 50 kg, centre of mass h 0.35 m, half-base b 0.09 m: a 0.70 m tall figure on a
                          0.18 m plinth (b/h 0.26, uplift 0.26 g; marble: about 0.15 m deep);
      "life-size 1500 kg" m 1500 kg, h 1.0 m, b 0.30 m: a 2 m standing figure on a 0.6 m plinth (b/h 0.30,
                          uplift 0.30 g; marble: about 0.47 m deep).
Sites (on the ground)
    'ec8:ag=0.25g,ground=C,type=1'                             the default site
    'ntc2018:ag=0.2g,F0=2.4,Tc=0.3,soil=B,topo=T1,ls=SLV'      an NTC 2018 site
Per (body, site), what the pipeline's isolator stage does (pipeline/stages.py isolator_stage, with the
default project file's [isolator] and [model]): the design set of 7 records matched to the site's target
(assessment.study.match_records, T_is = design.longest_period(), the site's code, seeds 1..7), ``--sets``
further sets (seeds 101.., 201.., 301..), the collapse-level spectrum (hazard.levels.collapse_site), the
fixed-base Housner RockingModel for the reserve, a_lim = min(contact_limits(model, uplift band)), fuse
release 0.075 g, boards 0.03 m, and verify(...) on an executor (--workers, 0: serial). The record sets
depend on the site only: they are matched once per site (the time is printed) and shared by the bodies;
the "wall s" column is verify() alone.

Columns: margins are limit / demand (>= 1 passes; verify.DEFINITIONS): design level "trav" (travel over
every set), "felt" (felt acceleration vs the uplift limit), "ball" (static ball load); SLC "trav" and
"ball"; "resv" the reserve. A failing case shows the nearest makeable device, its cost in brackets and
what_would_pass['text'] cut to 90 characters.

    python3 benchmarks/bench_isolator_devices.py              # 5 bodies x 2 sites, 3 further sets
    python3 benchmarks/bench_isolator_devices.py --quick      # default site only, no further sets
    python3 benchmarks/bench_isolator_devices.py --sets 1 --workers 0 --csv /tmp/devices.csv
"""
from __future__ import annotations

import argparse
import csv
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCANS = ("meshes/dancing_girl.ply", "meshes/maria_barjatinskaja.ply", "meshes/nefertiti_bust.obj")
SITES = ("ec8:ag=0.25g,ground=C,type=1", "ntc2018:ag=0.2g,F0=2.4,Tc=0.3,soil=B,topo=T1,ls=SLV")
SYNTHETIC = (("statuette 50 kg", {"b": 0.09, "h": 0.35, "m": 50.0}),
             ("life-size 1500 kg", {"b": 0.30, "h": 1.0, "m": 1500.0}))
EXTRA_SEEDS = 100            # pipeline.stages.EXTRA_SEEDS: further set k takes seeds k x 100 + 1 ..


def scan_bodies(tmp: Path) -> list:
    """[(name, RockingParams, uplift band or None)] of the bundled scans, through ``statue2model props``."""
    from statue2model.geometry.rocking_params import RockingParams
    from statue2model.io.files import read_json

    exe = Path(sys.executable).with_name("statue2model")
    out = []
    for rel in SCANS:
        mesh = ROOT / rel
        js = tmp / (mesh.stem + ".json")
        cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "statue2model"]
        subprocess.run(cmd + ["props", str(mesh), "--json", str(js)], check=True, capture_output=True, text=True)
        d = read_json(js)
        base = d.get("base") or {}
        rows = base.get("sensitivity") or []
        band = None
        if base.get("uncertain") and rows:          # pipeline.stages._uplift_band
            vals = [float(r["a_min"]) for r in rows]
            band = (min(vals), max(vals))
        out.append((mesh.stem, RockingParams.from_dict(d), band))
    return out


def synthetic_bodies() -> list:
    from statue2model.geometry.rocking_params import RockingParams

    return [(name, RockingParams.rectangular_block(**kw), None) for name, kw in SYNTHETIC]


def record_sets(hz, n_sets: int, cfg):
    """(design RecordSet of the matcher, info, [verify.RecordSet of the further sets]) as the pipeline
    builds them (stages._match, _design_set, _extra_set)."""
    from statue2model.assessment.study import match_records
    from statue2model.isolator.design import longest_period
    from statue2model.isolator.verify import RecordSet

    dc = cfg.dynamics

    def match(seed):
        return match_records(hz.target, dc.fragility_records, dc.fragility_duration, T1=None,
                             T_is=longest_period(), seed=seed, code=hz.ground.code)

    rs = match(1)
    n = len(rs.records)
    info = {"source": "design set", "rules_met": bool(rs.check()["met"]), "band_s": list(rs.band),
            "band_reason": rs.to_dict().get("band_reason"), "seeds": f"1-{n}",
            "duration_s": max(r.duration for r in rs.records)}
    extra = []
    for k in range(1, n_sets + 1):
        s0 = k * EXTRA_SEEDS + 1
        x = match(s0)
        nx = len(x.records)
        extra.append(RecordSet(f"seeds {s0}-{s0 + nx - 1}", tuple(x.records), f"{s0}-{s0 + nx - 1}",
                               {"rules_met": bool(x.check()["met"]), "band_s": list(x.band),
                                "band_reason": x.to_dict().get("band_reason")}))
    return rs, info, extra


def run_case(params, band, hz, sets, cfg, executor):
    """verify() with the isolator stage's arguments; returns the Design."""
    from statue2model.assessment.limit_states import contact_limits
    from statue2model.hazard.levels import collapse_site
    from statue2model.isolator.verify import verify
    from statue2model.rocking.model import RockingModel

    c, m = cfg.isolator, cfg.model
    rs, info, extra = sets
    model = RockingModel.housner(params, m.e_L, m.e_R, mu_static=m.mu_static)
    a_lim = min(contact_limits(model, band))
    why = ("min over the sides of alpha_side min(a_side, the low end of the uncertain base's uplift band "
           f"{band[0]:.4g}-{band[1]:.4g} m/s^2)" if band is not None else "min(alpha_L a_L, alpha_R a_R)")
    slc_hz, slc_why = collapse_site(hz, c.slc_spectrum)
    return verify(params, records=rs.records, extra_sets=extra, fixed_model=model, design_pga=hz.pga,
                  rtol=m.rtol, mu=c.mu, mu_low=c.mu_low, mu_high=c.mu_high, a_lim=a_lim, a_lim_why=why,
                  records_info=info, spectrum=hz.target, slc=slc_hz.target, slc_why=slc_why, motion=None,
                  target=c.target, alpha=(1.0, 1.0), n_grooves=c.grooves, layouts=c.layout, surfaces=c.surface,
                  materials=c.ball_material, thickness=c.thickness, side_max=c.side_max,
                  fuse_release=c.fuse_release, ball_capacity=c.ball_capacity, price_table=dict(c.prices),
                  executor=executor)


def _m(x) -> str:
    return "-" if x is None or not isinstance(x, (int, float)) or not math.isfinite(x) else f"{x:.2f}"


COLUMNS = ("body", "kg", "site", "pass", "layout", "n", "D mm", "surface", "side m", "T s", "EUR",
           "trav", "felt", "ball", "SLC trav", "SLC ball", "resv", "wall s")


def row_of(name, params, site_name, d, wall) -> dict:
    mg = d.th_margins or {}
    reason = "" if d.passed else (d.what_would_pass or {}).get("text", d.failure or "")[:90]
    return {"body": name, "kg": f"{params.m:.1f}", "site": site_name, "pass": "yes" if d.passed else "NO",
            "layout": d.layout, "n": str(d.n_grooves), "D mm": f"{2 * d.r * 1000:g}", "surface": d.surface,
            "side m": f"{d.side:.3f}", "T s": f"{d.T:.2f}",
            "EUR": f"{d.cost:.0f}" if d.passed else f"({d.cost:.0f})",
            "trav": _m(mg.get("travel")), "felt": _m(mg.get("acceleration")), "ball": _m(mg.get("bearing")),
            "SLC trav": _m(mg.get("travel_slc")), "SLC ball": _m(mg.get("bearing_slc")),
            "resv": _m(mg.get("reserve")), "wall s": f"{wall:.1f}", "reason": reason}


def print_table(rows) -> None:
    w = {c: max(len(c), *(len(r[c]) for r in rows)) for c in COLUMNS}
    left = {"body", "site", "layout", "surface", "pass"}
    def line(r):
        return " ".join(r[c].ljust(w[c]) if c in left else r[c].rjust(w[c]) for c in COLUMNS)

    print(line({c: c for c in COLUMNS}))
    for r in rows:
        print(line(r))
    fails = [r for r in rows if r["reason"]]
    if fails:
        print("why nothing passes:")
        for r in fails:
            print(f"  {r['body']} @ {r['site']}: {r['reason']}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="the default site only, no further sets")
    ap.add_argument("--sets", type=int, default=3, help="further record sets (default 3, the pipeline's)")
    ap.add_argument("--workers", type=int, default=2, help="worker processes for verify (0: serial; default 2)")
    ap.add_argument("--bodies", default=None, help="comma list of body names to run (default: all five)")
    ap.add_argument("--sites", default=None, help="comma list of site indexes 0,1 (default: both; --quick: 0)")
    ap.add_argument("--csv", default=None, help="also write the table as CSV here")
    a = ap.parse_args()
    from statue2model.compute.executors import make_executor
    from statue2model.hazard.site import site_hazard
    from statue2model.pipeline.config import load_config

    cfg = load_config(None)
    n_sets = 0 if a.quick else a.sets
    site_idx = [0] if a.quick else list(range(len(SITES)))
    if a.sites:
        site_idx = [int(s) for s in a.sites.split(",")]
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        bodies = scan_bodies(Path(tmp)) + synthetic_bodies()
    t_props = time.perf_counter() - t0
    if a.bodies:
        keep = [s.strip() for s in a.bodies.split(",")]
        bodies = [b for b in bodies if any(k in b[0] for k in keep)]
    print(f"bodies: props of the 3 scans by the CLI in {t_props:.1f} s; further sets {n_sets}; "
          f"workers {a.workers or 'serial'}")
    for name, p, band in bodies:
        print(f"  {name:20s} m {p.m:7.1f} kg, h {p.h:.3f} m, b_L {p.b_L:.3f} b_R {p.b_R:.3f} m, uplift "
              f"{min(p.a_L, p.a_R) / p.g:.3f} g" + (f" (uncertain base: band {band[0] / p.g:.3f}-"
                                                   f"{band[1] / p.g:.3f} g)" if band else ""))
    rows = []
    ex = make_executor(workers=a.workers) if a.workers else None
    try:
        for si in site_idx:
            hz = site_hazard(SITES[si])
            t = time.perf_counter()
            sets = record_sets(hz, n_sets, cfg)
            print(f"site {si} {SITES[si]}: design PGA {hz.pga / 9.81:.3f} g; {1 + n_sets} sets of "
                  f"{len(sets[0].records)} records matched in {time.perf_counter() - t:.1f} s "
                  f"(design set rules met: {sets[1]['rules_met']})")
            for name, p, band in bodies:
                t = time.perf_counter()
                d = run_case(p, band, hz, sets, cfg, ex)
                wall = time.perf_counter() - t
                rows.append(row_of(name, p, SITES[si].split(":")[0] + f"#{si}", d, wall))
                print(f"    {name} done in {wall:.1f} s", flush=True)
    finally:
        if ex is not None:
            ex.close()
    print()
    print_table(rows)
    print(f"total {time.perf_counter() - t0:.0f} s")
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            wr = csv.DictWriter(f, fieldnames=list(COLUMNS) + ["reason"])
            wr.writeheader()
            wr.writerows(rows)
        print(f"CSV: {a.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
