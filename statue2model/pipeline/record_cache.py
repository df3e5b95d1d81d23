"""Matched record sets kept between runs: a warm run does not match its record sets again.

A run matches its design record set (seeds 1..N) and the isolator's further sets (seeds
k x 100 + 1 ..) to the site's spectrum (hazard/matching.py match_set, through
assessment/study.match_records): the same arguments always give the same set, bit for bit,
and matching is the largest single cost of a warm default run. So each set is also kept on
disk, one file per set, under ``$STATUE2MODEL_RECORD_CACHE`` (default
``$XDG_CACHE_HOME/statue2model/record_sets``, i.e. ``~/.cache/statue2model/record_sets``);
``STATUE2MODEL_RECORD_CACHE=off`` keeps none.

A set's *key* is the SHA-256 of its matching arguments (pickled: the target spectrum whole,
not its repr), the package's version and its code (:func:`~statue2model.pipeline.cache.code_hash`):
any code change matches again. The file (``<key>.npz``) holds plain arrays and one JSON
string, never a pickle (nothing in it is executed), and the key again: a missing, stale,
malformed or tampered file is ignored and the set matched again, never an error; a folder that
cannot be written keeps nothing (the run goes on).
"""
from __future__ import annotations

import hashlib
import json
import os
import pickle
import tempfile
from pathlib import Path

import numpy as np

from ..version import __version__
from .cache import code_hash

ENV = "STATUE2MODEL_RECORD_CACHE"
"""The environment variable naming the folder ('off' or '0': no cache)."""

_CODE: list = []


def folder() -> Path | None:
    """The cache's folder, or None when it is switched off."""
    env = os.environ.get(ENV)
    if env is not None:
        return None if env.strip().lower() in ("", "off", "0", "no", "false") else Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "statue2model" / "record_sets"


def set_key(args: tuple) -> str:
    """Key of the record set matched with ``args`` (stages._match_args' tuple)."""
    if not _CODE:
        _CODE.append(code_hash())
    h = hashlib.sha256()
    h.update(pickle.dumps(args, protocol=4))
    h.update(json.dumps({"version": __version__, "code": _CODE[0]}).encode())
    return h.hexdigest()


def _to_file(path: Path, key: str, rs) -> None:
    """Write RecordSet ``rs`` to ``path`` (npz of arrays and a JSON header) atomically."""
    recs = rs.records
    meta = {"key": key, "dts": [m.dt for m in recs], "labels": [m.label for m in recs],
            "starts": [m.start for m in recs], "seeds": list(rs.seeds), "band": list(rs.band),
            "tolerance": list(rs.tolerance), "xi": rs.xi, "iterations": rs.iterations,
            "target_info": rs.target_info, "target_pga": rs.target_pga, "required_band": list(rs.required_band),
            "band_reason": rs.band_reason, "stationary_s": rs.stationary_s, "pga_scale": rs.pga_scale,
            "d_g": rs.d_g, "sd_plateau": rs.sd_plateau, "kind": rs.kind}
    arrays = {f"acc_{i}": np.asarray(m.samples) for i, m in enumerate(recs)}
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, meta=np.array(json.dumps(meta)), periods=rs.periods, spectra=rs.spectra,
                     target=rs.target, **arrays)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _from_file(path: Path, key: str):
    """The RecordSet in ``path`` if it holds ``key``, else None."""
    from ..hazard.matching import RecordSet
    from ..hazard.motions import record

    with np.load(path, allow_pickle=False) as z:
        meta = json.loads(str(z["meta"][()]))
        if meta.get("key") != key:
            return None
        n = len(meta["labels"])
        records = tuple(record(z[f"acc_{i}"], float(meta["dts"][i]), float(meta["starts"][i]), meta["labels"][i])
                        for i in range(n))
        periods, spectra, target = (np.array(z[k]) for k in ("periods", "spectra", "target"))
    return RecordSet(records, tuple(int(s) for s in meta["seeds"]), periods, spectra, target,
                     tuple(float(x) for x in meta["band"]), tuple(meta["tolerance"]), float(meta["xi"]),
                     int(meta["iterations"]), meta["target_info"], float(meta["target_pga"]),
                     tuple(float(x) for x in meta["required_band"]), meta["band_reason"],
                     float(meta["stationary_s"]), float(meta["pga_scale"]), meta["d_g"], meta["sd_plateau"],
                     meta["kind"])


def matched(args: tuple, match):
    """The record set ``match(args)`` gives: read from the cache when it holds it, else matched
    and kept there (see the module docstring)."""
    where = folder()
    if where is None:
        return match(args)
    try:
        key = set_key(args)
    except Exception:   # an argument that does not pickle: match, keep nothing
        return match(args)
    path = where / f"{key}.npz"
    try:
        rs = _from_file(path, key)
    except Exception:   # missing, truncated, malformed: matched again
        rs = None
    if rs is not None:
        return rs
    rs = match(args)
    try:
        _to_file(path, key, rs)
    except Exception:   # read-only or full disk: the run goes on without the cache
        pass
    return rs
