"""Objects on different floors of one museum: [rooms.NAME] and [objects] (issue #29, item 4).

Cheap: the project file is parsed, never run. The design PGAs are checked against EN 1998-1
eq. 4.25 by hand: a rigid object (T_a = 0) at height z of a building of height H takes
S_a = a_g S (1 + 1.5 z / H); the default site, EC8 type 1 ground C at a_g = 0.25 g, has S = 1.15.
"""
from __future__ import annotations

import pytest

from statue2model.errors import InputError
from statue2model.pipeline.cache import stage_key
from statue2model.pipeline.config import ProjectConfig, default_toml, load_config, load_config_text, site
from statue2model.pipeline.rooms import check_scans, config_for, object_placement, room_of
from statue2model.pipeline.run import write_config
from statue2model.pipeline.stages import DEPENDS

BUILDING = '[building]\nstoreys = 3\nheight = "12m"\n'
MUSEUM = BUILDING + """
[rooms.gallery_2]
floor = 2

[rooms."Sala 3"]          # the roof gallery of a concrete annex
floor = 3
structure = "concrete-frame"

[objects]
"maria_*" = "gallery_2"
"dancing_girl.ply" = { floor = 1 }
"NEF*" = "Sala 3"
"""
G_SPECTRUM = 9.80665               # the g of "ag=0.25g" in a spectrum
G_TABLE = 9.81                     # the g of the collection's columns (statue2model.quantities.G)
GROUND_PGA_G = 0.25 * G_SPECTRUM * 1.15 / G_TABLE


@pytest.fixture(scope="module")
def museum() -> ProjectConfig:
    return load_config_text(MUSEUM, "museum.toml")


def test_rooms_parse_as_building_keys(museum):
    assert dict(museum.rooms) == {"gallery_2": (("floor", 2),),
                                  "Sala 3": (("floor", 3), ("structure", "concrete-frame"))}
    assert dict(museum.objects)["dancing_girl.ply"] == (("floor", 1),)
    # a room's values go through [building]'s converters: "12m" -> 12.0, "auto" -> None
    cfg = load_config_text(BUILDING + '[rooms.annex]\nheight = "9000mm"\nperiod = "auto"\n', "p")
    assert dict(cfg.rooms)["annex"] == (("height", 9.0), ("period", None))


def test_config_for_each_object(museum):
    maria = config_for(museum, "maria_barjatinskaja.ply")
    assert (maria.building.floor, maria.building.storeys, maria.building.height) == (2, 3, 12.0)
    assert config_for(museum, "dancing_girl.ply").building.floor == 1
    by_stem = load_config_text(BUILDING + "[objects]\ndancing_girl = { floor = 1 }\n", "p")
    assert config_for(by_stem, "dancing_girl.ply").building.floor == 1     # the stem names it too
    sala = config_for(museum, "Nefertiti.PLY").building                      # case does not matter
    assert (sala.floor, sala.structure) == (3, "concrete-frame")
    other = config_for(museum, "venus.stl")                                  # no key: [building]
    assert other.building == museum.building and other.building.floor == 0
    # the table is applied and dropped: applying it again changes nothing
    assert maria.rooms == () and maria.objects == ()
    assert config_for(maria, "maria_barjatinskaja.ply") == maria
    assert config_for(ProjectConfig(), "x.ply") == ProjectConfig()
    # only the file name counts, never a folder of a path
    assert config_for(museum, "/data/maria_x/venus.ply").building.floor == 0


def test_design_pga_per_room(museum):
    """Two objects in different rooms get different design targets: eq. 4.25 by hand."""
    ground = site(config_for(museum, "venus.ply")).pga / G_TABLE
    first = site(config_for(museum, "dancing_girl.ply")).pga / G_TABLE
    second = site(config_for(museum, "maria_barjatinskaja.ply")).pga / G_TABLE
    assert ground == pytest.approx(GROUND_PGA_G, rel=1e-9)                  # 0.2874 g
    assert first == pytest.approx(GROUND_PGA_G * (1 + 1.5 * 1 / 3), rel=1e-6)
    assert second == pytest.approx(GROUND_PGA_G * (1 + 1.5 * 2 / 3), rel=1e-6)


