"""Are two run folders the same? Every file of one against the other, byte for byte.

A refactor that promises "behaviour unchanged" is checked with it: run the same command
with the old and the new code into two folders, then

    python benchmarks/same_outputs.py OLD_DIR NEW_DIR

prints one row per file that is not byte-identical: ``same numbers`` (a JSON file equal
once the keys that legitimately differ between two runs are left out: wall-clock times,
the hashes of files that are themselves compared), ``same content`` (a text, DXF, SVG or
3MF file equal once what every writer stamps anew is masked: dates, GUIDs and UUIDs, random
SVG clip ids, the run's own folder), or ``DIFFERS`` (with the first differing key or line);
then a count, and exits 1 if any file differs or is missing. Numbers are compared exactly
(JSON floats bit for bit, text digit for digit), never with a tolerance.
"""
from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

VOLATILE_KEYS = {"seconds", "mesh", "timings", "files", "key"}
"""JSON keys whose values are wall-clock times, the scan's path, the hashes of files (each
file is compared itself), a stage's cache key (it hashes the code, which a refactor
changes): left out, as is every key with 'wall', 'cpu' or 'real_time' in its name (measured
times and speeds, e.g. the 3D scenes' real-time factors)."""

VOLATILE_TEXT = [
    re.compile(r"\d{4}-\d\d-\d\d[T ]\d\d:\d\d(:\d\d(\.\d+)?)?(\+\d\d:\d\d)?"),   # time stamps
    re.compile(r"\b24\d{5}\.\d+\b"),                                        # DXF Julian dates
    re.compile(r"\{[0-9A-F]{8}(-[0-9A-F]{4}){3}-[0-9A-F]{12}\}"),              # DXF GUIDs
    re.compile(r"[0-9a-f]{8}(-[0-9a-f]{4}){3}-[0-9a-f]{12}"),                  # 3MF UUIDs
    re.compile(r"\b[pm][0-9a-f]{10}\b"),                                       # matplotlib SVG clip and marker ids
    re.compile(r"(/[\w.+-]+)+/(?=meshes/)"),                                   # the checkout holding the scan
    re.compile(r"\d+(\.\d+)? ?s\b(?! ?[a-z(])"),                                # durations in text
]
"""What every writer stamps anew: masked in text before two files are compared."""


def _strip(x):
    if isinstance(x, dict):
        return {k: _strip(v) for k, v in x.items()
                if k not in VOLATILE_KEYS and not any(w in k for w in ("wall", "cpu", "real_time"))}
    if isinstance(x, list):
        return [_strip(v) for v in x]
    if isinstance(x, str):
        for r in VOLATILE_TEXT:
            x = r.sub("~", x)
    return x


def _first_difference(a, b, where="") -> str:
    if type(a) is not type(b):
        return f"{where or '/'}: {type(a).__name__} vs {type(b).__name__}"
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{where}/{k}: only in {'new' if k not in a else 'old'}"
            d = _first_difference(a[k], b[k], f"{where}/{k}")
            if d:
                return d
        return ""
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{where}: {len(a)} vs {len(b)} items"
        for i, (u, v) in enumerate(zip(a, b)):
            d = _first_difference(u, v, f"{where}[{i}]")
            if d:
                return d
        return ""
    return "" if a == b else f"{where}: {a!r} vs {b!r}"


TEXT = (".toml", ".txt", ".csv", ".html", ".md", ".dxf", ".svg")


def _dxf_classes_sorted(s: str) -> str:
    """The DXF's CLASSES section with its entries in sorted order: ezdxf writes them in the
    order of a set, which changes with PYTHONHASHSEED from one process to the next."""
    lines = s.splitlines()
    try:
        i = [x.strip() for x in lines].index("CLASSES")
    except ValueError:
        return s
    j = next(k for k in range(i, len(lines)) if lines[k].strip() == "ENDSEC")
    blocks, cur = [], []
    for k in range(i + 1, j - 1):          # entries start at a '  0' / 'CLASS' pair
        if lines[k].strip() == "0" and lines[k + 1].strip() == "CLASS" and cur:
            blocks.append(cur)
            cur = []
        cur.append(lines[k])
    blocks.append(cur + [lines[j - 1]])
    tail = blocks[-1].pop()
    return "\n".join(lines[: i + 1] + [x for b in sorted(blocks) for x in b] + [tail] + lines[j:])


