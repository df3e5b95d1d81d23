"""Command-line stages of the 2D dynamics: rock, spectrum, variability, sweep, identify, motion,
records (a spectrum-compatible set of accelerograms).

Each command reads a PARAMS.json written by ``statue2model props`` (or any JSON
holding m, h, b_L, b_R, I_G), builds one immutable RockingModel, runs one stage
and writes OUT (JSON), OUT-derived CSV and PNG files beside it.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..errors import InputError
from .argtypes import finite_float, plausible, positive_float, scale_ratio

SPEC_HELP = ("ground motion: free:theta0=RAD | cosine:amp=A,freq=HZ | sine:amp=A,freq=HZ | rect:amp=A,dur=S | "
             "sines:amp=A,freq=HZ,cycles=N | file:path=P[,dt=S][,pga=A][,scale=1:N][,units=g] | "
             "synthetic[:duration=S,dt=S,pga=A,seed=N] | bundled:name=elcentro_1940_ns[,pga=A][,scale=1:N]; A with a unit: 0.3g or 2.94m/s2 (a bare 0.3 is refused); "
             "amp > 0 accelerates the ground toward +x; add start=S to delay a pulse")


def _model_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("params", metavar="PARAMS.json", help="rocking parameters: the JSON written by `statue2model props`")
    g = p.add_argument_group("model")
    g.add_argument("--model", choices=["housner", "imperfect"], default=None,
                   help="classical (Housner) or imperfect asymmetric model (default: imperfect if any alpha is "
                        "given, else housner)")
    g.add_argument("--linearised", action="store_true", help="slender-block linearisation (sin x -> x, cos x -> 1)")
    g.add_argument("--alpha", type=finite_float, metavar="A", help="alpha_L = alpha_R = A (imperfect model), in (0, 1]")
    g.add_argument("--alpha-L", type=finite_float, metavar="A", help="reduction of the left uplift acceleration, in (0, 1]")
    g.add_argument("--alpha-R", type=finite_float, metavar="A", help="reduction of the right uplift acceleration, in (0, 1]")
    g.add_argument("--theta", type=finite_float, metavar="RAD", help="theta_L = theta_R (rolling transition, rad)")
    g.add_argument("--theta-L", type=finite_float, metavar="RAD", help="left rolling-transition rotation, rad "
                   "(default 0.07 delta_L)")
    g.add_argument("--theta-R", type=finite_float, metavar="RAD", help="right rolling-transition rotation, rad "
                   "(default 0.07 delta_R)")
    g.add_argument("--e", metavar="E", help="e_L = e_R = E")
    g.add_argument("--e-L", metavar="E", help="restitution landing on the left edge: a number in [0, 1] or the JSON "
                   "of `statue2model identify` (its fitted curve); default: angular momentum, eq. 15")
    g.add_argument("--e-R", metavar="E", help="restitution landing on the right edge (as --e-L)")
    g.add_argument("--mu-static", type=plausible("static_friction", option="--mu-static"), default=None, metavar="MU",
                   help="static friction coefficient of the base on its support (default 0.7, a typical value "
                        "for stone on stone): a body whose uplift needs more than MU g slides before it rocks, "
                        "and its rocking outcome above MU g is not applicable")
    g.add_argument("--rtol", type=positive_float, default=None, metavar="TOL", help="solver tolerance (default 1e-8 for "
                   "rock, 1e-7 for sweeps)")


def _executor_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("parallel runs (default: the threads of this process)")
    x = g.add_mutually_exclusive_group()
    x.add_argument("--workers", type=int, metavar="N", help="run on N local worker processes, one core each")
    x.add_argument("--scheduler", metavar="ADDRESS", help="run on the workers of a Dask cluster, e.g. "
                   "tcp://10.0.0.5:8786 (start `dask scheduler`, then `dask worker ADDRESS` on each machine)")


def _executor(args):
    """The executor asked for by --workers / --scheduler (a context manager that
    closes it), or a null context yielding None (this process's threads)."""
    import contextlib

    if args.workers is None and args.scheduler is None:
        return contextlib.nullcontext(None)
    from ..compute.executors import make_executor

    ex = make_executor(scheduler=args.scheduler, workers=args.workers, cap=True)
    print(f"running on {ex.describe()}")
    return ex


def _restitution(text: str | None, side: str):
    if text is None:
        return None
    try:
        return float(text)
    except ValueError:
        pass
    path = Path(text)
    if not path.is_file():
        raise InputError(f"--e-{side}: {text!r} is neither a number nor an existing identify JSON")
    from ..io.files import read_json

    data = read_json(path)
    if f"e_{side}" not in data:
        raise InputError(f"--e-{side}: {path} holds no e_{side} (is it the output of `statue2model identify`?)")
    return data[f"e_{side}"]


def _load_params(path: str):
    from ..io.files import read_json
    from ..geometry.rocking_params import RockingParams

    p = Path(path)
    if p.suffix.lower() != ".json":
        raise InputError(f"{path}: expected the JSON written by `statue2model props` (run props on the scan first)")
    data = read_json(p)
    if not isinstance(data, dict):
        raise InputError(f"{path}: not a JSON object of rocking parameters")
    return RockingParams.from_dict(data)


def build_model(args):
    from ..rocking.model import RockingModel

    params = _load_params(args.params)
    aL = args.alpha_L if args.alpha_L is not None else args.alpha
    aR = args.alpha_R if args.alpha_R is not None else args.alpha
    tL = args.theta_L if args.theta_L is not None else args.theta
    tR = args.theta_R if args.theta_R is not None else args.theta
    eL = _restitution(args.e_L if args.e_L is not None else args.e, "L")
    eR = _restitution(args.e_R if args.e_R is not None else args.e, "R")
    kind = args.model or ("imperfect" if (aL is not None or aR is not None) else "housner")
    if kind == "housner":
        if any(v is not None for v in (aL, aR, tL, tR)):
            raise InputError("--alpha/--theta options belong to --model imperfect")
        return RockingModel.housner(params, eL, eR, args.linearised, mu_static=args.mu_static)
    if aL is None or aR is None:
        raise InputError("--model imperfect needs --alpha-L and --alpha-R (or --alpha for both)")
    for name, v in (("--theta-L", tL), ("--theta-R", tR)):
        if v is not None and v <= 0:
            raise InputError(f"{name} must be > 0 rad, got {v}")
    return RockingModel.imperfect(params, aL, aR, tL, tR, eL, eR, args.linearised, mu_static=args.mu_static)


def _print_notes(model) -> None:
    """The model's notes (plastic impacts, sliding), one line each."""
    for note in model.notes:
        print(note if note.startswith("warning") else f"note: {note}")


def _out(args, default_name: str, *beside: str):
    """The output JSON (``--json``, default ``default_name`` beside PARAMS.json) and the
    :class:`~statue2model.io.files.OutputGroup` of it and the files ``beside`` it (suffixes:
    ".csv" replaces .json, "_history.csv" is appended to the stem), checked now, before any
    work: a file of those names statue2model did not write is refused, never overwritten;
    the files appear together or not at all."""
    from ..io.files import OutputGroup

    out = Path(args.json) if args.json else Path(args.params).resolve().parent / default_name
    if out.exists() and out.is_dir():
        raise InputError(f"--json {out} is a folder; give a file name")
    paths = [out] + [out.with_suffix(b) if b.startswith(".") else out.with_name(out.stem + b) for b in beside]
    return out, OutputGroup.files(paths, args.command)


def _motion(spec: str):
    from ..hazard.motions import parse_spec

    return parse_spec(spec)


# --- rock -------------------------------------------------------------------------------
ROCK_BYTES_PER_SAMPLE = 256
"""Bytes one history sample of ``rock`` costs: the arrays of the run (72), the CSV lines (about 150)
and the plot's copy."""


def cmd_rock(args) -> int:
    from ..rocking.engine import FREE_TIME, simulate
    from ..io.files import atomic_write, write_json
    from ..report.dynamics_plots import plot_time_history

    model = build_model(args)
    motion, theta0 = _motion(args.motion)
    if args.t_end is not None and args.t_end <= 0:
        raise InputError(f"--t-end must be positive, got {args.t_end}")
    from ..compute.budget import check_history

    # the history, its CSV text and its plot, before anything is allocated
    check_history(args.t_end if args.t_end is not None else motion.end + FREE_TIME, args.dt_out, ROCK_BYTES_PER_SAMPLE,
                  t_name="--t-end", dt_name="--dt-out")
    out, group = _out(args, "rock.json", "_history.csv", ".png")
    r = simulate(model, motion, theta0=theta0, t_end=args.t_end, rtol=args.rtol or 1e-8, dt_out=args.dt_out)
    p = model.params
    rows = [("model", f"{model.kind}{' (linearised)' if model.linearised else ''}"),
            ("motion", motion.label),
            ("uplift limits", f"+{model.uplift_limits[0] / p.g:.4f} g / -{model.uplift_limits[1] / p.g:.4f} g"),
            ("outcome", r.outcome),
            ("theta_max_L / delta_L", f"{r.theta_max_over_delta_L:.4f}  ({r.theta_max_L:.5g} rad)"),
            ("theta_max_R / delta_R", f"{r.theta_max_over_delta_R:.4f}  ({r.theta_max_R:.5g} rad)"),
            ("uplift time", "-" if r.uplift_time is None else f"{r.uplift_time:.4f} s"),
            ("impacts", str(r.n_impacts)),
            ("overturned", "no" if not r.overturned else
             f"yes, mode {r.overturn_mode}, at {r.overturn_time:.4f} s on the {r.overturn_side} pivot"),
            ("at rest from", "-" if r.t_rest is None else f"{r.t_rest:.4f} s")]
    w = max(len(a) for a, _ in rows)
    print("\n".join(f"{a:<{w}}  {b}" for a, b in rows))
    _print_notes(model)
    if not r.applicable:
        print(f"the rocking outcome is not applicable: the body slides before it rocks (peak ground acceleration "
              f"{max(abs(a) for a in motion.extremes()) / p.g:.3f} g > mu_s g = {model.mu_static:.3f} g); the rotations "
              f"above are those of a base that cannot slide")
    if model.energy_gain_possible:
        print("warning: e_side^2 I_new / I_old > 1 at some impact: impacts add energy with these e values")
    with group as g:
        write_json(g / out, r.to_dict())
        written = [out.name]
        if r.history is not None:
            csv = atomic_write(g / out.with_name(out.stem + "_history.csv"), lambda f: f.write_text(r.history_csv()))
            png = plot_time_history(r, g / out.with_suffix(".png"))
            written += [csv.name, png.name]
    print(f"\nwrote {', '.join(written)} in {out.parent}")
    return 0


# --- spectrum -----------------------------------------------------------------------------
def _grid(text: str, what: str, accel: bool = False):
    from ..rocking.sweeps import linspace_spec

    return linspace_spec(text, what, accel)


def cmd_spectrum(args) -> int:
    import time

    from ..rocking.spectrum import stability_spectrum
    from ..io.files import atomic_write, write_json
    from ..report.dynamics_plots import plot_spectrum, plot_spectrum_not_applicable

    model = build_model(args)
    freqs = _grid(args.freq, "--freq")
    amps = _grid(args.amp, "--amp", accel=True)
    out, group = _out(args, f"spectrum_{args.pulse}.json", ".csv", ".png")
    with _executor(args) as ex:
        t0 = time.perf_counter()
        sp = stability_spectrum(model, freqs, amps, pulse=args.pulse, rtol=args.rtol or 1e-7, progress=True,
                                executor=ex)
        wall = time.perf_counter() - t0
    for name, n in sp.counts().items():
        print(f"{name:<16} {n:>7}")
    print(f"{sp.codes.size} runs ({sp.n_integrated} integrated) in {wall:.2f} s")
    _print_notes(model)
    na = ~sp.applicable
    if na.any():
        print(f"{int(na.sum())} of {sp.codes.size} points are not applicable (the body slides before it rocks "
              f"above {model.mu_static:.3f} g); grey in the plot")
    d = sp.to_dict()
    d["wall_s"] = wall
    with group as g:
        write_json(g / out, d)
        csv = atomic_write(g / out.with_suffix(".csv"), lambda f: f.write_text(sp.to_csv()))
        if na.any():
            png = plot_spectrum_not_applicable(sp, g / out.with_suffix(".png"))
        else:
            png = plot_spectrum(sp, g / out.with_suffix(".png"))
    print(f"wrote {out.name}, {csv.name}, {png.name} in {out.parent}")
    return 0


# --- variability / sweep -----------------------------------------------------------------------
def _write_sweep(sw, out: Path, group) -> None:
    from ..io.files import atomic_write, write_json
    from ..report.dynamics_plots import plot_sweep

    s = sw.summary()
    _print_notes(sw.model)
    if s["n_not_applicable"]:
        print(f"{s['n_not_applicable']} of {sw.values.size} runs are not applicable (the body slides before it "
              f"rocks): left out of the statistics and the plot")
    if s["n"]:
        print(f"{s['n']} runs: |theta|max/delta mean {s['mean']:.4f}, std {s['std']:.4f}, p05 {s['p05']:.4f}, "
              f"p50 {s['p50']:.4f}, p95 {s['p95']:.4f}, max {s['max']:.4f}; {s['n_overturned']} overturned")
    with group as g:
        write_json(g / out, sw.to_dict())
        csv = atomic_write(g / out.with_suffix(".csv"), lambda f: f.write_text(sw.to_csv()))
        names = [out.name, csv.name]
        if s["n"]:
            names.append(plot_sweep(sw.applicable_only() if s["n_not_applicable"] else sw,
                                    g / out.with_suffix(".png")).name)
        else:
            print("no run is applicable: no plot")
    print(f"wrote {', '.join(names)} in {out.parent}")


def cmd_variability(args) -> int:
    from ..rocking.sweeps import variability

    model = build_model(args)
    motion, theta0 = _motion(args.motion)
    if theta0 != 0 or motion.kind == "none":
        raise InputError("variability needs a ground motion (a record or a pulse), not free rocking")
    pgas = _grid(args.pga, "--pga", accel=True)
    out, group = _out(args, "variability.json", ".csv", ".png")
    with _executor(args) as ex:
        sw = variability(model, motion, pgas, rtol=args.rtol or 1e-7, progress=True, executor=ex)
    _write_sweep(sw, out, group)
    return 0


def cmd_sweep(args) -> int:
    from ..rocking.sweeps import linspace_spec, parameter_sweep

    model = build_model(args)
    motion, theta0 = _motion(args.motion)
    if theta0 != 0:
        raise InputError("sweep needs a ground motion, not free rocking")
    values = linspace_spec(args.values, "--values")
    if args.over_delta:
        if not args.param.startswith("theta"):
            raise InputError("--over-delta applies to theta_L, theta_R or theta")
        side = args.param[-1] if args.param != "theta" else "R"
        values = values * (model.params.delta_L if side == "L" else model.params.delta_R)
    out, group = _out(args, f"sweep_{args.param}.json", ".csv", ".png")
    with _executor(args) as ex:
        sw = parameter_sweep(model, motion, args.param, values, rtol=args.rtol or 1e-7, progress=True, executor=ex)
    _write_sweep(sw, out, group)
    return 0


# --- identify ---------------------------------------------------------------------------------
def cmd_identify(args) -> int:
    from ..rocking.identify import identify_restitution, read_rotation_record
    from ..io.files import atomic_write, write_json
    from ..report.dynamics_plots import plot_identification

    params = _load_params(args.params)
    out, group = _out(args, "identify.json", ".csv", ".png")
    t, theta = read_rotation_record(args.record, units=args.units)
    ident = identify_restitution(t, theta, params)
    print(f"{'i':>3} {'t [s]':>8} {'|theta_dot| [rad/s]':>20} {'e':>8} side")
    for i, (ti, w, e, s) in enumerate(zip(ident.t_impact, ident.speed, ident.e, ident.side)):
        print(f"{i:>3} {ti:>8.3f} {w:>20.4f} {e:>8.4f} {s}")
    for side in ("L", "R"):
        f = ident.fit[side]
        print(f"e_{side} = {f['c0']:.4f} {f['c1']:+.4f} |theta_dot|  ({f['n']} impacts, rms {f['rms_residual']:.2g})")
    with group as g:
        write_json(g / out, ident.to_dict())
        csv = atomic_write(g / out.with_suffix(".csv"), lambda f: f.write_text(ident.to_csv()))
        png = plot_identification(ident, g / out.with_suffix(".png"))
    print(f"wrote {out.name}, {csv.name}, {png.name} in {out.parent}  (use it as --e-L {out} --e-R {out})")
    return 0


# --- motion -----------------------------------------------------------------------------------
def cmd_motion(args) -> int:
    from ..hazard.motions import table_displacement
    from ..io.files import OutputGroup, atomic_write
    from ..report.dynamics_plots import plot_table_motion

    motion, theta0 = _motion(args.motion)
    if motion.kind == "none":
        raise InputError("free rocking has no ground motion to write")
    out = Path(args.csv) if args.csv else Path("outputs") / "motion" / "table.csv"
    if out.exists() and out.is_dir():
        raise InputError(f"--csv {out} is a folder; give a file name")
    group = OutputGroup.files([out, out.with_suffix(".png")], "motion")
    t, a, v, u = table_displacement(motion, args.dt)
    text = "t_s,acc_m_s2,vel_m_s,disp_m\n" + "".join(f"{a_:.9g},{b:.9g},{c:.9g},{d:.9g}\n"
                                                       for a_, b, c, d in zip(t, a, v, u))
    with group as g:
        atomic_write(g / out, lambda f: f.write_text(text))
        png = plot_table_motion(t, a, v, u, motion.label, g / out.with_suffix(".png"))
    print(f"{motion.label}: {t.size} samples, dt {t[1] - t[0]:.4g} s, PGA {motion.pga:.4g} m/s^2, "
          f"peak table displacement {abs(u).max() * 1000:.2f} mm, stroke {(u.max() - u.min()) * 1000:.2f} mm")
    print(f"wrote {out} and {png.name}")
    return 0


# --- records ----------------------------------------------------------------------------------
def _band(text: str) -> tuple[float, float]:
    parts = str(text).split(":")
    try:
        lo, hi = (float(x) for x in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a period band T0:T1 in s: {text!r} (e.g. 0.1:4)") from None
    return lo, hi


def _tolerance(text: str) -> tuple:
    """BELOW (artificial records: no upper bound) or BELOW:ABOVE (recorded motions), percent."""
    parts = str(text).split(":")
    try:
        vals = [float(x) / 100.0 for x in parts]
    except ValueError:
        vals = []
    if len(vals) not in (1, 2) or not all(math.isfinite(v) for v in vals):
        raise argparse.ArgumentTypeError(f"not a tolerance BELOW or BELOW:ABOVE in percent: {text!r} (e.g. 10 for "
                                         "artificial records, 10:30 for recorded ones)")
    return -abs(vals[0]), (vals[1] if len(vals) == 2 else None)


def cmd_records(args) -> int:
    from ..hazard.code_spectra import parse_spectrum
    from ..hazard.floor import parse_floor
    from ..hazard.matching import design_band, duration_for_band
    from ..io.files import open_output

    target = ground = parse_spectrum(args.spectrum)
    if args.floor:
        target = parse_floor(args.floor, ground)
    required, why = design_band(args.t1, args.t_is, ground.code)
    band = args.band if args.band is not None else required
    if args.duration is None:
        args.duration = duration_for_band(band)
    args.required_band, args.band_reason = required, why
    # the folder is checked (and locked) before any work: a user's files in it refuse it at once
    with open_output(args.out, "records", command="records", can_reuse=False) as od:
        return _records(args, od, target, band)


def _records(args, od, target, band) -> int:
    import json
    import re
    import time

    from ..hazard.matching import match_set, set_files
    from ..hazard.motions import write_record_csv
    from ..io.files import write_json
    from ..report.hazard_plots import plot_spectra

    t0 = time.perf_counter()
    matcher = match_set
    if args.method == "wavelet":
        from ..hazard.wavelet_matching import match_set_wavelet as matcher
    rs = matcher(target, n=args.n, seed=args.seed, duration=args.duration, dt=args.dt, band=band,
                   tolerance=args.tolerance, required_band=args.required_band, band_reason=args.band_reason)
    seconds = time.perf_counter() - t0
    c = rs.check()
    line = (f"{len(rs.records)} records of {args.duration:g} s, seeds {rs.seeds[0]}..{rs.seeds[-1]}, "
            f"{rs.iterations} iterations, {seconds:.1f} s: mean/target over {c['band_s'][0]:g}-{c['band_s'][1]:.4g} s "
            f"from {c['min_ratio']:.3f} (at {c['period_of_min_s']:.3g} s) to {c['max_ratio']:.3f} (at "
            f"{c['period_of_max_s']:.3g} s); {rs.window}")
    if not c["fit_met"] and not args.keep_unmet:
        raise InputError(f"the set misses its tolerance ({line}); try more records, another --seed or a longer "
                         f"--duration, or pass --keep-unmet to write it anyway")
    lam = args.scale
    names = [f"record_{i + 1:02d}.csv" for i in range(len(rs.records))]
    # the set replaces the folder's earlier one: its records this one does not have go too
    stale = [n for n in od.entries if re.fullmatch(r"record_\d+\.csv", n) and n not in names]
    # all or nothing: the records, set.json (naming them, with their lengths and hashes) and the
    # plot appear together once every one is complete; an interruption leaves the earlier set as it was
    with od.group([*names, "set.json", "spectra.png", *stale]) as g:
        for name, m in zip(names, rs.records):
            write_record_csv(g / name, m.froude(lam) if lam != 1.0 else m)
        data = rs.to_dict()
        data.update(spectrum=args.spectrum, floor=args.floor, duration_s=args.duration, dt_s=args.dt,
                    froude_scale=(f"1:{lam:g}" if lam != 1.0 else None),
                    files_dt_s=args.dt / lam ** 0.5,
                    note=("spectra and check at full scale; the files are Froude-scaled (times / sqrt(lambda), "
                          "accelerations unchanged)" if lam != 1.0 else "full scale"))
        data.update(set_files(g.tmp, names, "m/s2"))
        write_json(g / "set.json", json.loads(json.dumps(data)))
        plot_spectra(rs, g / "spectra.png", title=args.floor and "floor spectrum" or "ground spectrum")
    print(line)
    for r in rs.rules():
        print(f"  {'ok  ' if r['ok'] else 'FAIL'} {r['rule']}: {r['value']} (required {r['required']}; {r['clause']})")
    real = rs.realism()
    if real["d_g_m"]:
        print(f"  PGD {real['mean_pgd_m']:.3f} m mean, {real['max_pgd_m']:.3f} m max = {real['mean_pgd_over_d_g']:.2f} "
              f"x d_g {real['d_g_m']:.3f} m; PGV {real['mean_pgv_m_s']:.3f} m/s mean")
    if not c["fit_met"]:
        print(f"WARNING: the set does NOT meet its tolerance (worst mean/target {c['worst_ratio']:.3f} at "
              f"{c['period_of_worst_s']:.3g} s); set.json says met: false")
    elif not c["met"]:
        print("WARNING: the set breaks the code's rules marked FAIL above; set.json says met: false")
    if real["warning"]:
        print(f"WARNING: {real['warning']}")
    print(f"wrote {len(rs.records)} records, set.json and spectra.png to {od.path}")
    return 0


def add_parsers(sub) -> None:
    p = sub.add_parser("rock", help="one time history of the 2D rocking model",
                       description="Simulate the rocking model under a ground motion; print the response and write "
                                   "OUT (JSON), OUT_history.csv and OUT.png.")
    _model_options(p)
    p.add_argument("--motion", required=True, metavar="SPEC", help=SPEC_HELP)
    p.add_argument("--t-end", type=finite_float, metavar="S", help="end time (default: motion end + 20 s; the run stops at "
                   "overturning or rest)")
    p.add_argument("--dt-out", type=positive_float, default=0.002, metavar="S", help="history sampling step (default 2 ms)")
    p.add_argument("--json", metavar="OUT", help="output JSON (default: rock.json beside PARAMS.json)")
    p.set_defaults(func=cmd_rock)

    p = sub.add_parser("spectrum", help="stability spectrum of a pulse over (frequency, amplitude)",
                       description="Outcome (no motion, rolling, rocking, overturn mode 1/2/3) of a one-cosine or "
                                   "one-sine pulse over a grid; writes OUT, OUT.csv and OUT.png.")
    _model_options(p)
    p.add_argument("--pulse", choices=["cosine", "sine"], default="cosine")
    p.add_argument("--freq", default="0.5:10:100", metavar="F0:F1:N", help="frequencies in Hz (default 0.5:10:100)")
    p.add_argument("--amp", default="0.01g:1.5g:100", metavar="A0:A1:N",
                   help="amplitudes with a unit, g or m/s2 (default 0.01g:1.5g:100)")
    p.add_argument("--json", metavar="OUT", help="output JSON (default: spectrum_<pulse>.json beside PARAMS.json)")
    _executor_options(p)
    p.set_defaults(func=cmd_spectrum)

    p = sub.add_parser("variability", help="maximum rotation of a record scaled over a PGA range",
                       description="|theta|max/delta of one ground motion scaled to each PGA (thesis Fig. 70-75).")
    _model_options(p)
    p.add_argument("--motion", required=True, metavar="SPEC", help=SPEC_HELP)
    p.add_argument("--pga", default="0.02g:1g:50", metavar="P0:P1:N", help="PGA values (default 0.02g:1g:50)")
    p.add_argument("--json", metavar="OUT", help="output JSON (default: variability.json beside PARAMS.json)")
    _executor_options(p)
    p.set_defaults(func=cmd_variability)

    p = sub.add_parser("sweep", help="uncertainty sweep of one model parameter",
                       description="Run one motion for many values of a parameter and report the distribution of "
                                   "the peak response (e.g. 49 values of theta_R, thesis Table 24).")
    _model_options(p)
    p.add_argument("--motion", required=True, metavar="SPEC", help=SPEC_HELP)
    p.add_argument("--param", required=True, choices=["alpha_L", "alpha_R", "alpha", "theta_L", "theta_R", "theta",
                                                      "e_L", "e_R", "e"])
    p.add_argument("--values", required=True, metavar="V0:V1:N", help="values (START:STOP:N or a comma list)")
    p.add_argument("--over-delta", action="store_true", help="theta values are fractions of delta of that side")
    p.add_argument("--json", metavar="OUT", help="output JSON (default: sweep_<param>.json beside PARAMS.json)")
    _executor_options(p)
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("identify", help="e_L, e_R from a free-rocking record (eq. 43)",
                       description="Coefficients of restitution per impact and fitted e(|theta'|) curves from a "
                                   "measured free-rocking record (CSV: time s, rotation; theta > 0 on the right pivot).")
    p.add_argument("params", metavar="PARAMS.json", help="rocking parameters (JSON of `statue2model props`)")
    p.add_argument("record", metavar="RECORD.csv", help="two columns: time (s), rotation")
    p.add_argument("--units", choices=["rad", "deg"], default="rad", help="rotation unit of the record")
    p.add_argument("--json", metavar="OUT", help="output JSON (default: identify.json beside PARAMS.json)")
    p.set_defaults(func=cmd_identify)

    p = sub.add_parser("motion", help="shake-table input: baseline-corrected displacement of a motion",
                       description="Write t, acc, vel, disp (baseline-corrected double integration) of a ground "
                                   "motion for a shake table, with a plot.")
    p.add_argument("motion", metavar="SPEC", help=SPEC_HELP)
    p.add_argument("--dt", type=positive_float, metavar="S", help="sampling step (default: the record's, or 1 ms)")
    p.add_argument("--csv", metavar="OUT", help="output CSV (default: outputs/motion/table.csv)")
    p.set_defaults(func=cmd_motion)

    p = sub.add_parser("records", help="a spectrum-compatible set of artificial accelerograms",
                       description="N artificial records matched to a code spectrum (EC8 / NTC 2018) or to the "
                                   "floor spectrum of a storey, to the codes' rules (NTC 2018 3.2.3.6, EC8 3.2.3.1.2): "
                                   "7 records of at least 25 s with a 10 s stationary part, the mean spectrum not more "
                                   "than 10 %% below the target from 0.15 s to the largest of 2 s, 2 T1 and 1.2 T_is, "
                                   "the mean PGA not below Se(0); each rule and each record's PGA, PGV, PGD, Arias "
                                   "intensity and D5-95 in set.json. Writes record_01.csv ... (readable as "
                                   "file:path=...), set.json and spectra.png.")
    p.add_argument("--spectrum", required=True, metavar="SPEC",
                   help="ground spectrum: ec8:ag=A[,ground=A-E,type=1|2,xi=5] | ntc2018:ag=A,F0=F,Tc=S[,soil=A-E,"
                        "topo=T1-T4,xi=5,ls=SLO|SLD|SLV|SLC|SLA] (the limit state's a_g, F0, Tc* of the site)")
    p.add_argument("--floor", metavar="z=Z,H=H,T1=S,n=N[,structure=S][,xi=5][,code=C]",
                   help="match the floor spectrum at height z of a building of height H (storeys or m), period "
                        "T1 and n storeys instead; structure masonry|concrete-frame|steel-frame|other, xi its "
                        "damping in percent, code ec8 (EN 1998-1 eq. 4.25) | ntc2018 (Circolare C7.2.5-10, the "
                        "default on an NTC spectrum) | ntc2018-framed (C7.2.11, frames only)")
    p.add_argument("--n", type=int, default=7, help="number of records (default 7)")
    p.add_argument("--seed", type=int, default=1, help="seed of the first record; record i uses seed + i (default 1)")
    p.add_argument("--duration", type=positive_float, metavar="S",
                   help="record length (default: 25 s, or 5 times the band's end if longer)")
    p.add_argument("--dt", type=positive_float, default=0.01, metavar="S", help="time step (default 0.01 s)")
    p.add_argument("--t1", type=positive_float, metavar="S",
                   help="the building's fundamental period: the band reaches 2 T1 (NTC 2018 3.2.3.6)")
    p.add_argument("--t-is", type=positive_float, metavar="S",
                   help="the isolator's period: the band reaches 1.2 T_is (NTC 2018 3.2.3.6)")
    p.add_argument("--band", type=_band, metavar="T0:T1",
                   help="periods of the tolerance check (default 0.15 s to max(2 s, 2 T1, 1.2 T_is)); a band "
                        "narrower than the code's is checked and reported as a failed rule")
    p.add_argument("--tolerance", type=_tolerance, default=(-0.10, None), metavar="BELOW[:ABOVE]",
                   help="how far the mean spectrum may fall below (and rise above) the target, percent (default 10: "
                        "artificial records, no upper bound; 10:30 is NTC's window for recorded motions)")
    p.add_argument("--scale", type=scale_ratio, default=1.0, metavar="1:N",
                   help="write the records Froude-scaled for a 1:N prototype (times / sqrt(N))")
    p.add_argument("--method", choices=["fourier", "wavelet"], default="fourier",
                   help="fourier: SIMQKE Fourier-amplitude correction (default, core); wavelet: reqpy's CWT "
                        "matching (the [records] extra; about 45 x slower, lower PGD: docs/records.md)")
    p.add_argument("--keep-unmet", action="store_true",
                   help="write a set that misses its tolerance (with a warning and met: false) instead of refusing")
    p.add_argument("--out", default=str(Path("outputs") / "records"), metavar="DIR",
                   help="output folder (default outputs/records)")
    p.set_defaults(func=cmd_records)
