"""Where the bundled data lives.

The bundled scans are in ``meshes/`` at the top of the repository (with their
attribution in meshes/ATTRIBUTION.md); the default scan is dancing_girl.ply.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError

REPO_ROOT = Path(__file__).resolve().parents[2]
MESHES_DIR = REPO_ROOT / "meshes"
DEFAULT_SCAN = "dancing_girl.ply"


def default_scan() -> Path:
    """Path of the bundled default scan (an error if the checkout has no meshes/ folder)."""
    path = MESHES_DIR / DEFAULT_SCAN
    if not path.is_file():
        raise InputError(f"the bundled default scan {path} is missing: give a mesh file")
    return path
