"""Helpers for the tests of what commands write: folder snapshots and one-line errors."""
from __future__ import annotations

import hashlib
from pathlib import Path

# a hand-written params record (kg, m, kg m^2), enough for the dynamics commands
PARAMS = {"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8}


def snapshot(folder: Path) -> dict[str, str]:
    """relative path -> sha256 of every file and "dir" of every folder, hidden ones too."""
    return {str(p.relative_to(folder)): "dir" if p.is_dir() else hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*"))}


def only_line(capsys) -> str:
    """The one line a refused command printed on stderr."""
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]
