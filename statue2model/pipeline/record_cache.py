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

import dataclasses
import functools
import hashlib
import json
import os
import pickle
from pathlib import Path

import numpy as np

from ..io.files import atomic_write
from ..version import __version__
from .cache import code_hash

ENV = "STATUE2MODEL_RECORD_CACHE"
"""The environment variable naming the folder ('off' or '0': no cache)."""

ARRAYS = ("periods", "spectra", "target")
"""The RecordSet fields kept as npz arrays; ``records`` as one array each; every other field in
the JSON header, by its dataclass name (a field added to RecordSet is kept without a change here)."""


@functools.cache
def _code() -> str:
    """The package's code hash, once per process."""
    return code_hash()


def folder() -> Path | None:
    """The cache's folder, or None when it is switched off."""
    env = os.environ.get(ENV)
    if env is not None:
        return None if env.strip().lower() in ("", "off", "0", "no", "false") else Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "statue2model" / "record_sets"


def set_key(args: tuple) -> str:
    """Key of the record set matched with ``args`` (stages._match_args' tuple)."""
    h = hashlib.sha256()
    h.update(pickle.dumps(args, protocol=4))
    h.update(json.dumps({"version": __version__, "code": _code()}).encode())
    return h.hexdigest()


def _to_file(path: Path, key: str, rs) -> None:
    """Write RecordSet ``rs`` to ``path`` (npz of arrays and a JSON header) atomically."""
    recs = rs.records
    fields = {f.name: getattr(rs, f.name) for f in dataclasses.fields(rs) if f.name not in ("records", *ARRAYS)}
    meta = {"key": key, "dts": [m.dt for m in recs], "labels": [m.label for m in recs],
            "starts": [m.start for m in recs], "fields": fields,
            "tuples": [name for name, v in fields.items() if isinstance(v, tuple)]}
    arrays = {f"acc_{i}": np.asarray(m.samples) for i, m in enumerate(recs)}
    header = np.array(json.dumps(meta))

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as f:
            np.savez(f, meta=header, **{k: getattr(rs, k) for k in ARRAYS}, **arrays)

    atomic_write(path, write)


def _from_file(path: Path, key: str):
    """The RecordSet in ``path`` if it holds ``key``, else None."""
    from ..hazard.matching import RecordSet
    from ..hazard.motions import record

    with np.load(path, allow_pickle=False) as z:
        meta = json.loads(str(z["meta"][()]))
        if meta.get("key") != key:
            return None
        records = tuple(record(z[f"acc_{i}"], float(dt), float(start), label)
                        for i, (dt, start, label) in enumerate(zip(meta["dts"], meta["starts"], meta["labels"])))
        arrays = {k: np.array(z[k]) for k in ARRAYS}
    fields = meta["fields"]
    for name in meta["tuples"]:
        fields[name] = tuple(fields[name])
    return RecordSet(records=records, **arrays, **fields)


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
