"""The project file: every choice of a ``statue2model run``, in one TOML file.

Sections and keys (SI units: metres, kilograms, seconds, m/s^2; a string may carry
a unit instead: ``"9mm"``, ``"0.075g"``; ``"auto"`` leaves a choice to the program).
An acceleration inside a string (motions ``amp=``, ``pga=``, spectra ``ag=``, grids) needs
its unit: ``0.3g`` or ``2.94m/s2``; a bare ``amp=0.3`` is refused.

[scan]       units, up, height, density, mass, direction, base_tol      (``props``)
[prototype]  enabled, scale, board, glue, policy, tool, compensate, tolerance, rod,
             clearance, wall, sheet, margin, edge, feed, pass_depth, board_density,
             glue_density, rod_density, front, previews                 (``slice``)
[model]      kind, alpha_L, alpha_R, theta_L, theta_R, e_L, e_R, rtol   (the 2D rocking model)
[sliding]    mu_statue, mu_pedestal, kinetic_ratio, allowance           (friction: sliding and the
                                                                         regime; assessment/support.py)
[pedestal]   size = [width, depth, height] (m), mass (kg), position = [x, y] (m, the centre of the
             statue's base from the pedestal's axis; default centred): the statue stands on it
             (rocking/stack.py); width is along the excitation direction; or file (a scan of the
             pedestal), units, up, density instead of size
[isolator]   enabled, mu, spectrum, motion, slc_spectrum, grooves, layout, surface, ball_material,
             thickness, side_max, target, fuse_release, segments, mu_low, mu_high (friction bounds),
             ball_capacity (a load test: N on a 40 mm ball), extra_sets, under (statue | pedestal)
[isolator.prices]  item = EUR: the device's price table (isolator/prices.py PRICES)
[building]   floor, storeys, height, period, structure, damping, isolated, floor_spectrum
             (where the object stands: floor 0 = on the ground, the [isolator] spectrum itself;
             an upper floor takes the floor spectrum of the Circolare / EC8, hazard/floor.py)
[rooms.NAME] the [building] keys of one room that differ from [building] (floor = 2, ...)
[values]     scan file name (or its stem, or a pattern) = the object's value > 0: the collection
             ranks by risk x value (pipeline/rooms.py value_of)
[objects]    scan file name (or its stem, or a pattern: "maria_*") = a room name, or inline
             [building] keys ({ floor = 1 }): each scan of a folder on its own floor
             (pipeline/rooms.py; an exact name wins over a pattern)
[dynamics]   enabled, pulse, freq, amp, motion, pga, isolated,          (spectra, variability,
             fragility, fragility_records, fragility_duration,          time histories, fragility)
             fragility_levels, fragility_samples, fragility_rounds
[crosscheck] enabled, quick, motion, dt, statue_dt, iterations, grid, groove, pulse_freq, isolator, ensemble,
             ensemble_budget
[run]        stages, workers, scheduler                                 (what a plain ``run`` does
                                                                         and where sweeps run)

Every physical key has a range (:data:`RANGES`, docs/run.md "Ranges of the physical keys"; ``statue2model
config`` writes each beside its key): an impossible value stops the load with one line, an unusual one is a
warning (``ProjectConfig.warnings``, printed by ``statue2model run``); a [dynamics] grid needs a level above 0.

``[run] stages`` is what ``statue2model run`` does without ``--stages``: by default
``"params, prototype, isolator, dynamics"`` (the assessment; the core install has all it
needs). ``"all"`` adds the 3D cross-check (``crosscheck``, the ``[physics]`` extra);
stages switched off by their ``enabled = false`` are left out.

The scale is written ``"1:2"`` (or the ratio prototype/statue, ``0.5``); a bare 2 is
refused (1:2 or 2:1?).

The defaults are the thesis' choices: a 1:2 prototype of 9 mm OSB boards (620 kg/m^3)
glued with 0.5 mm films, a 3 mm cutter, 8 mm steel alignment rods, 2500 x 1250 mm
panels (ch. 6.2.2); marble (2650 kg/m^3); the classical rocking model with the
angular-momentum restitution (eq. 15) until a prototype test identifies alpha and
theta (then ``kind = "imperfect"``; the thesis' statue: alpha_L 0.159, alpha_R 0.175,
Table 24); one-cosine pulse spectra (Fig. 65-68); an isolator whose rolling friction follows
the measured laws (Tables 19, 25) of the balls and groove surface it is built with, designed
on the EC8 type 1 spectrum (its collapse level x gamma_x 1.2), and the thesis' fuse released
at 0.075 g (ch. 5.3).

Example
-------
>>> cfg = load_config(None)                       # the defaults
>>> cfg.prototype.scale, cfg.prototype.board, cfg.isolator.mu, cfg.isolator.surface
(2.0, 0.009, None, 'auto')
>>> import tempfile, pathlib
>>> p = pathlib.Path(tempfile.mkdtemp()) / "project.toml"
>>> _ = p.write_text('[prototype]\\nscale = "1:4"\\nboard = "12mm"\\n[dynamics]\\npga = "0.05g:0.4g:8"\\n')
>>> cfg = load_config(p)
>>> cfg.prototype.scale, cfg.prototype.board, cfg.dynamics.pga
(4.0, 0.012, '0.05g:0.4g:8')
>>> load_config(p).to_toml() == load_config_text(cfg.to_toml(), "resolved").to_toml()   # round trip
True
>>> _ = p.write_text('[prototype]\\nbord = 0.009\\n')
>>> load_config(p)
Traceback (most recent call last):
...
statue2model.errors.InputError: ...project.toml: unknown key 'bord' in [prototype] (did you mean 'board'?)
"""
from __future__ import annotations

import difflib
import math
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from .. import quantities as Q
from ..quantities import G
from ..errors import InputError, quoted
from ..io.tomlfile import parse_toml
from ..quantities import scale_text

AUTO = "auto"


@dataclass(frozen=True)
class ScanConfig:
    """How the scan is read (see ``statue2model props``). None = auto."""

    units: str = "auto"                 # m | mm | cm | in | auto
    up: str = "auto"                    # x | y | z | -x | -y | -z | auto
    height: float | None = None         # rescale to this real height, m
    density: float = 2650.0             # kg/m^3 (marble); ignored when mass is given
    mass: float | None = None           # measured mass, kg
    direction: float | None = None      # excitation direction, deg from +x toward +y; None = weakest
    base_tol: float | None = None       # contact tolerance, m


@dataclass(frozen=True)
class PrototypeConfig:
    """The stacked-board prototype (see ``statue2model slice``)."""

    enabled: bool = True
    scale: float = 2.0                  # lambda of a 1:lambda prototype (written "1:2" or 0.5 in the file)
    board: float = 0.009                # m
    glue: float = 0.0005                # m
    policy: str = "mid"                 # mid | envelope | core
    tool: float = 0.003                 # cutter diameter, m
    compensate: bool = False
    tolerance: float = 5e-5             # chordal tolerance, m
    rod: float = 0.008                  # m
    clearance: float = 0.0002           # m
    wall: float = 0.005                 # m
    sheet: tuple[float, float] = (2.5, 1.25)   # panel W x H, m
    margin: float = 0.002               # m
    edge: float = 0.01                  # m
    feed: float = 2000.0 / 60000.0      # cutting feed, m/s (2000 mm/min)
    pass_depth: float | None = None     # m; None = the cutter diameter
    board_density: float = 620.0        # kg/m^3 (OSB)
    glue_density: float = 1100.0        # kg/m^3
    rod_density: float = 7850.0         # kg/m^3 (steel)
    front: float | None = None          # deg; None = the scan's front
    previews: bool = True