def test_object_placement(museum):
    p = object_placement(museum, "maria_barjatinskaja.ply")
    assert {k: p[k] for k in ("room", "key", "floor", "storeys", "height", "on_floor")} == {
        "room": "gallery_2", "key": "maria_*", "floor": 2, "storeys": 3, "height": 12.0, "on_floor": True}
    assert p["pga_g"] == pytest.approx(2.0 * GROUND_PGA_G, rel=1e-6)
    inline = object_placement(museum, "dancing_girl.ply")
    assert (inline["room"], inline["key"], inline["floor"]) == (None, "dancing_girl.ply", 1)
    none = object_placement(museum, "venus.ply")
    assert (none["room"], none["key"], none["floor"], none["on_floor"]) == (None, None, 0, False)
    assert none["pga_g"] == pytest.approx(GROUND_PGA_G, rel=1e-9)


def test_stage_keys_follow_the_room(museum):
    """An object moved to another floor is computed again from the isolator on; its scan
    properties (params) are not."""
    def key(cfg, stage):
        return stage_key(stage, {"config": {s: cfg.section(s) for s in DEPENDS[stage][2]}})

    a, b = config_for(museum, "maria_a.ply"), config_for(museum, "dancing_girl.ply")
    same = config_for(museum, "maria_b.ply")
    for stage in ("isolator", "dynamics", "crosscheck"):
        assert key(a, stage) != key(b, stage)
        assert key(a, stage) == key(same, stage)
    assert key(a, "params") == key(b, "params")
    # the table itself is in no stage's key: another object's room changes nothing here
    moved = load_config_text(MUSEUM.replace('"maria_*" = "gallery_2"', '"maria_*" = "Sala 3"'), "p")
    assert key(config_for(moved, "dancing_girl.ply"), "dynamics") == key(b, "dynamics")


def test_round_trip(museum, tmp_path):
    text = museum.to_toml()
    assert '[rooms."Sala 3"]' in text and '"maria_*" = "gallery_2"' in text
    again = load_config_text(text, "museum.toml")
    assert again == museum and again.to_toml() == text
    path = write_config(museum, tmp_path / "config.toml")
    assert load_config(path).rooms == museum.rooms and load_config(path).objects == museum.objects
    d = museum.to_dict()
    assert d["rooms"]["gallery_2"] == {"floor": 2} and d["objects"]["dancing_girl.ply"] == {"floor": 1}
    assert "rooms" not in ProjectConfig().to_dict() and "[rooms" not in ProjectConfig().to_toml()
    # the file's order has no meaning
    swapped = MUSEUM.replace('"maria_*" = "gallery_2"\n"dancing_girl.ply" = { floor = 1 }',
                             '"dancing_girl.ply" = { floor = 1 }\n"maria_*" = "gallery_2"')
    assert swapped != MUSEUM and load_config_text(swapped, "museum.toml") == museum


def test_default_toml_shows_the_table():
    text = default_toml()
    assert '# [rooms.gallery_2]' in text and '# "maria_*" = "gallery_2"' in text
    cfg = load_config_text(text, "default")
    assert cfg.rooms == () and cfg.objects == ()
    # the commented example, uncommented, is a valid table (over a building with storeys)
    tail = text.split("# Objects on other floors")[1].splitlines()[1:]
    example = "\n".join(line[2:] for line in tail)
    cfg = load_config_text(BUILDING + example, "example")
    assert config_for(cfg, "maria_barjatinskaja.ply").building.floor == 2


