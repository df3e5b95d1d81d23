"""One command from scan to report: run the stages in order, cached, with progress.

    OUT/config.toml        the resolved configuration (every key; repeat the run with it)
    OUT/params/ OUT/prototype/ OUT/isolator/ OUT/dynamics/ OUT/crosscheck/
                           one folder per stage, each with its manifest stage.json
    OUT/run.json           the verdict (hazard, fixed base, isolator, recommendation: assessment/verdict.py),
                           stages (status, seconds, cached, key, warnings) and their headline numbers;
                           ``warnings``: every stage's warnings, [{stage, text}]
    OUT/report.html        the self-contained report
    OUT/.statue2model.json what statue2model wrote in OUT (files.open_output): only these names are
                           ever replaced; a folder with other files is refused unless ``reuse``
    OUT/.statue2model.lock one run per folder at a time (PID, host, start time); released at the end

A stage whose inputs (scan bytes, the configuration sections it reads, the stages
it reads, the package's code) did not change is taken from its folder; ``force``
recomputes. Stages not asked for are taken from their folders when complete, and
computed when a stage that was asked for needs them. A stage's warnings (its
manifest's ``warnings``) are printed after its line, also when it is taken from the
cache: they still apply.

A folder of scans (:func:`run_collection`) runs each scan as one task of an
executor: local processes, or a Dask cluster; the numbers do not depend on which.

Example
-------
>>> import tempfile, pathlib
>>> from statue2model.io.paths import default_scan
>>> out = pathlib.Path(tempfile.mkdtemp()) / "girl"
>>> res = run_project(default_scan(), out, stages=["params"], report=False, say=lambda m: None)
>>> res.stages["params"]["status"], round(res.stages["params"]["data"]["a_R"], 4)
('done', 2.717)
>>> run_project(default_scan(), out, stages=["params"], report=False, say=lambda m: None).stages["params"]["status"]
'cached'
"""
from __future__ import annotations

import errno
import time
from dataclasses import dataclass, field
from pathlib import Path

from ..version import __version__
from ..quantities import G
from ..io.csvsafe import write_csv
from ..errors import InputError, OutputError, quoted
from ..io.files import LOCK_NAME, MANIFEST_NAME, atomic_write, open_output, output_error, write_json
from ..io.inputs import check_input
from .cache import MANIFEST, completed, file_hash, run_stage, stage_key
from .config import ProjectConfig, check_stage_names, motion_files, stage_list
from .stages import DEPENDS, STAGES, Context, enabled
from .rooms import PLACEMENT_COLUMNS, check_scans, config_for, object_placement, where_text
from ..assessment.collection import RANKING_RULE, csv_rows, object_row, rank
from ..assessment.collection import summary as collection_summary
from ..report.collection_page import write_collection_page
from .assess import assess
from ..geometry.scan import SCAN_SUFFIXES


@dataclass(frozen=True)
class RunResult:
    """``stages``: name -> manifest with ``status`` (done, cached, skipped, disabled,
    failed) and ``seconds``; ``report``: path of report.html (or None)."""

    mesh: Path
    out: Path
    config: ProjectConfig
    stages: dict = field(default_factory=dict)
    report: Path | None = None
    seconds: float = 0.0
    verdict: dict | None = None

    @property
    def warnings(self) -> list[dict]:
        """Every stage's warnings, in pipeline order: [{"stage": name, "text": warning}]."""
        return stage_warnings(self.stages)

    def summary_rows(self) -> list[tuple[str, str, str]]:
        rows = []
        for name, m in self.stages.items():
            t = m.get("seconds")
            rows.append((name, m["status"], "" if t is None else f"{t:.1f} s"))
        return rows


def stage_warnings(stages: dict) -> list[dict]:
    """[{"stage", "text"}] of the manifests ``stages`` (name -> manifest), in their order."""
    return [{"stage": name, "text": str(w)} for name, m in stages.items() for w in m.get("warnings", ()) or ()]


def warnings_line(n: int) -> str:
    """The count line of a run's summary, e.g. "3 warnings: see above / run.json"."""
    return f"{n} warning{'s' if n != 1 else ''}: see above / run.json"


def _say_warnings(say, man: dict, prefix: str = "") -> None:
    for w in man.get("warnings", ()) or ():
        say(f"        warning{prefix}: {w}")


def _needed(asked: list[str], cfg: ProjectConfig) -> list[str]:
    """The stages to run for ``asked``: those and what they read, in pipeline order."""
    need = set()

    def add(n):
        if n in need:
            return
        need.add(n)
        required, optional, _ = DEPENDS[n]
        for dep in (*required, *(d for d in optional if enabled(d, cfg))):
            add(dep)

    for n in asked:
        add(n)
    return [n for n in STAGES if n in need]