@dataclass(frozen=True)
class ModelConfig:
    """The 2D rocking model used by every analysis (MODEL.md section 2)."""

    kind: str = "housner"               # housner | imperfect
    alpha_L: float = 1.0                # reduced uplift accelerations (imperfect)
    alpha_R: float = 1.0
    theta_L: float | None = None        # rolling-transition rotation, rad; None = 0.07 delta_L
    theta_R: float | None = None
    e_L: float | None = None            # restitution; None = angular momentum (eq. 15)
    e_R: float | None = None
    rtol: float = 1e-7


MU_SOURCES = ("Monaco et al. 2020 (Procedia Struct. Integrity 29: a 650 kg marble statue on its pedestal, mu_s 0.40, "
              "mu_k 0.30); Kafali, Fathali, Grigoriu & Whittaker 2007 (MCEER-07-0001: tilt and pull tests give "
              "higher coefficients than the kinetic ones shake-table responses imply)")
"""Where the default friction comes from (docs/pedestal.md lists the ranges)."""


@dataclass(frozen=True)
class SlidingConfig:
    """Friction of the statue on its support and of the pedestal on the floor (assessment/support.py): the
    sliding limit states and the regime (a body whose uplift needs more than mu_s g slides first). Defaults
    :data:`MU_SOURCES`: stone, marble or bronze on wood or stone lies about 0.3-0.7 static; the lower value is
    the conservative reading for sliding."""

    mu_statue: float = 0.4              # static friction of the statue on its support (floor or pedestal top)
    mu_pedestal: float = 0.4            # static friction of the pedestal on the floor
    kinetic_ratio: float = 0.75         # mu_k / mu_s (0.30 / 0.40 in Monaco et al. 2020)
    allowance: float | None = None      # m the body may slide; auto = the pedestal top's edge, on the floor 0.05 m


@dataclass(frozen=True)
class PedestalConfig:
    """The pedestal the statue stands on (rocking/stack.py); neither size nor file: the statue stands on the
    floor. A scanned pedestal (``file``) is read as a statue's scan is and enters the 2D model as its
    equivalent box (its base's extent along the excitation direction, its height, its mass)."""

    size: tuple | None = None           # [width along the excitation, depth, height], m
    mass: float | None = None           # kg (with file: auto = its volume x density)
    position: tuple = (0.0, 0.0)        # m: the centre of the statue's base (along the excitation direction,
                                        # across it) from the pedestal's vertical axis
    file: str | None = None             # a scan of the pedestal (any format a statue's scan may have)
    units: str = "auto"                 # of the pedestal's scan, as [scan] units
    up: str = "auto"                    # of the pedestal's scan, as [scan] up
    density: float = 2650.0             # kg/m^3 of the pedestal's scan when no mass is given


@dataclass(frozen=True)
class IsolatorConfig:
    """Rolling-ball isolator design (see ``statue2model isolator design``; isolator/design.py): the cheapest
    device that passes every check, searched over balls, layouts, groove surfaces and boards."""

    enabled: bool = True
    mu: float | None = None             # rolling friction; auto = each ball/surface pair's law (Tables 19, 25)
    spectrum: str | None = "ec8:ag=0.25g,ground=C,type=1"
    motion: str | None = None           # design on a ground motion instead of a spectrum
    # the device at the collapse level (SLC): auto = the design spectrum x gamma_x 1.2 on an EC8 site (EN
    # 1998-1 10.3(2)); on an NTC site give the site's a_g, F0, T_C* at T_R of SLC (else scaled: hazard/levels.py)
    slc_spectrum: str | None = None
    grooves: int | None = None          # number of balls (3, 4, 5, 6, 8, 9, 12, 16); auto = the cheapest
    layout: str = "auto"                # ring3 .. ring8, grid3x3, grid3x4, grid4x4 (isolator/layout.py)
    surface: str = "auto"               # beech, robinia, beech_rubber, hdpe, pom, steel_race (isolator/bearing.py)
    ball_material: str = "auto"         # steel | resin
    thickness: float = 0.03             # wooden board thickness, m (stacked and glued where a groove needs more)
    side_max: float = 1.5               # largest plate side, m (the CNC bed; 1.25 for a 1250 x 2500 mm one)
    target: float | None = None         # stricter plate acceleration limit, m/s^2
    fuse_release: float | None = 0.075 * G   # m/s^2; None = no fuse
    segments: int = 256                 # groove tessellation of the plate solids
    # the time-history verification (isolator/verify.py) runs every record at two friction bounds;
    # auto = mu times the spread measured on the thesis' four-groove device (Table 25: 0.0039 to
    # 0.0108 about 0.0073), as EN 15129 / ASCE 7-16 17.2.8.4 bound analyses ask
    mu_low: float | None = None         # lower bound (the travel); auto = mu x 0.0039 / 0.0073
    mu_high: float | None = None        # upper bound (the forces); auto = mu x 0.0108 / 0.0073
    # a load test of the groove surface: N carried on a 40 mm ball (r 20 mm) with the allowed dent; auto =
    # each surface's model (isolator/bearing.py: beech calibrated on the thesis' 73.6 N)
    ball_capacity: float | None = None
    extra_sets: int = 3                 # further record sets (other seeds) the device must hold on
    under: str = "statue"               # statue | pedestal: what the device carries (with a [pedestal]: "pedestal"
                                        # carries the stack, designed for its mass and the smaller uplift)
    prices: tuple = ()                  # [isolator.prices] item = EUR (isolator/prices.py), as (item, EUR) pairs


@dataclass(frozen=True)
class BuildingConfig:
    """Where the object stands (MODEL.md section 7; statue2model.hazard.site): the design target of
    every analysis is the [isolator] spectrum on the ground floor, the floor spectrum above it."""

    floor: int = 0                      # the floor the object stands on: 0 = ground floor, storeys = roof
    storeys: int | None = None          # storeys above the foundation
    height: float | None = None         # m, foundation to roof
    period: float | None = None         # T1, s; auto = C_t H^(3/4) (EN 1998-1 eq. 4.6)
    structure: str = "masonry"          # masonry | concrete-frame | steel-frame | other
    damping: float = 5.0                # the building's damping, percent
    isolated: bool = False              # a base-isolated building (its floors take z = 0)
    floor_spectrum: str = "auto"        # auto (NTC: general C7.2.5-10; EC8: eq. 4.25) | ec8 | ntc2018 | ntc2018-framed


@dataclass(frozen=True)
class DynamicsConfig:
    """2D analyses, on a fixed base and on the isolator."""

    enabled: bool = True
    pulse: str = "cosine"               # cosine | sine (stability spectra)
    freq: str = "0.5:10:40"             # pulse frequencies START:STOP:N, Hz
    amp: str = "0.02g:1g:40"            # pulse amplitudes START:STOP:N
    motion: str = "synthetic:duration=20,pga=0.4g,seed=1"    # time histories, variability
    pga: str = "0.05g:1.2g:24"          # variability: the motion scaled to these PGAs
    isolated: bool = True               # also on the isolator (needs [isolator] enabled)
    fragility: bool = True              # fragility curves over a set matched to [isolator] spectrum
    fragility_records: int = 7          # records of the set (seeds 1..N)
    fragility_duration: float | None = None   # s, each record; auto = 25 s or 5 x the band's end
    fragility_levels: str = "auto"      # coarse PGA levels: auto (0.2-3 x the design PGA, 10) or START:STOP:N
    fragility_samples: int = 7          # parameter samples: theta_R, e, alpha (imperfect), e (Housner), mu bounds
    fragility_rounds: int = 3           # rounds of adaptive levels around each curve's median (0: coarse only)


