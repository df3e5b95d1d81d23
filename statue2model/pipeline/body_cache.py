"""The Body of a run, built once: kept in memory for the stages of the process, and
on disk beside props.json (``OUT/params/body.npz``) for later runs.

The Body (the scan read, repaired, oriented, in SI units, with its mass properties)
is what the params, prototype and crosscheck stages start from. Its *key* is the
SHA-256 of everything it depends on: the scan file's bytes and the path it is read
from (the Body records it), the [scan] settings that change it (units, up, height,
density or mass, base tolerance), the package's version and its code
(:func:`~statue2model.pipeline.cache.code_hash`).

:func:`load_body` returns, in this order, the Body already built in this run under
the same key (``memory``: a dict the run holds, one per run, dropped with it); the one
in the params stage's folder (when that stage is complete in this run) if the stage's
manifest lists the file with the same SHA-256, the file holds the same key and is well
formed; else the Body built from the scan. A missing, unlisted, stale, malformed or
tampered file is ignored (the Body is built again), never an error, and nothing in it
is executed (plain arrays, no pickle: :mod:`statue2model.geometry.body_store`). The
params stage writes the file into its folder with its other files, so the stage's
manifest lists it and the folder checks of :mod:`~statue2model.pipeline.cache` cover it.
Every caller gets its own copy of the Body: a stage that changes an array in place
cannot change what the next stage sees.
"""
from __future__ import annotations

import copy
import hashlib
import json
import os
from pathlib import Path

from ..version import __version__
from .cache import code_hash, file_hash

BODY_FILE = "body.npz"
"""The Body's file in the params stage's folder."""


def body_key(mesh: str | os.PathLike, options: dict, scan_sha256: str | None = None) -> str:
    """Key of the Body of scan ``mesh`` read with ``options`` (the keyword arguments of
    :func:`statue2model.geometry.body.load_body`); ``scan_sha256``: the scan's hash when the
    caller has it (the run hashes its scan once), else it is read here."""
    scan = scan_sha256 if scan_sha256 is not None else file_hash(mesh)
    blob = json.dumps({"scan": scan, "source": str(mesh), "options": options,
                       "version": __version__, "code": code_hash()}, sort_keys=True, default=str)
    return hashlib.sha256(blob.encode()).hexdigest()


def load_body(mesh: str | os.PathLike, options: dict, *, scan_sha256: str | None = None,
              memory: dict | None = None, cached: str | os.PathLike | None = None,
              cached_sha256: str | None = None, store: str | os.PathLike | None = None):
    """The Body of scan ``mesh`` with ``options`` (see the module docstring). ``scan_sha256``:
    the scan's hash if known (see :func:`body_key`); ``memory``: the run's dict of Bodies
    (key -> Body; None: keep none); ``cached``: a complete params stage
    folder to read body.npz from, taken only when its SHA-256 is ``cached_sha256`` (the
    hash the stage's manifest lists for it); ``store``: a folder to write it into."""
    from ..geometry import body as geometry_body
    from ..geometry.body_store import read_body, write_body

    try:
        key = body_key(mesh, options, scan_sha256)
    except OSError:                 # no readable scan: the reader says why, in its own words
        return geometry_body.load_body(mesh, **options)
    body = None if memory is None else memory.get(key)
    if body is None and cached is not None and cached_sha256 is not None:
        path = Path(cached) / BODY_FILE
        try:
            listed = path.is_file() and not path.is_symlink() and file_hash(path) == cached_sha256
        except OSError:
            listed = False
        body = read_body(path, key) if listed else None
    if body is None:
        body = geometry_body.load_body(mesh, **options)
    if memory is not None:
        memory.clear()                  # one Body at a time: a run has one scan
        memory[key] = body
    if store is not None:
        write_body(Path(store) / BODY_FILE, body, key)
    return copy.deepcopy(body)