def _text_difference(ba: bytes, bb: bytes, folders=(), dxf: bool = False) -> str:
    def lines(b):
        s = b.decode("utf-8", "replace")
        if dxf:
            s = _dxf_classes_sorted(s.replace("\r\n", "\n"))
        for f in folders:                      # the run's own folder, wherever it was
            s = s.replace(str(f.resolve()), "OUT")
        for f in folders:
            s = s.replace(f.name, "OUT")
        return [_strip(x) for x in s.splitlines()]

    la, lb = lines(ba), lines(bb)
    return next((f"line {i + 1}: {x!r} vs {y!r}" for i, (x, y) in enumerate(zip(la, lb)) if x != y),
                "" if len(la) == len(lb) else f"{len(la)} vs {len(lb)} lines")


def _zip_difference(ba: bytes, bb: bytes, folders=()) -> str:
    import io
    import zipfile

    za, zb = zipfile.ZipFile(io.BytesIO(ba)), zipfile.ZipFile(io.BytesIO(bb))
    if sorted(za.namelist()) != sorted(zb.namelist()):
        return "different members"
    for n in sorted(za.namelist()):
        d = _text_difference(za.read(n), zb.read(n), folders)
        if d:
            return f"{n}: {d}"
    return ""


def compare(old: Path, new: Path, expect_new=()) -> list[tuple[str, str, str]]:
    """(relative path, verdict, detail) for every file of either folder; a file only in ``new``
    whose name is in ``expect_new`` is 'new (expected)'."""
    names = sorted({p.relative_to(old).as_posix() for p in old.rglob("*") if p.is_file()}
                   | {p.relative_to(new).as_posix() for p in new.rglob("*") if p.is_file()})
    rows = []
    for name in names:
        a, b = old / name, new / name
        if not a.exists() and Path(name).name in expect_new:
            rows.append((name, "new (expected)", ""))
            continue
        if not a.exists() or not b.exists():
            rows.append((name, "DIFFERS", f"only in {'new' if not a.exists() else 'old'}"))
            continue
        ba, bb = a.read_bytes(), b.read_bytes()
        if ba == bb:
            rows.append((name, "same", ""))
            continue
        if name.endswith(".json"):
            d = _first_difference(_strip(json.loads(ba)), _strip(json.loads(bb)))
            rows.append((name, "DIFFERS", d) if d else (name, "same numbers", ""))
        elif name.endswith(TEXT):
            diff = _text_difference(ba, bb, (old, new), dxf=name.endswith(".dxf"))
            rows.append((name, "DIFFERS", diff[:200]) if diff else (name, "same content", ""))
        elif name.endswith(".3mf"):
            diff = _zip_difference(ba, bb, (old, new))
            rows.append((name, "DIFFERS", diff[:200]) if diff else (name, "same content", ""))
        else:
            rows.append((name, "DIFFERS", f"{len(ba)} vs {len(bb)} bytes"))
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--all", action="store_true", help="list identical files too")
    ap.add_argument("--expect-new", nargs="*", default=(), metavar="NAME",
                    help="file names the new code adds on purpose (e.g. body.npz)")
    args = ap.parse_args(argv)
    rows = compare(args.old, args.new, set(args.expect_new))
    counts: dict[str, int] = {}
    for name, verdict, detail in rows:
        counts[verdict] = counts.get(verdict, 0) + 1
        if args.all or verdict not in ("same",):
            print(f"{verdict:13s} {name}  {detail}")
    print(", ".join(f"{n} {v}" for v, n in sorted(counts.items())) + f" of {len(rows)} files")
    return 1 if counts.get("DIFFERS") else 0


if __name__ == "__main__":
    sys.exit(main())