@dataclass(frozen=True)
class CrosscheckConfig:
    """3D PyBullet cross-check (see ``statue2model crosscheck``)."""

    enabled: bool = True
    quick: bool = False
    motion: str = "synthetic:duration=8,pga=0.2g,seed=1"
    dt: float = 5e-4                    # s, the ball isolator scenes (the exact one runs at statue_dt)
    statue_dt: float = 2e-3             # s, the statue scenes
    iterations: int = 50
    grid: float = 0.004                 # groove lattice spacing on the sphere, m; 0 = the CNC mesh
    groove: str = "exact"               # the isolator: "exact" (translating spherical pendulum, fast) or ball
                                        # contacts on "lattice" grooves or "tiles" (the detailed mode)
    pulse_freq: float = 1.5             # Hz
    isolator: bool = True               # also the statue on the isolator
    ensemble: bool = True               # also the 2D/3D classification over the design record set (needs the
                                        # dynamics stage's fragility medians; exact isolator scene only)
    ensemble_budget: float = 600.0      # s of wall time its 3D runs may take (fewer levels, or none, if not)


@dataclass(frozen=True)
class RunConfig:
    """What a plain ``run`` does (``stages``) and where the sweeps run (never changes a result)."""

    stages: str = "params, prototype, isolator, dynamics"   # or "all" (adds crosscheck)
    workers: int | None = None          # local processes; None = one per core
    scheduler: str | None = None        # Dask scheduler address (tcp://host:8786)


SECTIONS = {"scan": ScanConfig, "prototype": PrototypeConfig, "model": ModelConfig, "sliding": SlidingConfig,
            "pedestal": PedestalConfig, "isolator": IsolatorConfig,
            "building": BuildingConfig, "dynamics": DynamicsConfig, "crosscheck": CrosscheckConfig, "run": RunConfig}

# how a value is read: the converter of each key that is not a plain number/bool/str
_LENGTHS = {("scan", "height"), ("scan", "base_tol"), ("prototype", "board"), ("prototype", "glue"),
            ("prototype", "tool"), ("prototype", "tolerance"), ("prototype", "rod"), ("prototype", "clearance"),
            ("prototype", "wall"), ("prototype", "margin"), ("prototype", "edge"), ("prototype", "pass_depth"),
            ("isolator", "thickness"), ("isolator", "side_max"), ("crosscheck", "grid"), ("building", "height"),
            ("sliding", "allowance")}
_ACCELS = {("isolator", "target"), ("isolator", "fuse_release")}
_AUTO_GRIDS = {("dynamics", "fragility_levels")}     # "auto" or a grid
_CHOICES = {("scan", "units"): ("auto", "m", "mm", "cm", "in"),
            ("scan", "up"): ("auto", "x", "y", "z", "-x", "-y", "-z"),
            ("pedestal", "units"): ("auto", "m", "mm", "cm", "in"),
            ("pedestal", "up"): ("auto", "x", "y", "z", "-x", "-y", "-z"),
            ("prototype", "policy"): ("mid", "envelope", "core"),
            ("model", "kind"): ("housner", "imperfect"),
            ("dynamics", "pulse"): ("cosine", "sine"),
            ("crosscheck", "groove"): ("exact", "lattice", "tiles"),
            ("building", "structure"): ("masonry", "concrete-frame", "steel-frame", "other"),
            ("isolator", "layout"): ("auto", "ring3", "ring4", "ring5", "ring6", "ring8", "grid3x3", "grid3x4",
                                     "grid4x4"),
            ("isolator", "surface"): ("auto", "beech", "robinia", "beech_rubber", "hdpe", "pom", "steel_race"),
            ("isolator", "ball_material"): ("auto", "steel", "resin"),
            ("isolator", "under"): ("statue", "pedestal"),
            ("building", "floor_spectrum"): ("auto", "ec8", "ntc2018", "ntc2018-framed")}

RANGES = {("scan", "height"): "height", ("scan", "mass"): "mass", ("scan", "density"): "density",
          ("scan", "base_tol"): "base_tol",
          **{("prototype", k): k for k in ("board", "glue", "tool", "rod", "clearance", "wall", "margin", "edge",
                                           "tolerance", "feed", "pass_depth", "board_density", "glue_density",
                                           "rod_density")},
          ("prototype", "sheet"): "sheet_side",
          ("model", "alpha_L"): "alpha", ("model", "alpha_R"): "alpha", ("model", "theta_L"): "transition_rotation",
          ("model", "theta_R"): "transition_rotation", ("model", "e_L"): "restitution", ("model", "e_R"): "restitution",
          ("sliding", "mu_statue"): "static_friction", ("sliding", "mu_pedestal"): "static_friction",
          ("sliding", "kinetic_ratio"): "kinetic_ratio", ("sliding", "allowance"): "allowance",
          ("pedestal", "size"): "pedestal_side", ("pedestal", "mass"): "pedestal_mass", ("pedestal", "density"): "density",
          ("isolator", "mu"): "rolling_friction", ("isolator", "mu_low"): "rolling_friction",
          ("isolator", "mu_high"): "rolling_friction", ("isolator", "thickness"): "plate_thickness",
          ("isolator", "side_max"): "plate_side", ("isolator", "target"): "plate_acceleration",
          ("isolator", "fuse_release"): "fuse_release", ("isolator", "ball_capacity"): "ball_capacity",
          ("building", "storeys"): "storeys", ("building", "height"): "building_height",
          ("building", "period"): "building_period", ("building", "damping"): "building_damping",
          ("crosscheck", "grid"): "grid", ("crosscheck", "pulse_freq"): "pulse_frequency"}
"""(section, key) -> its row of :data:`statue2model.geometry.units.PLAUSIBLE` (the one table of ranges, which the
command-line options of the same quantities read too): a value outside the row's possible range is refused
when the file is read (one line, exit 2), one outside its usual range is a warning (:func:`validate` returns
them, :func:`load_config` keeps them in ``ProjectConfig.warnings``). The grids ([dynamics] freq, amp, pga,
fragility_levels) are checked level by level (pulse_frequency, acceleration) and need a positive level;
[building] height / storeys is a storey's height (storey_height). docs/run.md lists every range."""
GRID_RANGES = {"freq": "pulse_frequency", "amp": "acceleration", "pga": "acceleration",
               "fragility_levels": "acceleration"}


def range_text(sec: str, key: str) -> str:
    """The usual and possible range of a key of :data:`RANGES`, in words (for the documentation).

    >>> range_text("building", "storeys")
    'usually 1 to 20; possible 1 to 200'
    >>> range_text("isolator", "ball_capacity")
    'usually 10 to 2.5e+04 N; possible 0.1 to 6e+04 N'
    """
    from ..geometry.units import PLAUSIBLE

    r = PLAUSIBLE[RANGES[sec, key] if (sec, key) in RANGES else GRID_RANGES[key]]
    k, u = (1 / G, " g") if r.unit == "m/s^2" else (1.0, "" if r.unit == "-" else f" {r.unit}")   # as users write it
    return f"usually {r.low * k:.4g} to {r.high * k:.4g}{u}; possible {r.hard_low * k:.4g} to {r.hard_high * k:.4g}{u}"


def check_ranges(sec: str, values: dict, shown: str | None = None) -> list[str]:
    """The keys of section ``sec`` in ``values`` (key -> value; None skipped, a tuple checked item by item)
    against :data:`RANGES`: an :class:`InputError` for an impossible value, the warnings for unusual ones.
    ``shown``: the table's name in the messages (default ``sec``: a room's [building] keys are named as
    [rooms.NAME]'s)."""
    from ..geometry.units import check_plausible

    out = []
    for key, v in values.items():
        quantity = RANGES.get((sec, key))
        if quantity is None or v is None:
            continue
        for x in (v if isinstance(v, (tuple, list)) else (v,)):
            note = check_plausible(quantity, x, f"[{shown or sec}] {key}")
            if note:
                out.append(note)
    if sec == "building" and values.get("storeys") and values.get("height") is not None:
        note = check_plausible("storey_height", values["height"] / values["storeys"],
                               f"[{shown or sec}] height / storeys ({values['height']:g} m / {values['storeys']})")
        if note:
            out.append(note)
    return out


