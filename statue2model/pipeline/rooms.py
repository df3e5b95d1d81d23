"""Objects on different floors of one museum: rooms, and which scan stands in which room.

One project file runs every scan of a folder (``statue2model run FOLDER``); its
``[building]`` section places every object at one spot. Objects on upper floors face
other design spectra (MODEL.md section 7), so the project file may place each object:

.. code-block:: toml

    [building]                      # the museum, and where an object stands by default
    storeys = 3
    height = "12m"

    [rooms.gallery_2]               # a room: the [building] keys that differ from [building]
    floor = 2

    [objects]                       # a scan -> its room, or its own [building] keys
    "maria_*" = "gallery_2"
    "dancing_girl.ply" = { floor = 1 }

``[rooms.NAME]`` holds any keys of ``[building]`` (floor, storeys, height, period,
structure, damping, isolated, floor_spectrum), read and checked as ``[building]`` is: a
room is ``[building]`` updated with its keys. A second building of the museum is a
room too (its own storeys, height, structure).

``[objects]`` maps a scan to a room name or to an inline table of ``[building]`` keys; the inline
table may give the object its own pedestal, ``pedestal = { size = [0.6, 0.6, 1.0], mass = 250 }``
(the keys of ``[pedestal]``; ``pedestal = false``: it stands on the floor), which replaces
``[pedestal]`` for that object.
A key is the scan's file name (``"dancing_girl.ply"``), its name without the suffix
(``"dancing_girl"``) or a pattern on them (``*``, ``?``, ``[abc]``; ``"maria_*"``),
compared without regard to case. It names a file of the folder, never a path (a ``/``
or ``\\`` in it is refused). A pattern may match several scans. A key without wildcards
wins over patterns (a rule and its exception: ``"maria_*"`` in one room,
``"maria_b.ply"`` in another); two keys of the same kind that place one scan in two
different rooms are an error naming both. A scan no key matches stands where
``[building]`` puts it. A key matching no scan of the folder is a warning
(:func:`check_scans`), not an error: one project file may serve several folders.

:func:`config_for` gives one object's configuration: ``[building]`` replaced by its
room's, and the table itself dropped (it has been applied: running that configuration
again gives the same object). Its stages' cache keys read ``[building]``
(pipeline/stages.py ``DEPENDS``), so an object moved to another floor is computed again
from the isolator stage on, and its scan properties are not. A single scan
(``statue2model run MESH``) takes its room from the table too when a key matches it.

Example
-------
>>> from statue2model.pipeline.config import load_config_text
>>> cfg = load_config_text('''
... [building]
... storeys = 3
... height = 12.0
... [rooms.gallery_2]
... floor = 2
... [objects]
... "maria_*" = "gallery_2"
... "dancing_girl.ply" = { floor = 1 }
... ''')
>>> config_for(cfg, "maria_barjatinskaja.ply").building.floor, config_for(cfg, "dancing_girl.ply").building.floor
(2, 1)
>>> config_for(cfg, "nefertiti.ply").building.floor              # no key matches: [building]
0
>>> ped = load_config_text('[objects]\\n"maria_*" = { floor = 0, pedestal = { size = [0.6, 0.6, 1.0], mass = 250 } }')
>>> config_for(ped, "maria_b.ply").pedestal.size, config_for(ped, "nefertiti.ply").pedestal.size
((0.6, 0.6, 1.0), None)
>>> p = object_placement(cfg, "maria_barjatinskaja.ply")
>>> p["room"], p["key"], p["floor"], p["on_floor"]
('gallery_2', 'maria_*', 2, True)
>>> check_scans(cfg, ["maria_barjatinskaja.ply", "nefertiti.ply"])
['[objects] "dancing_girl.ply" matches no scan of the folder']
"""
from __future__ import annotations

from dataclasses import fields, replace
from fnmatch import fnmatchcase

from ..errors import InputError
from ..quantities import G
from .config import BuildingConfig, PedestalConfig, ProjectConfig, _label, site

ROOM_KEYS = tuple(f.name for f in fields(BuildingConfig))
"""The keys a room (or an object's inline table) may set: those of ``[building]``. The table is
read and checked in pipeline/config.py (:func:`parse_rooms`, :func:`check_rooms`)."""

WILDCARDS = "*?["


def _matches(key: str, scan_name: str) -> bool:
    name = scan_name.lower()
    stem = name.rsplit(".", 1)[0] if "." in name.lstrip(".") else name
    return fnmatchcase(name, key.lower()) or fnmatchcase(stem, key.lower())


def room_of(cfg: ProjectConfig, scan_name: str) -> tuple[str | None, str | None, dict]:
    """(room name or None, the [objects] key that placed it or None, its [building] keys) of the
    scan named ``scan_name`` (a file name: only its last part is used); an InputError when two keys
    of the same kind place it in different rooms."""
    scan_name = str(scan_name).replace("\\", "/").rsplit("/", 1)[-1]
    hits = [(k, v) for k, v in cfg.objects if _matches(k, scan_name)]
    exact = [(k, v) for k, v in hits if not any(c in k for c in WILDCARDS)]
    hits = exact or hits
    if not hits:
        return None, None, {}
    rooms = dict(cfg.rooms)
    (k0, v0), *rest = hits
    for k, v in rest:
        if v != v0:
            def what(key, value):
                shown = f'"{value}"' if isinstance(value, str) else "{ " + ", ".join(
                    f"{kk} = {vv!r}" for kk, vv in value) + " }"
                return f"{_label(key)} = {shown}"
            raise InputError(f"[objects]: scan {scan_name!r} is placed by both {what(k0, v0)} and {what(k, v)}; "
                             "keep one of them, or name the scan exactly (an exact name wins over a pattern)")
    if isinstance(v0, str):
        if v0 not in rooms:
            raise InputError(f"[objects] {_label(k0)} = {v0!r}: unknown room")
        return v0, k0, dict(rooms[v0])
    return None, k0, dict(v0)


