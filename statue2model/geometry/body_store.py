"""A Body as a file of plain arrays (``.npz``, no pickle), and back, bit for bit.

The pipeline keeps the Body of a run beside the params stage's props.json so later
stages and runs need not read and repair the scan again. A file in an output folder
is input like any other (it may be edited, replaced or planted), so it holds only
numbers, never objects: it is read with ``allow_pickle=False`` and a file that is
not exactly what :func:`write_body` writes is refused (None), never an error.

File layout (an uncompressed ``.npz``; every array numeric, C order as written):

    meta          uint8     JSON (UTF-8): FORMAT, the caller's key, the strings (source,
                            kind, units, up, log, warnings, the base's why), units_sure (bool)
                            and every scalar with its Python type ([type, value]: float, int,
                            float64)
    vertices      (n, 3)    float, m          faces         (f, 3) int, indices < n
    com           (3,)      m                 inertia       (3, 3) kg m^2
    rotation      (3, 3)    -                 translation   (3,) m
    hull          (k, 2)    m, the footprint's convex hull
    rings         (r, 2)    m, the footprint's rings one after the other (each polygon's
                            exterior, then its holes); ring_sizes (number of points of
                            each ring), ring_holes (number of holes of each polygon)
    case_hull_0/1/2 (k, 2)  m, the contact hulls at half, one and double the tolerance

The Body read back is built from these fields directly (nothing is recomputed), so it
equals the Body written field by field: the same dtypes, shapes, bytes and scalar types.

Example
-------
>>> import tempfile, pathlib
>>> import trimesh
>>> from statue2model.geometry.body import body_from_mesh
>>> box = trimesh.creation.box(extents=(0.4, 0.3, 1.0))
>>> body = body_from_mesh(box.vertices, box.faces, units="m", up="z")
>>> path = write_body(pathlib.Path(tempfile.mkdtemp()) / "body.npz", body, key="k1")
>>> again = read_body(path, key="k1")
>>> bool(np.array_equal(again.vertices, body.vertices)), again.mass.mass == body.mass.mass
(True, True)
>>> read_body(path, key="another key") is None              # stale: refused, not an error
True
"""
from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from .base import BaseContact, BaseSurface, ContactCase
from .body import Body
from .footprint import Footprint
from .massprops import MassProperties

__all__ = ["FORMAT", "body_arrays", "body_from_arrays", "read_body", "write_body"]

FORMAT = "statue2model.body/2"
"""The ``format`` of the file's meta record; a file with another one is refused."""


class _Refused(ValueError):
    """The arrays are not a Body written by :func:`body_arrays` (read_body returns None)."""


def _scalar(x) -> list:
    """A scalar as [type, value]: its Python type survives the JSON round trip."""
    tag = {float: "float", int: "int", np.float64: "float64", np.int64: "int64"}.get(type(x))
    if tag is None:
        raise TypeError(f"a scalar of type {type(x).__name__} is not stored")
    return [tag, float(x) if tag.startswith("float") else int(x)]


_SCALARS = {"float": (float, float), "int": (int, int), "float64": (float, np.float64), "int64": (int, np.int64)}


def _unscalar(v):
    """The scalar of ``_scalar``'s [type, value]; a finite number of the recorded type, else refused."""
    if not (isinstance(v, list) and len(v) == 2 and v[0] in _SCALARS):
        raise _Refused("malformed scalar")
    json_type, make = _SCALARS[v[0]]
    x = v[1]
    if type(x) is not json_type or (json_type is float and not math.isfinite(x)):
        raise _Refused("malformed scalar")
    return make(x)