@dataclass(frozen=True)
class ProjectConfig:
    """All sections; immutable. ``source`` is the file it was read from (None: defaults)."""

    scan: ScanConfig = field(default_factory=ScanConfig)
    prototype: PrototypeConfig = field(default_factory=PrototypeConfig)
    model: ModelConfig = field(default_factory=ModelConfig)
    sliding: SlidingConfig = field(default_factory=SlidingConfig)
    pedestal: PedestalConfig = field(default_factory=PedestalConfig)
    isolator: IsolatorConfig = field(default_factory=IsolatorConfig)
    building: BuildingConfig = field(default_factory=BuildingConfig)
    dynamics: DynamicsConfig = field(default_factory=DynamicsConfig)
    crosscheck: CrosscheckConfig = field(default_factory=CrosscheckConfig)
    run: RunConfig = field(default_factory=RunConfig)
    # [rooms.NAME] and [objects] (pipeline/rooms.py): ((room, ((key, value), ...)), ...) and
    # ((scan name or pattern, room name or ((key, value), ...)), ...); values as [building]'s
    rooms: tuple = ()
    objects: tuple = ()
    # [values] (pipeline/rooms.py value_of): ((scan name or pattern, the user's value > 0), ...): the
    # collection ranks by risk x value when given; no stage reads it
    values: tuple = ()
    source: str | None = None
    # the unusual values of the file ([section] key = value is unusual for ...: RANGES), said once at load
    warnings: tuple = field(default=(), compare=False)

    def section(self, name: str) -> dict:
        """One section as a plain dict (None kept), for content hashes; ``"sec:key1,key2"`` only those
        keys of it (a stage that reads two keys of a section is not recomputed when another changes).

        >>> ProjectConfig().section("dynamics:fragility_records,fragility_duration")
        {'fragility_records': 7, 'fragility_duration': None}
        """
        sec, _, keys = name.partition(":")
        d = asdict(getattr(self, sec))
        return {k: d[k] for k in keys.split(",")} if keys else d

    def to_dict(self) -> dict:
        """Every section; ``rooms`` and ``objects`` too when the file has them."""
        out = {name: self.section(name) for name in SECTIONS}
        if self.rooms:
            out["rooms"] = {name: dict(keys) for name, keys in self.rooms}
        if self.objects:
            out["objects"] = {k: v if isinstance(v, str) else {kk: dict(vv) if kk == "pedestal" else vv
                                                               for kk, vv in v} for k, v in self.objects}
        if self.values:
            out["values"] = dict(self.values)
        return out

    def to_toml(self) -> str:
        """The resolved configuration: every key, None written as "auto"."""
        import tomli_w

        def clean(v):
            if v is None:
                return AUTO
            if isinstance(v, tuple):
                return list(v)
            return v

        data = {name: {k: clean(v) for k, v in sec.items()} for name, sec in self.to_dict().items()
                if name in SECTIONS}
        table = self.to_dict()
        if "rooms" in table:
            data["rooms"] = {name: {k: clean(v) for k, v in keys.items()} for name, keys in table["rooms"].items()}
        if "objects" in table:
            data["objects"] = {k: v if isinstance(v, str) else {
                kk: {pk: clean(pv) for pk, pv in vv.items()} if kk == "pedestal" else clean(vv)
                for kk, vv in v.items()} for k, v in table["objects"].items()}
        if "values" in table:
            data["values"] = dict(table["values"])
        data["prototype"]["scale"] = scale_text(self.prototype.scale)     # "1:2", as the user writes it
        data["isolator"]["prices"] = {k: v for k, v in self.isolator.prices}   # [isolator.prices]
        for sec, key in _ACCELS:                # accelerations with their unit, as the user writes them
            v = getattr(getattr(self, sec), key)
            if v is not None:
                data[sec][key] = f"{v!r}m/s2"
        return tomli_w.dumps(data)

    def with_section(self, name: str, **changes) -> ProjectConfig:
        return replace(self, **{name: replace(getattr(self, name), **changes)})


def _show(v) -> str:
    return f'"{v}"' if isinstance(v, str) else str(v).lower() if isinstance(v, bool) else str(v)


def _whole(parse, value):
    """``parse(value)`` (a function of :mod:`statue2model.quantities`) with its whole message
    kept when it refuses the value (ValueError; an InputError's message would be cut)."""
    try:
        return parse(value)
    except InputError as exc:
        raise ValueError(str(exc)) from None


def _convert(sec: str, key: str, value, default, where: str, nullable: bool = False, shown: str | None = None):
    """One TOML value -> the field's type, or an InputError naming it (in table ``shown``, default
    ``sec``: a room's keys are read as [building]'s and named as [rooms.NAME]'s)."""
    name = f"{where}: [{shown or sec}] {key}"
    if isinstance(value, str) and value.strip().lower() in (AUTO, "none"):
        if (sec, key) in _CHOICES and AUTO in _CHOICES[sec, key] or (sec, key) in _AUTO_GRIDS:
            return AUTO
        if nullable:
            return None
        shown = f'"{scale_text(default)}"' if key == "scale" else _show(default)
        raise InputError(f"{name} = {quoted(value)}: needs a value (default {shown})")
    try:
        # bool is an int in Python: without this, board = true would read as a 1 m board
        if not isinstance(default, bool) and (isinstance(value, bool) or isinstance(value, (list, tuple))
                                              and any(isinstance(x, bool) for x in value)):
            raise ValueError("true/false where a value is due")
        if (sec, key) == ("isolator", "prices"):
            return _prices(value)
        if (sec, key) in (("pedestal", "size"), ("pedestal", "position")):
            k = 3 if key == "size" else 2
            if not isinstance(value, (list, tuple)) or len(value) != k or any(
                    isinstance(x, bool) or not isinstance(x, (int, float)) for x in value):
                raise ValueError("must be [width, depth, height] in m" if k == 3 else "must be [x, y] in m")
            v = tuple(float(x) for x in value)
            if not all(math.isfinite(x) for x in v):
                raise ValueError("must be finite")
            return v
        if (sec, key) in _CHOICES:
            v = str(value).strip().lower()
            if v not in _CHOICES[sec, key]:
                raise ValueError(f"must be one of {', '.join(_CHOICES[sec, key])}")
            return v
        if (sec, key) in _LENGTHS:
            v = _whole(Q.length, value) if isinstance(value, str) else float(value)
        elif (sec, key) in _ACCELS:
            if not isinstance(value, str):  # one meaning everywhere: an acceleration carries its unit
                raise ValueError(f"an acceleration needs its unit: write \"{float(value):g}g\" or "
                                 f"\"{float(value):g}m/s2\"")
            try:
                v = Q.parse_accel(value, key, key=key)
            except InputError as exc:       # its whole message ("fuse_release=0.3 has no unit: ...")
                raise ValueError(str(exc)) from None
        elif key == "scale":
            v = _whole(Q.scale_ratio, value)         # "1:2" or 0.5; a bare 2 is refused (1:2 or 2:1?)
        elif key == "sheet":
            v = _whole(Q.sheet_size, value) if isinstance(value, str) else tuple(float(x) for x in value)
            if len(v) != 2:
                raise ValueError("must be [W, H] in m or 'WxHmm'")
            return v
        elif key == "feed" and isinstance(value, str):
            t = value.strip().lower().replace(" ", "")
            if not t.endswith("mm/min"):
                raise ValueError("give m/s or 'N mm/min'")
            v = float(t[:-6]) / 60000.0
        elif isinstance(default, bool):
            if not isinstance(value, bool):
                raise ValueError("must be true or false")
            return value
        elif isinstance(default, int) or key in ("grooves", "workers", "iterations", "segments", "storeys"):
            if isinstance(value, bool) or not float(value).is_integer():
                raise ValueError("must be a whole number")
            return int(value)
        elif isinstance(default, str) or key in ("spectrum", "motion", "scheduler", "slc_spectrum", "file"):
            if not isinstance(value, str):
                raise ValueError("must be a string")
            return value
        else:
            if isinstance(value, bool):
                raise ValueError("must be a number")
            v = float(value)
    except (ValueError, TypeError, InputError) as exc:
        msg = str(exc).split(": ")[-1] if isinstance(exc, InputError) else str(exc)
        raise InputError(f"{name} = {quoted(value)}: {msg}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} = {quoted(value)}: must be finite")
    return v