def value_of(cfg: ProjectConfig, scan_name: str) -> float | None:
    r"""The user's value of the scan named ``scan_name`` from ``[values]`` (matched as [objects]' keys: an
    exact name wins over a pattern; two patterns that give different values are an InputError naming
    both), None when no key matches.

    >>> from statue2model.pipeline.config import load_config_text
    >>> cfg = load_config_text('[values]\n"maria_*" = 2\n"maria_b.ply" = 5\n')
    >>> value_of(cfg, "maria_b.ply"), value_of(cfg, "maria_a.ply"), value_of(cfg, "nefertiti.obj")
    (5.0, 2.0, None)
    """
    scan_name = str(scan_name).replace("\\", "/").rsplit("/", 1)[-1]
    hits = [(k, v) for k, v in getattr(cfg, "values", ()) if _matches(k, scan_name)]
    exact = [(k, v) for k, v in hits if not any(c in k for c in WILDCARDS)]
    hits = exact or hits
    if not hits:
        return None
    (k0, v0), *rest = hits
    for k, v in rest:
        if v != v0:
            raise InputError(f"[values]: scan {scan_name!r} gets {v0:g} from {_label(k0)} and {v:g} from "
                             f"{_label(k)}; keep one, or name the scan exactly")
    return v0


def config_for(cfg: ProjectConfig, scan_name: str) -> ProjectConfig:
    """The configuration of one object: ``[building]`` updated with the keys of the room (or inline
    table) ``[objects]`` places the scan ``scan_name`` in, and ``rooms``/``objects`` dropped (applied).
    ``cfg`` itself when the table is empty; a scan no key matches keeps ``[building]``."""
    if not cfg.objects and not cfg.rooms and not getattr(cfg, "values", ()):
        return cfg
    _, _, keys = room_of(cfg, scan_name)
    ped = dict(keys.pop("pedestal", ()))
    pedestal = replace(PedestalConfig(), **ped) if ped else cfg.pedestal
    return replace(cfg, building=replace(cfg.building, **keys), pedestal=pedestal, rooms=(), objects=(), values=())


def object_placement(cfg: ProjectConfig, scan_name: str) -> dict:
    """Where ``[objects]`` puts the scan, for a collection's table: ``room`` (None: [building] or
    its own inline keys), ``key`` (the [objects] key that matched, None: none), the building keys
    ``floor``, ``storeys``, ``height`` (m), ``on_floor`` (the design target is a floor spectrum) and
    ``pga_g``: the design target's Se(0) in g (the ground's design PGA, or the peak floor
    acceleration on a floor; statue2model.hazard.site.SiteHazard.pga)."""
    room, key, _ = room_of(cfg, scan_name)
    one = config_for(cfg, scan_name)
    hz = site(one)
    b = one.building
    return {"room": room, "key": key, "floor": b.floor, "storeys": b.storeys, "height": b.height,
            "on_floor": bool(hz.on_floor), "pga_g": hz.pga / G, "value": value_of(cfg, scan_name)}


def where_text(place: dict) -> str:
    """One line for a collection page: the room (or "building"), the floor and the design PGA at the object.

    >>> where_text({"room": "gallery_2", "floor": 2, "storeys": 3, "pga_g": 0.575})
    'gallery_2, floor 2 of 3, 0.575 g'
    >>> where_text({"room": None, "floor": 0, "storeys": None, "pga_g": 0.2874})
    'ground floor, 0.287 g'
    """
    floor = place.get("floor") or 0
    parts = [] if place.get("room") is None else [str(place["room"])]
    parts.append("ground floor" if floor == 0 else
                 f"floor {floor}" + (f" of {place['storeys']}" if place.get("storeys") else ""))
    pga = place.get("pga_g")
    if pga is not None:
        parts.append(f"{pga:.3f} g")
    return ", ".join(parts)


PLACEMENT_COLUMNS = (("room", "room"), ("floor", "floor"), ("pga_g", "design PGA at the object [g]"))
"""(key of :func:`object_placement`, column label) for a collection's table."""


def check_scans(cfg: ProjectConfig, scan_names) -> list[str]:
    """Check ``[objects]`` against the scans of a folder before any work: an InputError when
    a scan is placed in two rooms (:func:`room_of`); the warnings (one line each) of keys
    that match no scan."""
    names = [str(n).replace("\\", "/").rsplit("/", 1)[-1] for n in scan_names]
    for n in names:
        room_of(cfg, n)
    for n in names:
        value_of(cfg, n)
    return [f"[{table}] {_label(k)} matches no scan of the folder" for table, rows in
            (("objects", cfg.objects), ("values", getattr(cfg, "values", ()))) for k, _ in rows
            if not any(_matches(k, n) for n in names)]