def body_arrays(body: Body, key: str = "") -> dict[str, np.ndarray]:
    """The arrays of the module docstring for ``body`` (``key``: stored in meta, checked on reading)."""
    fp, base = body.footprint, body.base
    rings = [r for ext, holes in fp.polygons for r in (ext, *holes)]
    meta = {
        "format": FORMAT, "key": key, "source": body.source, "kind": body.kind, "units": body.units,
        "up": body.up, "log": list(body.log), "warnings": list(body.warnings), "scale": _scalar(body.scale),
        "units_sure": bool(body.units_sure),
        "mass": {k: _scalar(getattr(body.mass, k)) for k in ("volume", "mass", "density")},
        "footprint": {k: _scalar(getattr(fp, k)) for k in ("area", "hull_area", "tol")},
        "base": None if base is None else {
            "tol": _scalar(base.tol), "why": base.why, "tilt": _scalar(base.tilt),
            "surface": {k: _scalar(getattr(base.surface, k)) for k in ("edge", "roughness", "warp", "n_points")},
            "cases": [{"tol": _scalar(c.tol), "a_min": _scalar(c.a_min)} for c in base.cases]},
    }
    arrays = {
        "meta": np.frombuffer(json.dumps(meta, allow_nan=False).encode("utf-8"), dtype=np.uint8),
        "vertices": body.vertices, "faces": body.faces, "com": body.mass.com, "inertia": body.mass.inertia,
        "rotation": body.rotation, "translation": body.translation, "hull": fp.hull,
        "rings": np.concatenate(rings) if rings else np.zeros((0, 2)),
        "ring_sizes": np.array([len(r) for r in rings], dtype=np.int64),
        "ring_holes": np.array([len(holes) for _, holes in fp.polygons], dtype=np.int64),
    }
    if base is not None:
        arrays.update({f"case_hull_{i}": c.hull for i, c in enumerate(base.cases)})
    return arrays


def _array(arrays, name: str, kind: str, shape: tuple) -> np.ndarray:
    """``arrays[name]``: numeric of dtype kind ``kind`` ('f' finite float, 'i' integer), native byte
    order, with ``shape`` (None: any length on that axis); else refused."""
    a = arrays.get(name)
    if not isinstance(a, np.ndarray) or not a.dtype.isnative or a.dtype.fields is not None:
        raise _Refused(f"{name}: not a plain array")
    if not (a.dtype.kind == kind or (kind == "i" and a.dtype.kind == "u")):
        raise _Refused(f"{name}: dtype {a.dtype}")
    if a.ndim != len(shape) or any(n is not None and n != m for n, m in zip(shape, a.shape)):
        raise _Refused(f"{name}: shape {a.shape}")
    if kind == "f" and not np.isfinite(a).all():
        raise _Refused(f"{name}: not finite")
    return a


def _text(x) -> str:
    if not isinstance(x, str):
        raise _Refused("malformed text")
    return x


def _texts(x) -> tuple[str, ...]:
    if not isinstance(x, list):
        raise _Refused("malformed text list")
    return tuple(_text(s) for s in x)


def _no_constant(name: str):
    raise _Refused(f"meta: {name}")    # NaN, Infinity: never written


def _record(x, keys: tuple) -> dict:
    if not isinstance(x, dict) or set(x) != set(keys):
        raise _Refused("malformed record")
    return x