def run_project(mesh: str | Path, out: str | Path, config: ProjectConfig | None = None, *,
                stages: list[str] | None = None, force: bool = False, executor=None, report: bool = True,
                say=print, reuse: bool = False) -> RunResult:
    """Run ``stages`` (default: ``[run] stages`` of the configuration, less those
    switched off) on ``mesh`` into folder ``out``: new, empty
    or a previous run's (its manifest .statue2model.json); ``reuse``: a folder holding
    other files too, which are never touched (see files.open_output). One run per folder
    at a time (a lock)."""
    cfg = ProjectConfig() if config is None else config
    mesh = check_input(mesh, "scan")           # a regular file: not a dangling link, a loop, a FIFO
    cfg = config_for(cfg, mesh.name)            # [objects]: this scan's room (single scans and collections)
    asked = check_stage_names(stages) if stages else [n for n in stage_list(cfg.run.stages) if enabled(n, cfg)]
    off = [n for n in asked if not enabled(n, cfg)]
    if off and stages:
        raise InputError(f"stage(s) {', '.join(off)} asked for but disabled in the configuration "
                         f"({', '.join(f'[{n}] enabled = false' for n in off)})")
    order = _needed(asked, cfg)
    with open_output(out, "run", reuse=reuse, command="run", adopt=older_run) as od:
        return _run_stages(mesh, Path(out), od, cfg, order, force=force, executor=executor, report=report, say=say)


RUN_FILES = ("config.toml", "run.json", "report.html")
NOT_ASKED = {"crosscheck": "Not asked for in this run: the 3D cross-check (PyBullet, the [physics] extra) runs "
                           "with --stages all (or crosscheck), or [run] stages = \"all\" in the project file."}