def _prices(value) -> tuple:
    """[isolator.prices]: a table of item = EUR -> sorted (item, EUR) pairs, checked by isolator/prices.py."""
    from ..isolator.prices import prices

    if not isinstance(value, dict):
        raise ValueError("must be a table [isolator.prices] of item = price in EUR")
    try:
        prices(value)
    except InputError as exc:
        raise ValueError(str(exc).split(": ", 1)[-1]) from None
    return tuple(sorted((str(k), float(v)) for k, v in value.items()))


# --- [rooms.NAME] and [objects]: each object of a folder on its own floor (pipeline/rooms.py) ---
_ROOM_KEYS = tuple(f.name for f in fields(BuildingConfig))
_MAX_NAME = 255                      # characters of a room name or an [objects] key


def _label(text: str) -> str:
    """A table name as TOML writes it: bare when it can be, else quoted."""
    bare = text and all(c.isascii() and (c.isalnum() or c in "_-") for c in text)
    return text if bare else '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _check_name(kind: str, name: str, where: str) -> None:
    if not name or not name.isprintable() or len(name) > _MAX_NAME or name != name.strip():
        raise InputError(f"{where}: {kind} {quoted(name)} must be 1 to {_MAX_NAME} printable characters, without "
                         "leading or trailing spaces")


def _building_keys(table, shown: str, where: str) -> tuple:
    """The [building] keys of a room or an inline [objects] table, converted as [building]'s."""
    defaults = {f.name: f.default for f in fields(BuildingConfig)}
    nullable = {f.name: "None" in str(f.type) for f in fields(BuildingConfig)}
    out = []
    for key, value in table.items():
        if key not in defaults:
            near = difflib.get_close_matches(key, _ROOM_KEYS, 1)
            hint = f" (did you mean '{near[0]}'?)" if near else f" (the keys of [building]: {', '.join(_ROOM_KEYS)})"
            raise InputError(f"{where}: unknown key {quoted(key)} in [{shown}]{hint}")
        out.append((key, _convert("building", key, value, defaults[key], where, nullable[key], shown=shown)))
    return tuple(sorted(out, key=lambda kv: kv[0]))


def _pedestal_keys(table, shown: str, where: str) -> tuple:
    """An object's own pedestal (``pedestal = { size = [...], mass = ... }`` in its inline [objects] table, or
    ``pedestal = false``: none), converted and checked as [pedestal]'s: ((key, value), ...)."""
    if table is False:
        return (("mass", None), ("size", None))
    if not isinstance(table, dict):
        raise InputError(f"{where}: [{shown}] pedestal must be a table {{ size = [w, d, h], mass = kg }} or false")
    defaults = {f.name: f.default for f in fields(PedestalConfig)}
    out = {}
    for key, value in table.items():
        if key not in defaults:
            raise InputError(f"{where}: unknown key {quoted(key)} in [{shown}] pedestal (the keys of [pedestal]: "
                             f"{', '.join(defaults)})")
        out[key] = _convert("pedestal", key, value, defaults[key], where, key != "position", shown=f"{shown} pedestal")
        if key == "file" and out[key] is not None and not Path(out[key]).is_absolute():
            raise InputError(f"{where}: [{shown}] pedestal file must be an absolute path here (or give it as "
                             "[pedestal] file, read relative to the project file)")
    check_pedestal(PedestalConfig(**out), f"{where}: [{shown}] pedestal")
    return tuple(sorted(out.items()))


def check_pedestal(pd: PedestalConfig, where: str) -> None:
    """A pedestal's keys checked: both size and mass or neither, plausible sizes, the statue on its top."""
    def bad(msg):
        raise InputError(f"{where}: {msg}")

    if pd.file is not None:
        if pd.size is not None:
            bad("give either size (a box) or file (a scan of the pedestal), not both")
        if not Path(pd.file).is_file():
            bad(f"file {quoted(pd.file)} is not a readable file")
        if not 100 <= pd.density <= 20000:
            bad(f"density must be in 100..20000 kg/m^3, got {pd.density}")
        if pd.mass is not None and not 0.1 <= pd.mass <= 1e6:
            bad(f"mass must be in 0.1..1e6 kg, got {pd.mass}")
        return
    if (pd.size is None) != (pd.mass is None):
        bad("give both size = [width, depth, height] (m) and mass (kg), or neither")
    if pd.size is not None:
        if not all(0.01 <= x <= 20 for x in pd.size):
            bad(f"size must be three lengths in 0.01..20 m (width, depth, height), got {list(pd.size)}")
        if not 0.1 <= pd.mass <= 1e6:
            bad(f"mass must be in 0.1..1e6 kg, got {pd.mass}")
        if any(abs(x) > s_ / 2 for x, s_ in zip(pd.position, pd.size)):
            bad(f"position {list(pd.position)} puts the centre of the statue's base off the pedestal's top "
                f"({pd.size[0]:g} x {pd.size[1]:g} m)")
    elif pd.position != (0.0, 0.0):
        bad("position needs a pedestal: give its size and mass")


def parse_rooms(rooms, objects, where: str = "project file") -> tuple[tuple, tuple]:
    """The ``[rooms]`` and ``[objects]`` tables of a project file (parsed TOML: dicts, or None
    when absent) as ProjectConfig's ``rooms`` ((name, ((key, value), ...)), ...) and
    ``objects`` ((key, room name or ((key, value), ...)), ...), each sorted by name; values
    converted as ``[building]``'s. The rooms named in ``[objects]`` are checked by :func:`check_rooms`."""
    room_rows, object_rows = [], []
    if rooms is not None:
        if not isinstance(rooms, dict):
            raise InputError(f"{where}: rooms must be tables [rooms.NAME] of [building] keys")
        for name, table in rooms.items():
            _check_name("room name", name, where)
            if not isinstance(table, dict):
                raise InputError(f"{where}: [rooms] {_label(name)} = {quoted(table)}: a room is a table "
                                 f"[rooms.{_label(name)}] of [building] keys (floor = 2, ...)")
            room_rows.append((name, _building_keys(table, f"rooms.{_label(name)}", where)))
    if objects is not None:
        if not isinstance(objects, dict):
            raise InputError(f"{where}: objects must be a table [objects] of scan name = room")
        for key, value in objects.items():
            _check_name("[objects] key", key, where)
            if "/" in key or "\\" in key:
                raise InputError(f"{where}: [objects] {_label(key)}: a key is a scan's file name or a pattern "
                                 "on it, not a path")
            if isinstance(value, dict):
                value = dict(value)
                ped = value.pop("pedestal", None)
                keys = _building_keys(value, f"objects.{_label(key)}", where)
                if ped is not None:
                    keys = tuple(sorted((*keys, ("pedestal", _pedestal_keys(ped, f"objects.{_label(key)}", where)))))
                object_rows.append((key, keys))
            elif isinstance(value, str):
                object_rows.append((key, value))
            else:
                raise InputError(f"{where}: [objects] {_label(key)} = {quoted(value)}: give a room name "
                                 "(\"gallery_2\") or [building] keys ({ floor = 1 })")
    return tuple(sorted(room_rows)), tuple(sorted(object_rows, key=lambda row: row[0]))   # file order is no meaning