def body_from_arrays(arrays, key: str = "") -> Body:
    """The Body of :func:`body_arrays`' ``arrays`` (a mapping name -> ndarray) if they hold
    ``key``; raises ValueError when anything is missing, extra, of another dtype or shape,
    non-finite, out of range, or stored under another key or format."""
    raw = _array(arrays, "meta", "i", (None,))
    if raw.dtype != np.uint8:
        raise _Refused("meta: dtype")
    try:
        meta = json.loads(raw.tobytes().decode("utf-8"), parse_constant=_no_constant)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise _Refused(f"meta: {exc}") from None
    meta = _record(meta, ("format", "key", "source", "kind", "units", "up", "log", "warnings", "scale", "mass",
                          "footprint", "base", "units_sure"))
    if not isinstance(meta["units_sure"], bool):
        raise _Refused("meta: units_sure")
    if meta["format"] != FORMAT or meta["key"] != key or not isinstance(key, str):
        raise _Refused("another format or key")
    v = _array(arrays, "vertices", "f", (None, 3))
    f = _array(arrays, "faces", "i", (None, 3))
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        raise _Refused("faces: index out of range")
    sizes = _array(arrays, "ring_sizes", "i", (None,))
    holes = _array(arrays, "ring_holes", "i", (None,))
    rings_all = _array(arrays, "rings", "f", (None, 2))
    if (sizes < 0).any() or (holes < 0).any() or int(sizes.sum()) != len(rings_all) \
            or len(holes) + int(holes.sum()) != len(sizes):
        raise _Refused("footprint rings: sizes do not add up")
    ends = np.cumsum(sizes)
    rings = [rings_all[e - n:e].copy() for n, e in zip(sizes.tolist(), ends.tolist())]
    polygons, i = [], 0
    for n_holes in holes.tolist():
        polygons.append((rings[i], tuple(rings[i + 1:i + 1 + n_holes])))
        i += 1 + n_holes
    m = _record(meta["mass"], ("volume", "mass", "density"))
    mass = MassProperties(volume=_unscalar(m["volume"]), mass=_unscalar(m["mass"]), density=_unscalar(m["density"]),
                          com=_array(arrays, "com", "f", (3,)), inertia=_array(arrays, "inertia", "f", (3, 3)))
    fm = _record(meta["footprint"], ("area", "hull_area", "tol"))
    fp = Footprint(polygons=tuple(polygons), hull=_array(arrays, "hull", "f", (None, 2)),
                   area=_unscalar(fm["area"]), hull_area=_unscalar(fm["hull_area"]), tol=_unscalar(fm["tol"]))
    names = {"meta", "vertices", "faces", "com", "inertia", "rotation", "translation", "hull", "rings",
             "ring_sizes", "ring_holes"}
    base = None
    if meta["base"] is not None:
        b = _record(meta["base"], ("tol", "why", "tilt", "surface", "cases"))
        s = _record(b["surface"], ("edge", "roughness", "warp", "n_points"))
        if not (isinstance(b["cases"], list) and len(b["cases"]) == 3):
            raise _Refused("base: three contact cases")
        cases = []
        for i, c in enumerate(b["cases"]):
            c = _record(c, ("tol", "a_min"))
            cases.append(ContactCase(tol=_unscalar(c["tol"]), hull=_array(arrays, f"case_hull_{i}", "f", (None, 2)),
                                     a_min=_unscalar(c["a_min"])))
            names.add(f"case_hull_{i}")
        surface = BaseSurface(edge=_unscalar(s["edge"]), roughness=_unscalar(s["roughness"]),
                              warp=_unscalar(s["warp"]), n_points=_unscalar(s["n_points"]))
        base = BaseContact(tol=_unscalar(b["tol"]), why=_text(b["why"]), surface=surface, tilt=_unscalar(b["tilt"]),
                           cases=tuple(cases))
    if set(arrays) != names:
        raise _Refused("unexpected arrays")
    return Body(source=_text(meta["source"]), kind=_text(meta["kind"]), vertices=v, faces=f, mass=mass,
                footprint=fp, units=_text(meta["units"]), up=_text(meta["up"]), scale=_unscalar(meta["scale"]),
                rotation=_array(arrays, "rotation", "f", (3, 3)), translation=_array(arrays, "translation", "f", (3,)),
                log=_texts(meta["log"]), warnings=_texts(meta["warnings"]), base=base, units_sure=meta["units_sure"])


def write_body(path: str | os.PathLike, body: Body, key: str = "") -> Path | None:
    """Write ``body`` to ``path`` (an uncompressed ``.npz``), atomically (files.atomic_write).
    A Body that would not read back (a non-finite number, a scalar of another type) is not
    written (None): it is simply built again where it is needed."""
    from ..io.files import atomic_write

    try:
        arrays = body_arrays(body, key)
        body_from_arrays(arrays, key)
    except (TypeError, ValueError):
        return None

    def save(p: Path) -> None:
        with open(p, "wb") as fh:             # a file object: np.savez would add .npz to a name
            np.savez(fh, **arrays)

    return atomic_write(path, save, size=sum(a.nbytes for a in arrays.values()))


def read_body(path: str | os.PathLike, key: str = "") -> Body | None:
    """The Body in ``path`` when it is a regular file written by :func:`write_body` with
    ``key``; None when it is missing, stale (another key or format), malformed or tampered
    with (never an error: the caller builds the Body from the scan instead). Nothing in the
    file is executed: arrays are read with ``allow_pickle=False``."""
    path = Path(path)
    try:
        if path.is_symlink() or not path.is_file():       # a link, a FIFO, a device: not ours
            return None
        with np.load(path, allow_pickle=False) as z:
            arrays = {name: z[name] for name in z.files}
        return body_from_arrays(arrays, key)
    except Exception:       # noqa: BLE001 - any malformed file (zip, npy header, object arrays, ...)
        return None