def older_run(folder: Path) -> list[str]:
    """The names of a run made before output manifests (stage folders with their
    stage.json, run.json, config.toml and report.html written by statue2model)."""
    import json

    def head(p: Path, n: int = 65536) -> str:
        try:
            with open(p, encoding="utf-8", errors="replace") as f:
                return f.read(n)
        except OSError:
            return ""

    names = []
    for n in STAGES:
        try:
            m = json.loads((folder / n / MANIFEST).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if isinstance(m, dict) and m.get("stage") == n and isinstance(m.get("key"), str):
            names.append(n)
    try:
        run = json.loads((folder / "run.json").read_text(encoding="utf-8"))
        if isinstance(run, dict) and str(run.get("schema", "")).startswith("statue2model.run/"):
            names.append("run.json")
    except (OSError, ValueError):
        pass
    if not names:
        return []
    if head(folder / "config.toml", 200).startswith("# statue2model"):
        names.append("config.toml")
    if "statue2model" in head(folder / "report.html"):
        names.append("report.html")
    return names


def _run_stages(mesh: Path, out: Path, od, cfg: ProjectConfig, order: list[str], *, force, executor, report,
                say) -> RunResult:
    """The stages ``order`` into the opened (locked) output folder ``od`` (path ``out``)."""
    od.clean()
    od.claim([*order, *RUN_FILES])         # before writing: a clash with a user's file refuses here
    for stale in RUN_FILES:                 # written again at the end, together
        od.remove(stale)
    mesh_hash = file_hash(mesh)
    t_run = time.perf_counter()
    keys, dirs, manifests, results = {}, {}, {}, {}
    bodies: dict = {}                          # the run's Body, built once and shared by its stages
    record_sets: dict = {}                     # the run's design record set, matched once for its stages
    n = len(order)
    for name in STAGES:
        required, optional, sections = DEPENDS[name]
        if not enabled(name, cfg):
            results[name] = {"status": "disabled", "summary": {}, "text": [f"[{name}] enabled = false"]}
            continue
        missing = [dep for dep in required if dep not in keys]
        if missing:
            results[name] = {"status": "not run", "summary": {}}
            continue
        inputs = {"mesh": mesh_hash, "config": {s: cfg.section(s) for s in sections},
                  "files": motion_files(cfg, sections),
                  "upstream": {dep: keys.get(dep) for dep in (*required, *optional)}}
        key = stage_key(name, inputs)
        if name not in order:           # not asked for: taken from its folder when complete
            man = completed(out / name, key) if od.owns(name) else None
            if man is not None:
                keys[name], dirs[name], manifests[name] = key, out / name, man
                results[name] = {**_shown(man), "status": "cached"}
                _say_warnings(say, man, f" ({name}, taken from an earlier run)")
            else:
                results[name] = {"status": "not run", "summary": {}, "text": [NOT_ASKED.get(
                    name, f"Not asked for in this run: add it with --stages {name} or [run] stages.")]}
            continue
        i = order.index(name) + 1
        ctx = Context(mesh=mesh, config=cfg, executor=executor, dirs=dict(dirs), manifests=dict(manifests),
                      say=lambda msg: say(f"        {msg}"), bodies=bodies, mesh_sha256=mesh_hash,
                      record_sets=record_sets)
        say(f"[{i}/{n}] {name:<10} ...")
        t0 = time.perf_counter()
        man = run_stage(out / name, key, lambda d, f=STAGES[name], c=ctx: f(c, d), force=force)
        status = "cached" if man["cached"] else "done"
        say(f"[{i}/{n}] {name:<10} {status} in {time.perf_counter() - t0:.1f} s"
            + (f" (computed in {man['seconds']:.1f} s earlier)" if man["cached"] else ""))
        for k, v in man.get("summary", {}).items():
            say(f"        {k}: {v}")
        _say_warnings(say, man)
        keys[name], dirs[name], manifests[name] = key, out / name, man
        results[name] = {**_shown(man), "status": status}
    write_config(cfg, out / "config.toml", mesh, out)
    verdict = assess(results, dirs, cfg)
    res = RunResult(mesh=mesh, out=out, config=cfg, stages=results, seconds=time.perf_counter() - t_run,
                    verdict=verdict)
    write_json(out / "run.json", {"schema": "statue2model.run/1", "version": __version__, "mesh": str(mesh),
                                  "mesh_sha256": mesh_hash, "seconds": res.seconds, "verdict": verdict,
                                  "stages": results, "warnings": res.warnings})
    if report:
        from ..report.page import write_html

        res = RunResult(mesh=mesh, out=out, config=cfg, stages=results, seconds=res.seconds,
                        report=write_html(res), verdict=verdict)
    return res


def _shown(man: dict) -> dict:
    """A stage manifest for run.json and the report: without its list of file hashes
    (``files``: the cache's check, kept in the stage's own stage.json)."""
    return {k: v for k, v in man.items() if k != "files"}


def write_config(cfg: ProjectConfig, path: Path, mesh: Path | None = None, out: Path | None = None) -> Path:
    """The resolved configuration, with the command that repeats the run (absolute paths,
    shell-quoted: a newline or control character in a path cannot end the comment line)."""
    again = (f"statue2model run {shell_arg(Path(mesh).resolve()) if mesh else 'MESH'} "
             f"--config {shell_arg(Path(path).resolve())}"
             + (f" --out {shell_arg(Path(out).resolve())}" if out else ""))
    head = (f"# statue2model {__version__}: the resolved configuration of this run.\n"
            f"# Repeat it with: {again}\n\n")
    return atomic_write(path, lambda p: p.write_text(head + cfg.to_toml(), encoding="utf-8"))


def shell_arg(value) -> str:
    """``value`` as one POSIX shell word on one line: ``shlex.quote`` when every character
    is printable, else bash's ``$'...'`` with escapes (newlines, CR, control characters).

    >>> shell_arg("/tmp/a b"), shell_arg("/tmp/x\\n[run] workers = 3")
    ("'/tmp/a b'", "$'/tmp/x\\\\n[run] workers = 3'")
    """
    import shlex

    text = str(value)
    if text.isprintable():
        return shlex.quote(text)
    named = {"\n": "\\n", "\r": "\\r", "\t": "\\t", "\\": "\\\\", "'": "\\'"}
    body = "".join(named.get(c) or (c if c.isprintable() else
                                    f"\\x{ord(c):02x}" if ord(c) < 0x100 else
                                    f"\\u{ord(c):04x}" if ord(c) < 0x10000 else f"\\U{ord(c):08x}")
                   for c in text)
    return f"$'{body}'"


# --- a folder of scans ----------------------------------------------------------------------------
def scans_in(folder: str | Path) -> list[Path]:
    """The scans in a folder (by suffix), sorted by name; an error if there is none. Every
    entry with a scan's suffix that is not a folder counts: one that cannot be read (a
    dangling symbolic link, a link loop, a FIFO) is then refused with its reason, a row of
    the collection as any unreadable scan, never left out unsaid."""
    folder = Path(folder)
    scans = sorted(p for p in folder.iterdir() if p.suffix.lower() in SCAN_SUFFIXES and not p.is_dir())
    if not scans:
        raise InputError(f"no scans ({', '.join(SCAN_SUFFIXES)}) in folder {folder}")
    return scans


COLLECTION_FILES = ("config.toml", "collection.json", "collection.csv", "collection.html")
"""What a collection writes beside its objects' folders."""
_RESERVED = frozenset(n.casefold() for n in (*COLLECTION_FILES, *RUN_FILES, "run.json", MANIFEST_NAME, LOCK_NAME))


def object_folders(scans) -> list[str]:
    """The output folder name of each scan of a collection (file names or paths), in their order:
    the scan's name without its suffix (``girl.ply`` -> ``girl``) when that name is the scan's
    alone, else its whole file name (``a.stl`` and ``a.ply`` -> ``a.stl``, ``a.ply``;
    ``collection.html.stl`` -> ``collection.html.stl``). Never one of the collection's own files
    (collection.html, config.toml, ...: none ends with a scan's suffix) and never another scan's
    folder, also where names differ only in case: a stem is used only when no other scan's stem
    equals it in any case, it is not a name of the run's own, and it does not itself end with a
    scan's suffix (which only whole file names do). A function of the folder's scan names alone,
    so a resumed collection finds its objects' folders again.

    >>> object_folders(["girl.ply", "a.stl", "a.ply", "collection.html.stl", "b.stl.stl", "B.stl"])
    ['girl', 'a.stl', 'a.ply', 'collection.html.stl', 'b.stl.stl', 'B']
    """
    names = [Path(s).name for s in scans]
    stems = [Path(n).stem for n in names]
    count: dict[str, int] = {}
    for st in stems:
        count[st.casefold()] = count.get(st.casefold(), 0) + 1
    out = []
    for name, st in zip(names, stems):
        key = st.casefold()
        own = count[key] == 1 and key not in _RESERVED and not key.endswith(SCAN_SUFFIXES)
        out.append(st if own else name)
    folded = [n.casefold() for n in out]
    clash = sorted({n for n, f in zip(out, folded) if folded.count(f) > 1})
    if clash:                # whole file names that differ only in case: one folder on some file systems
        raise InputError(f"scans {', '.join(quoted(n) for n in clash)} differ only in case: their output "
                         "folders would be one on a case-insensitive file system; rename one")
    return out


WRITE_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS})
"""errno of an ``OSError`` that is a failure to write (disk full, quota, file too large, read-only
file system), whoever raised it: the run's, never one scan's (a library writing directly)."""