def parse_values(values, where: str = "project file") -> tuple:
    """The ``[values]`` table (scan file name, its stem or a pattern = the user's value of the object, a
    number > 0: a price, an insured value or a 1-5 importance) as ProjectConfig's ``values``, sorted."""
    if values is None:
        return ()
    if not isinstance(values, dict):
        raise InputError(f"{where}: values must be a table [values] of scan name = a number > 0")
    rows = []
    for key, value in values.items():
        _check_name("[values] key", key, where)
        if "/" in key or "\\" in key:
            raise InputError(f"{where}: [values] {_label(key)}: a key is a scan's file name or a pattern on it, "
                             "not a path")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value > 0) \
                or value > 1e15:
            raise InputError(f"{where}: [values] {_label(key)} = {quoted(value)}: give a number > 0 (a price, an "
                             "insured value or an importance; at most 1e15)")
        rows.append((key, float(value)))
    return tuple(sorted(rows))


def check_rooms(cfg: ProjectConfig, where: str = "project file") -> list[str]:
    """Every room and inline table of ``cfg`` checked as ``[building]`` is (its keys' ranges, the floor
    spectrum can be built), and every room named in ``[objects]`` defined; the warnings of unusual values."""
    names = [name for name, _ in cfg.rooms]
    for key, value in cfg.objects:
        if isinstance(value, str) and value not in names:
            near = difflib.get_close_matches(value, names, 1)
            hint = (f" (did you mean '{near[0]}'?)" if near else
                    f" (rooms: {', '.join(names)})" if names else " (the file defines no [rooms.NAME])")
            raise InputError(f"{where}: [objects] {_label(key)} = {quoted(value)}: unknown room{hint}")
    shown = [(f"rooms.{_label(n)}", k) for n, k in cfg.rooms]
    shown += [(f"objects.{_label(n)}", tuple(kv for kv in v if kv[0] != "pedestal"))
              for n, v in cfg.objects if not isinstance(v, str)]
    warnings = []
    for table, keys in shown:
        own = dict(keys)
        if "storeys" in own or "height" in own:        # a storey's height of the building the room is in
            own = {"storeys": cfg.building.storeys, "height": cfg.building.height, **own}
        try:
            warnings += check_ranges("building", own, table)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
        try:
            site(replace(cfg, building=replace(cfg.building, **dict(keys))))
        except InputError as exc:
            raise InputError(f"{where}: [{table}] (the [building] with its keys): {exc}") from None
    return warnings


def load_config_text(text: str, where: str = "project file", base_dir: Path | None = None) -> ProjectConfig:
    """Parse TOML text (unknown sections or keys are errors, with a suggestion);
    relative paths of ``file:`` motions are taken from ``base_dir`` (default: the
    current folder) and stored absolute."""
    data = parse_toml(text, where)
    kw = dict(zip(("rooms", "objects"), parse_rooms(data.pop("rooms", None), data.pop("objects", None), where)))
    kw["values"] = parse_values(data.pop("values", None), where)
    for sec, table in data.items():
        if sec not in SECTIONS:
            known = [*SECTIONS, "rooms", "objects", "values"]
            near = difflib.get_close_matches(sec, known, 1)
            hint = f" (did you mean [{near[0]}]?)" if near else f" (sections: {', '.join(known)})"
            raise InputError(f"{where}: unknown section [{quoted(sec, bare=True)}]{hint}")
        if not isinstance(table, dict):
            raise InputError(f"{where}: {quoted(sec, bare=True)} must be a [section]")
        cls = SECTIONS[sec]
        defaults = {f.name: f.default for f in fields(cls)}
        nullable = {f.name: "None" in str(f.type) for f in fields(cls)}
        values = {}
        for key, value in table.items():
            if (sec, key) == ("model", "mu_static"):
                raise InputError(f"{where}: [model] mu_static has moved: write it as [sliding] mu_statue (the "
                                 "statue's static friction on its support)")
            if key not in defaults:
                near = difflib.get_close_matches(key, defaults, 1)
                hint = f" (did you mean '{near[0]}'?)" if near else ""
                raise InputError(f"{where}: unknown key {quoted(key)} in [{sec}]{hint}")
            values[key] = _convert(sec, key, value, defaults[key], where, nullable[key])
        for key in ("motion",):
            if key in values:
                values[key] = _absolute_file_spec(values[key], Path(base_dir) if base_dir else Path.cwd())
        if sec == "pedestal" and values.get("file"):
            values["file"] = str(((Path(base_dir) if base_dir else Path.cwd()) / values["file"]).resolve())
        kw[sec] = cls(**values)
    cfg = ProjectConfig(**kw, source=where)
    return replace(cfg, warnings=tuple(validate(cfg, where)))


def load_config(path: str | Path | None) -> ProjectConfig:
    """The project file at ``path`` over the defaults (None: the defaults alone)."""
    if path is None:
        return ProjectConfig()
    path = Path(path)
    if not path.is_file():
        raise InputError(f"project file not found: {path}")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read project file {path}: {exc}") from None
    return replace(load_config_text(text, str(path), base_dir=path.resolve().parent), source=str(path))


MOTION_KEYS = (("isolator", "motion"), ("dynamics", "motion"), ("crosscheck", "motion"))


def _absolute_file_spec(spec: str | None, base_dir: Path) -> str | None:
    """A ``file:path=P,...`` motion with P made absolute (relative to ``base_dir``), so
    the resolved configuration names the same record from any folder."""
    if not spec or not spec.strip().lower().startswith("file:"):
        return spec
    kind, _, rest = spec.partition(":")
    parts = []
    for part in rest.split(","):
        key, eq, value = part.partition("=")
        if eq and key.strip().lower() == "path" and not Path(value.strip()).is_absolute():
            part = f"path={(base_dir / value.strip()).resolve()}"
        parts.append(part)
    return f"{kind}:{','.join(parts)}"


def motion_files(cfg: ProjectConfig, sections) -> dict:
    """{path: SHA-256} of the motion records (and the pedestal's scan) that ``sections`` of ``cfg`` read
    (for cache keys)."""
    from .cache import file_hash

    out = {}
    if "pedestal" in sections and cfg.pedestal.file and Path(cfg.pedestal.file).is_file():
        out[cfg.pedestal.file] = file_hash(cfg.pedestal.file)
    for sec, key in MOTION_KEYS:
        spec = getattr(getattr(cfg, sec), key) if sec in sections else None
        if spec and spec.strip().lower().startswith("file:"):
            for part in spec.partition(":")[2].split(","):
                k, _, v = part.partition("=")
                if k.strip().lower() == "path" and Path(v.strip()).is_file():
                    out[v.strip()] = file_hash(v.strip())
    return out