@pytest.mark.parametrize("text, message", [
    ('[rooms.g]\nflor = 2\n', "p.toml: unknown key 'flor' in [rooms.g] (did you mean 'floor'?)"),
    ('[rooms.g]\nfloor = 1.5\n', "p.toml: [rooms.g] floor = 1.5: must be a whole number"),
    ('[rooms.g]\nstructure = "wood"\n', "p.toml: [rooms.g] structure = 'wood': must be one of masonry"),
    ('[rooms.g]\nfloor = 7\n', "p.toml: [rooms.g] (the [building] with its keys): floor must be a whole number "
                               "from 0 (the ground floor) to 3"),
    ('[rooms]\ng = 2\n', "p.toml: [rooms] g = 2: a room is a table [rooms.g] of [building] keys"),
    ('[objects]\na = "nowhere"\n', "p.toml: [objects] a = 'nowhere': unknown room (the file defines no"),
    ('[rooms.g]\nfloor = 2\n[objects]\na = "gg"\n', "p.toml: [objects] a = 'gg': unknown room (did you mean 'g'?)"),
    ('[objects]\na = 3\n', "p.toml: [objects] a = 3: give a room name"),
    ('[objects]\n"../x.ply" = { floor = 1 }\n', "p.toml: [objects] \"../x.ply\": a key is a scan's file name or a "
                                                "pattern on it, not a path"),
    ('[objects]\na = { stories = 3 }\n', "p.toml: unknown key 'stories' in [objects.a] (did you mean 'storeys'?)"),
    ('[objects.a]\nisolated = 1\n', "p.toml: [objects.a] isolated = 1: must be true or false"),
    ('[room.g]\nfloor = 1\n', "p.toml: unknown section [room] (did you mean [rooms]?)"),
])
def test_errors_name_the_table_and_key(text, message):
    with pytest.raises(InputError) as exc:
        load_config_text(BUILDING + text, "p.toml")
    assert str(exc.value).startswith(message) and "\n" not in str(exc.value)


def test_a_room_needs_its_building():
    with pytest.raises(InputError, match=r"^p.toml: \[rooms.g\] \(the \[building\] with its keys\): .*storeys"):
        load_config_text('[rooms.g]\nfloor = 2\n', "p.toml")
    # a second building of the museum is a room with its own storeys and height
    cfg = load_config_text('[rooms.annex]\nfloor = 1\nstoreys = 2\nheight = 8.0\n[objects]\n"*" = "annex"\n', "p")
    assert site(config_for(cfg, "x.ply")).pga / G_TABLE == pytest.approx(GROUND_PGA_G * 1.75, rel=1e-6)


def test_two_rooms_for_one_scan_and_unmatched_keys():
    cfg = load_config_text(BUILDING + '[rooms.a]\nfloor = 1\n[rooms.b]\nfloor = 2\n[objects]\n'
                           '"m*" = "a"\n"*a*" = "b"\n"maria.ply" = "b"\n"venus*" = "a"\n"v*" = "a"\n', "p")
    assert room_of(cfg, "maria.ply")[:2] == ("b", "maria.ply")     # an exact name wins over patterns
    assert room_of(cfg, "venus.ply")[:2] == ("a", "v*")            # two patterns, one room: fine
    with pytest.raises(InputError) as exc:
        config_for(cfg, "mab.ply")
    assert str(exc.value) == ("[objects]: scan 'mab.ply' is placed by both \"*a*\" = \"b\" and \"m*\" = \"a\"; keep "
                              "one of them, or name the scan exactly (an exact name wins over a pattern)")
    with pytest.raises(InputError, match="placed by both"):
        check_scans(cfg, ["maria.ply", "mab.ply"])
    warnings = check_scans(cfg, ["maria.ply", "venus.ply"])
    assert warnings == []
    assert check_scans(cfg, ["maria.ply"]) == ['[objects] "v*" matches no scan of the folder',
                                               '[objects] "venus*" matches no scan of the folder']


def test_the_example_of_docs_run_md():
    """The ```toml block of docs/run.md's "Objects on other floors" reads as it says."""
    import re
    from pathlib import Path

    page = (Path(__file__).resolve().parents[1] / "docs" / "run.md").read_text(encoding="utf-8")
    section = page[page.index("### Objects on other floors"):]
    cfg = load_config_text(re.search(r"^```toml\n(.*?)^```", section, re.S | re.M).group(1), "run.md")
    sala = config_for(cfg, "nefertiti.ply").building
    assert (sala.floor, sala.structure, sala.storeys) == (3, "concrete-frame", 3)
    assert [object_placement(cfg, n)["floor"] for n in ("maria_b.ply", "dancing_girl.ply", "venus.ply")] == [2, 1, 0]