def _scan_task(task) -> dict:
    """One scan of a collection (module level: runs in worker processes or on Dask workers). Its
    own errors (a bad scan, a bug) are its row's; an output that cannot be written (disk full,
    quota, read-only: :class:`~statue2model.errors.OutputError`) ends the whole run, exit 3: the
    next scan would fail the same way, and the scan is not to blame."""
    mesh, out, cfg, stages, force, *rest = task
    try:
        res = run_project(mesh, out, cfg, stages=stages, force=force, executor=None, report=True,
                          say=lambda m: None, reuse=bool(rest and rest[0]))
    except OutputError:
        raise
    except OSError as exc:
        if exc.errno in WRITE_ERRNOS:
            raise output_error(exc, exc.filename if exc.filename is not None else out) from None
        return {"scan": Path(mesh).name, "folder": Path(out).name,
                "error": f"internal error ({type(exc).__name__}: {exc})", "internal": True}
    except InputError as exc:
        return {"scan": Path(mesh).name, "folder": Path(out).name, "error": str(exc)}
    except Exception as exc:        # one object's internal error must not cost the others their assessment
        return {"scan": Path(mesh).name, "folder": Path(out).name,
                "error": f"internal error ({type(exc).__name__}: {exc})", "internal": True}
    return {"scan": Path(mesh).name, "folder": Path(out).name, "out": str(res.out), "report": str(res.report) if res.report else None,
            "status": {k: v["status"] for k, v in res.stages.items()}, "warnings": res.warnings,
            "data": {k: v.get("data", {}) for k, v in res.stages.items()}, "verdict": res.verdict}


COLLECTION_COLUMNS = (("params", "m", "mass [kg]", 1.0), ("params", "h", "h [m]", 1.0),
                      ("params", "b_L", "b_L [m]", 1.0), ("params", "b_R", "b_R [m]", 1.0),
                      ("params", "a_min", "weakest uplift [g]", 1 / G),
                      ("params", "weakest_deg", "weakest direction [deg]", 1.0),
                      ("dynamics", "spectrum_overturn_fraction_fixed", "pulses overturning, fixed", 1.0),
                      ("dynamics", "spectrum_overturn_fraction_isolated",
                       "pulses overturning or exceeding the isolator's capacity, isolated", 1.0),
                      ("dynamics", "first_overturn_pga_fixed", "lowest overturning PGA fixed [g]", 1 / G),
                      ("dynamics", "first_overturn_pga_isolated",
                       "lowest failing PGA isolated (overturning or capacity exceeded) [g]", 1 / G),
                      ("isolator", "R", "isolator R [m]", 1.0), ("isolator", "T", "isolator T [s]", 1.0),
                      ("isolator", "passed", "isolator passes", None))