def validate(cfg: ProjectConfig, where: str = "project file") -> list[str]:
    """Check what can be checked before any work starts (grids, motions, spectra,
    ranges), so a typo fails in a second, not after minutes: an impossible value is an
    :class:`InputError` (one line); the unusual ones (:data:`RANGES`) are returned as warnings
    (``"[building] storeys = 40 is unusual for a number of storeys (1 to 20)"``)."""
    from ..assessment.study import fragility_levels
    from ..hazard.code_spectra import parse_spectrum
    from ..hazard.motions import parse_spec
    from ..rocking.sweeps import linspace_spec

    def bad(msg):
        raise InputError(f"{where}: {msg}")

    p, m, i, d, c, r = (cfg.prototype, cfg.model, cfg.isolator, cfg.dynamics, cfg.crosscheck, cfg.run)
    warnings: list[str] = []
    if p.pass_depth is not None and not p.pass_depth > 0:
        bad("[prototype] pass_depth must be positive")
    if not 1 <= p.scale <= 100:
        bad(f"[prototype] scale must be 1:1 .. 1:100, got 1:{p.scale:g}")
    if m.kind == "housner" and (m.alpha_L != 1 or m.alpha_R != 1):
        bad("[model] alpha_L/alpha_R belong to kind = \"imperfect\"")
    for name in ("alpha_L", "alpha_R"):
        if not 0 < getattr(m, name) <= 1:
            bad(f"[model] {name} must be in (0, 1], got {getattr(m, name)}")
    for name in ("e_L", "e_R"):
        v = getattr(m, name)
        if v is not None and not 0 <= v <= 1:
            bad(f"[model] {name} must be in [0, 1], got {v}")
    for name in ("theta_L", "theta_R"):
        v = getattr(m, name)
        if v is not None and not v > 0:
            bad(f"[model] {name} must be > 0 rad, got {v}")
    if not 0 < m.rtol < 1e-2:
        bad(f"[model] rtol must be in (0, 0.01), got {m.rtol}")
    pd = cfg.pedestal
    check_pedestal(pd, f"{where}: [pedestal]")
    if i.under == "pedestal" and pd.size is None and pd.file is None:
        bad('[isolator] under = "pedestal" needs a [pedestal] (its size and mass, or its file)')
    if i.mu is not None and not 0 <= i.mu < 0.5:
        bad(f"[isolator] mu must be in [0, 0.5), got {i.mu}")
    if i.enabled and (i.spectrum is None) == (i.motion is None):
        bad("[isolator] give exactly one of spectrum and motion")
    def named(fn, name, spec):
        try:
            return fn(spec)
        except InputError as exc:
            raise InputError(f"{where}: {name} = {quoted(spec)}: {exc}") from None

    if i.enabled and i.spectrum:
        named(parse_spectrum, "[isolator] spectrum", i.spectrum)
    def full_scale(name, motion):
        if getattr(motion, "froude_scale", 1.0) != 1.0:
            bad(f"{name}: the record is Froude-scaled for a 1:{motion.froude_scale:g} prototype (a scale= key or "
                "the file's header says so), and a run models the full-size statue of the scan: use the "
                "full-scale record")

    if i.enabled and i.motion:
        full_scale("[isolator] motion", named(parse_spec, "[isolator] motion", i.motion)[0])
    from ..isolator.layout import LAYOUTS

    counts = sorted({lay.n for lay in LAYOUTS.values()})
    if i.grooves is not None and i.grooves not in counts:
        bad(f"[isolator] grooves (the number of balls) must be one of {', '.join(map(str, counts))} or \"auto\", "
            f"got {i.grooves}")
    if i.layout != "auto" and i.grooves is not None and LAYOUTS[i.layout].n != i.grooves:
        bad(f"[isolator] layout {i.layout} has {LAYOUTS[i.layout].n} balls, not grooves = {i.grooves}")
    if i.surface != "auto" and i.ball_material != "auto":
        from ..isolator.bearing import BALLS_MATERIALS

        if i.surface not in BALLS_MATERIALS[i.ball_material].surfaces:
            bad(f"[isolator] {i.ball_material} balls are not an option on surface {i.surface} (resin balls roll on "
                "the wooden surfaces only, as the thesis tested them)")
    if not 0 <= i.extra_sets <= 10:
        bad(f"[isolator] extra_sets must be in 0..10, got {i.extra_sets}")
    if i.enabled and i.slc_spectrum:
        if not i.spectrum:
            bad("[isolator] slc_spectrum goes with a design spectrum, not a motion")
        from ..hazard.levels import collapse_spectrum_text

        named(lambda t: collapse_spectrum_text(i.spectrum, t), "[isolator] slc_spectrum", i.slc_spectrum)
    if not 16 <= i.segments <= 4096:
        bad(f"[isolator] segments must be in 16..4096, got {i.segments}")
    for name, v in (("mu_low", i.mu_low), ("mu_high", i.mu_high)):
        if v is not None and not 0 <= v < 0.5:
            bad(f"[isolator] {name} must be in [0, 0.5), got {v}")
    if i.mu is not None and i.mu_low is not None and i.mu_low > i.mu:
        bad(f"[isolator] mu_low ({i.mu_low}) must not exceed mu ({i.mu}): it is the lower friction bound")
    if i.mu is not None and i.mu_high is not None and i.mu_high < i.mu:
        bad(f"[isolator] mu_high ({i.mu_high}) must not be below mu ({i.mu}): it is the upper friction bound")
    if (i.mu_low is None) != (i.mu_high is None) and i.mu is None:
        bad("[isolator] give mu_low and mu_high together, or mu (the bounds then default about it)")
    if i.mu_low is not None and i.mu_high is not None and i.mu_low > i.mu_high:
        bad(f"[isolator] mu_low ({i.mu_low}) must not exceed mu_high ({i.mu_high})")
    # every physical key against its range (RANGES): a number that cannot be physical (a unit slip: height =
    # 1800 for 1.8 m; 1e9 storeys; a ball carrying 1e30 N) is refused here, in a second; an unusual one is a warning
    try:
        for sec in SECTIONS:
            warnings += check_ranges(sec, cfg.section(sec))
    except InputError as exc:
        bad(str(exc))
    if i.ball_capacity is not None:
        if i.surface == "auto":
            bad("[isolator] ball_capacity is a load test of one groove surface: name that surface with [isolator] "
                "surface")
    try:
        site(cfg)
    except InputError as exc:
        bad(str(exc))
    warnings += check_rooms(cfg, where)
    freqs = linspace_spec(d.freq, f"{where}: [dynamics] freq")
    amps = linspace_spec(d.amp, f"{where}: [dynamics] amp", accel=True)
    pgas = linspace_spec(d.pga, f"{where}: [dynamics] pga", accel=True)
    if np.any(freqs <= 0) or np.any(amps < 0) or np.any(pgas < 0):
        bad("[dynamics] frequencies must be > 0 and amplitudes, PGAs >= 0")
    grids = [("freq", d.freq, freqs), ("amp", d.amp, amps), ("pga", d.pga, pgas)]
    if d.fragility and str(d.fragility_levels).strip().lower() != "auto":
        grids.append(("fragility_levels", d.fragility_levels,
                      fragility_levels(d.fragility_levels, f"{where}: [dynamics] fragility_levels")))
    warnings += _check_grids(grids, where)
    if d.fragility:
        if not 2 <= d.fragility_records <= 100:
            bad(f"[dynamics] fragility_records must be in 2..100, got {d.fragility_records}")
        if d.fragility_duration is not None and not 5.0 <= d.fragility_duration <= 120.0:
            bad(f"[dynamics] fragility_duration must be in 5..120 s, got {d.fragility_duration}")
        if not 1 <= d.fragility_samples <= 1000:
            bad(f"[dynamics] fragility_samples must be in 1..1000, got {d.fragility_samples}")
        if not 0 <= d.fragility_rounds <= 10:
            bad(f"[dynamics] fragility_rounds must be in 0..10, got {d.fragility_rounds}")
        if str(d.fragility_levels).strip().lower() != "auto":
            fragility_levels(d.fragility_levels, f"{where}: [dynamics] fragility_levels")
    for name, spec, on in (("[dynamics] motion", d.motion, d.enabled), ("[crosscheck] motion", c.motion, c.enabled)):
        if not on:
            continue
        motion, theta0 = named(parse_spec, name, spec)
        full_scale(name, motion)
        if motion.kind == "none" or theta0 != 0 or not motion.pga > 0:
            bad(f"{name} must be a ground motion (not zero), got {quoted(spec)}")
        _check_sizes(name, motion, d, freqs, amps, pgas, where)
    if c.iterations < 1 or not c.pulse_freq > 0:
        bad("[crosscheck] iterations must be >= 1 and pulse_freq > 0 Hz")
    if not (math.isfinite(c.ensemble_budget) and c.ensemble_budget > 0):
        bad(f"[crosscheck] ensemble_budget must be a positive number of seconds, got {c.ensemble_budget}")
    from ..crosscheck.world import check_user_dt

    for name in ("dt", "statue_dt"):
        try:
            check_user_dt(f"[crosscheck] {name}", getattr(c, name))
        except InputError as exc:
            bad(str(exc))
    if not (c.grid == 0 or 0.0005 <= c.grid <= 0.05):
        bad(f"[crosscheck] grid must be 0 or in 0.5..50 mm, got {c.grid}")
    if r.workers is not None and r.workers < 1:
        bad(f"[run] workers must be >= 1, got {r.workers}")
    try:
        stage_list(r.stages)
    except InputError as exc:
        bad(f"[run] stages = {quoted(r.stages)}: {exc}")
    return warnings


