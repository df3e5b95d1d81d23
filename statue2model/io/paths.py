"""Where the bundled data lives.

The bundled scans are in ``meshes/`` at the top of the repository (with their
attribution in meshes/ATTRIBUTION.md); the default scan is dancing_girl.ply.
The bundled ground-motion records are package data, ``statue2model/data/records/``
(each with its provenance in the README.md beside it): :func:`bundled_record`.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError

REPO_ROOT = Path(__file__).resolve().parents[2]
MESHES_DIR = REPO_ROOT / "meshes"
DEFAULT_SCAN = "dancing_girl.ply"
RECORDS_DIR = Path(__file__).resolve().parents[1] / "data" / "records"


def default_scan() -> Path:
    """Path of the bundled default scan (an error if the checkout has no meshes/ folder)."""
    path = MESHES_DIR / DEFAULT_SCAN
    if not path.is_file():
        raise InputError(f"the bundled default scan {path} is missing: give a mesh file")
    return path


def bundled_records() -> list[str]:
    """Names (file stems) of the bundled ground-motion records, e.g. ["elcentro_1940_ns"]."""
    return sorted(p.stem for p in RECORDS_DIR.glob("*.AT2"))


def bundled_record(name: str) -> Path:
    """Path of a bundled record by name (``elcentro_1940_ns``, or with its .AT2 suffix);
    its source and licence are in README.md beside it."""
    stem = str(name).strip()
    if stem.lower().endswith(".at2"):
        stem = stem[:-4]
    path = RECORDS_DIR / f"{stem}.AT2"
    if "/" in stem or "\\" in stem or not path.is_file():
        known = ", ".join(bundled_records()) or "none: the package data is missing"
        raise InputError(f"no bundled record {name!r} (bundled: {known})")
    return path