def run_collection(folder: str | Path, out: str | Path, config: ProjectConfig | None = None, *,
                   stages: list[str] | None = None, force: bool = False, executor=None, say=print,
                   reuse: bool = False) -> dict:
    """Every scan of ``folder`` as one sweep: OUT/<scan name>/ per scan (its own
    cached stages and report), OUT/collection.json and collection.csv. OUT is opened
    as in :func:`run_project` (manifest, lock, ``reuse``)."""
    scans = scans_in(folder)
    names = object_folders(scans)          # each scan's own folder, none of the collection's files
    # two rooms for one scan stop the run before any work; a pattern that places nothing is a warning
    room_warnings = check_scans(ProjectConfig() if config is None else config, [s.name for s in scans])
    def older(f: Path) -> list[str]:          # a collection written before output manifests
        subs = [n for n in names if (f / n).is_dir() and older_run(f / n)]
        return subs + [n for n in COLLECTION_FILES if subs and (f / n).is_file()]

    with open_output(out, "collection", reuse=reuse, command="run", adopt=older) as od:
        od.clean()
        od.claim([*names, *COLLECTION_FILES])
        return _run_collection(folder, Path(out), config, scans, stages=stages, force=force, executor=executor,
                               say=say, reuse=reuse, room_warnings=room_warnings, folders=names)


def _run_collection(folder, out: Path, config, scans, *, stages, force, executor, say, reuse,
                    room_warnings=(), folders=None) -> dict:
    cfg = ProjectConfig() if config is None else config
    for w in room_warnings:
        say(f"warning: {w}")
    folders = object_folders(scans) if folders is None else folders
    tasks = [(s, out / f, config_for(cfg, s.name), stages, force, reuse) for s, f in zip(scans, folders)]
    say(f"{len(scans)} scans in {folder} on {executor.describe() if executor is not None else 'this process'}")
    t0 = time.perf_counter()
    rows = executor.map(_scan_task, tasks, desc="scans") if executor is not None else [_scan_task(t) for t in tasks]
    wall = time.perf_counter() - t0
    for r in rows:                 # what each object did: a resumed collection shows its cached stages here
        if "error" in r:
            say(f"  {r['scan']}: not assessed: {r['error']}")
        else:
            say(f"  {r['scan']}: " + ", ".join(f"{k} {v}" for k, v in r["status"].items() if v in ("done", "cached")))
    places = {r["scan"]: object_placement(cfg, r["scan"]) for r in rows}
    table = []
    for r in rows:
        row = {"scan": r["scan"], **{label: places[r["scan"]][k] for k, label in PLACEMENT_COLUMNS}}
        if "error" in r:
            row["error"] = r["error"]
        for stage, key, label, factor in COLLECTION_COLUMNS:
            v = r.get("data", {}).get(stage, {}).get(key)
            row[label] = v if (v is None or factor is None) else v * factor
        row["warnings"] = len(r.get("warnings", ()))
        table.append(row)
    objects = []
    for r in rows:
        o, place = object_row(r, out), places[r["scan"]]
        o.update(room=place.get("room"), floor=place.get("floor"), where=where_text(place), value=place.get("value"))
        objects.append(o)
    ranked = rank(objects)
    summ = collection_summary(ranked)
    data = {"schema": "statue2model.collection/2", "folder": str(folder), "ranking_rule": RANKING_RULE,
            "summary": summ, "rows": ranked, "scans": rows, "table": table, "seconds": wall,
            "executor": executor.describe() if executor is not None else "this process",
            "placement": places, "warnings": list(room_warnings),
            "retried": [rows[i]["scan"] for i in getattr(executor, "retried", ())],
            "executor_notes": list(getattr(executor, "notes", ()))}
    write_config(cfg, out / "config.toml", Path(folder), out)
    write_json(out / "collection.json", data)
    header, cells = csv_rows(ranked)
    # the csv module quotes commas and quotes in scan names; safe_cell neutralises formulas
    write_csv(out / "collection.csv", header, cells)
    write_collection_page(ranked, summ, out / "collection.html", title=f"Collection: {Path(folder).name}",
                          config_text=(out / "config.toml").read_text(encoding="utf-8"))
    return data