def _check_grids(grids, where: str) -> list[str]:
    """The [dynamics] grids (name, text, levels in SI) against :data:`GRID_RANGES`: a grid without a
    positive level (``pga = "0g:0g:1"``: nothing would shake the statue, and the report would say it
    overturned at no level) or with an impossible level is an :class:`InputError`; the warnings of
    unusual levels (the largest and the smallest positive one) are returned."""
    from ..geometry.units import PLAUSIBLE

    out = []
    for key, text, levels in grids:
        levels = np.asarray(levels, dtype=float)
        if not np.any(levels > 0):
            raise InputError(f"{where}: [dynamics] {key} = {quoted(text)} has no positive level: "
                             f"give at least one level above 0 ({range_text('dynamics', key)})")
        r = PLAUSIBLE[GRID_RANGES[key]]
        k, u = (1 / G, "g") if r.unit == "m/s^2" else (1.0, f" {r.unit}")        # in the grid's own unit
        for x in (float(np.max(levels)), float(np.min(levels[levels > 0]))):
            if not r.hard_low <= x <= r.hard_high:
                raise InputError(f"{where}: [dynamics] {key} = {quoted(text)}: a level of {x * k:.4g}{u} is impossible for "
                                 f"{'an' if r.what[0] in 'aeiou' else 'a'} {r.what} ({range_text('dynamics', key)})")
            if not r.low <= x <= r.high:
                out.append(f"[dynamics] {key} = {quoted(text)}: a level of {x * k:.4g}{u} is unusual for "
                           f"{'an' if r.what[0] in 'aeiou' else 'a'} {r.what} ({range_text('dynamics', key)})")
                break
    return out


STAGE_NAMES = ("params", "prototype", "isolator", "dynamics", "crosscheck")
"""The stages of a run in their order (:data:`statue2model.pipeline.stages.STAGES` runs them)."""


def check_stage_names(names) -> list[str]:
    """``names`` as a list, or an :class:`InputError` naming the unknown ones and the known."""
    bad = [n for n in names if n not in STAGE_NAMES]
    if bad:
        raise InputError(f"unknown stage(s) {quoted(', '.join(bad), bare=True)}; stages are {', '.join(STAGE_NAMES)}")
    return list(names)


def stage_list(text: str) -> list[str]:
    """The stage names of a comma list (``"params, dynamics"``), or every stage for
    ``"all"``; an unknown name is an :class:`InputError` naming the known ones."""
    names = [n.strip() for n in str(text).split(",") if n.strip()]
    if names == ["all"]:
        return list(STAGE_NAMES)
    if not names:
        raise InputError("no stage named")
    return check_stage_names(names)


def _check_sizes(name: str, motion, d: DynamicsConfig, freqs, amps, pgas, where: str) -> None:
    """Refuse, before any work, analyses beyond the memory budget or the run cap
    (:mod:`statue2model.compute.budget`): the spectrum grids, the PGA levels (each level's task
    carries the record: levels x samples), the histories of the motion."""
    from ..compute.budget import check_bytes, check_history, check_runs, num
    from ..rocking.engine import FREE_TIME, HISTORY_BYTES_PER_SAMPLE
    from ..rocking.spectrum import BYTES_PER_RUN, check_grid

    def named(fn, *a, **kw):
        try:
            fn(*a, **kw)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None

    end = motion.end + FREE_TIME
    if name == "[dynamics] motion":
        named(check_grid, freqs.size, amps.size, "[dynamics] freq x amp (fixed base and isolated spectra)",
              "use fewer frequencies or amplitudes (the N of START:STOP:N)")
        samples = 0 if motion.samples is None else motion.samples.size
        named(check_runs, pgas.size, BYTES_PER_RUN, f"[dynamics] pga: {pgas.size} levels", "use fewer PGA levels")
        named(check_bytes, 8.0 * pgas.size * max(samples, 1), f"[dynamics] pga: {pgas.size} levels x {samples} "
              "samples of the motion (each level's task carries the record)", "use fewer PGA levels or a shorter motion")
        named(check_history, end, 0.005, 2 * HISTORY_BYTES_PER_SAMPLE, what="the time histories",
              head=f"[dynamics] motion of {num(motion.end)} s (+{num(FREE_TIME)} s free) sampled every 5 ms",
              fix="use a shorter motion")
    else:
        # the 2D threshold times of the cross-check sample the 2D history every 0.1 ms
        named(check_history, end, 1e-4, HISTORY_BYTES_PER_SAMPLE, what="the 2D histories",
              head=f"[crosscheck] motion of {num(motion.end)} s (+{num(FREE_TIME)} s free) sampled every 0.1 ms",
              fix="use a shorter motion")


def site(cfg: ProjectConfig):
    """The run's :class:`statue2model.hazard.site.SiteHazard`: the [isolator] spectrum (the default
    one of the verdict when the isolator designs on a motion) under the [building] section."""
    from ..assessment.verdict import DEFAULT_SPECTRUM
    from ..hazard.site import site_of

    return site_of(cfg, DEFAULT_SPECTRUM)


def default_toml() -> str:
    """The project file with every key at its default, and this module's notes on top; each physical key
    with its range beside it (:data:`RANGES`: ``storeys = "auto"  # usually 1 to 20; possible 1 to 200``)."""
    head = "\n".join("# " + line if line else "#" for line in __doc__.split("Example")[0].strip().splitlines())
    lines, sec = [], None
    for line in ProjectConfig().to_toml().splitlines():
        if line.startswith("["):
            sec = line.strip("[]")
        key = line.split("=", 1)[0].strip() if "=" in line and not line.startswith("[") else None
        if key and ((sec, key) in RANGES or (sec == "dynamics" and key in GRID_RANGES)):
            line += f"    # {range_text(sec, key)}"
        lines.append(line)
    return head + "\n\n" + "\n".join(lines) + "\n" + ROOMS_EXAMPLE


ROOMS_EXAMPLE = """
# Objects on other floors (a folder of scans; pipeline/rooms.py, docs/run.md):
# [rooms.gallery_2]                 # a room: the [building] keys that differ from [building]
# floor = 2
#
# [objects]                         # scan file name, its stem or a pattern -> a room, or [building] keys
# "maria_*" = "gallery_2"
# "dancing_girl.ply" = { floor = 1 }
#
# [values]                          # optional: the object's value (a price, or an importance 1-5):
# "dancing_girl.ply" = 5            # the collection ranks by risk x value
"""
