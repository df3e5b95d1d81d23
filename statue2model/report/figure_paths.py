"""The figures a stage's manifest names, checked before the report embeds them: a manifest
(stage.json) is input, it may have been edited, so only files inside the stage's own folder
are read.
"""
from __future__ import annotations

from pathlib import Path


def safe_figures(manifest: dict, folder: Path) -> list[dict]:
    """The figures of a stage's ``manifest`` for the report, each checked to be a file the
    stage wrote inside its ``folder`` (a manifest is input: an edited stage.json can name
    anything). Returns [{"path", "caption", "root"}] with ``path`` resolved (symlinks
    followed) inside ``folder`` (or the unresolved path of a missing file), or
    [{"path", "caption", "refused": reason}] for an entry that is malformed, absolute,
    holds '..', or resolves outside ``folder``: the report shows a note, never its bytes.

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp()); _ = (d / "a.png").write_bytes(b"x")
    >>> [f.get("refused") for f in safe_figures({"figures": [{"path": "a.png", "caption": ""},
    ...      {"path": "../../etc/hostname"}, {"path": "/etc/hostname"}]}, d)]
    [None, 'path outside the stage folder', 'path outside the stage folder']
    """
    root = Path(folder).resolve()
    entries = manifest.get("figures") if isinstance(manifest, dict) else None
    out = []
    for fig in entries if isinstance(entries, list) else ():
        rel = fig.get("path") if isinstance(fig, dict) else None
        caption = str(fig.get("caption") or "") if isinstance(fig, dict) else ""
        if not isinstance(rel, str) or not rel.strip() or "\x00" in rel:
            out.append({"path": str(rel), "caption": caption, "refused": "malformed figure entry"})
            continue
        p = Path(rel)
        if p.is_absolute() or p.drive or ".." in p.parts or ".." in rel.replace("\\", "/").split("/"):
            out.append({"path": rel, "caption": caption, "refused": "path outside the stage folder"})
            continue
        try:
            real = (root / p).resolve(strict=True)
        except FileNotFoundError:       # missing: the report says so
            out.append({"path": str(root / p), "caption": caption, "root": str(root)})
            continue
        except (OSError, RuntimeError):  # a symlink loop, a name too long, ...
            out.append({"path": rel, "caption": caption, "refused": "unreadable figure path"})
            continue
        if not real.is_relative_to(root) or real == root:
            out.append({"path": rel, "caption": caption, "refused": "path outside the stage folder"})
            continue
        out.append({"path": str(real), "caption": caption, "root": str(root)})
    return out
