"""Every physical key of the project file and the options of the same quantities have a range in one
table (geometry/units.py PLAUSIBLE; pipeline/config.py RANGES): an impossible value is one line and exit
2, an unusual one a warning (issue #24, item 11)."""
from __future__ import annotations

import pytest

from statue2model.cli import build_parser
from statue2model.errors import InputError
from statue2model.geometry.units import PLAUSIBLE
from statue2model.pipeline.config import (GRID_RANGES, RANGES, SECTIONS, ProjectConfig, default_toml,
                                          load_config_text, range_text, validate)

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]


def _load(text):
    return load_config_text(text, "p.toml")


@pytest.mark.parametrize("text, says", [
    ('[isolator]\nsurface = "beech"\nball_capacity = 1e30\n', "ball_capacity = 1e+30 N is implausible"),
    ("[building]\nfloor = 1\nstoreys = 1000000000\nheight = 12\n", "storeys = 1e+09 is implausible"),
    ("[building]\nfloor = 1\nstoreys = 3\nheight = 40\n", "height / storeys (40 m / 3) = 13.33 m is implausible"),
    ("[building]\nfloor = 1\nstoreys = 12\nheight = 12\n", "height / storeys (12 m / 12) = 1 m is implausible"),
    ("[building]\nfloor = 1\nstoreys = 3\nheight = 12\n[rooms.top]\nfloor = 2\nstoreys = 40\n",
     "[rooms.top] height / storeys (12 m / 40) = 0.3 m is implausible"),
    ('[dynamics]\npga = "0g:0g:1"\n', "[dynamics] pga = '0g:0g:1' has no positive level"),
    ('[dynamics]\namp = "0g:0g:3"\n', "[dynamics] amp = '0g:0g:3' has no positive level"),
    ('[dynamics]\nfreq = "0.5:500:3"\n', "a level of 500 Hz is impossible"),
    ("[building]\nfloor = 1\nstoreys = 3\nheight = 12\nperiod = 60\n", "period = 60 s is implausible"),
    ("[building]\ndamping = 80\n", "damping = 80 % is implausible"),
    ("[isolator]\nmu_low = 0.001\nmu_high = 0.7\n", "mu_high"),
    ('[isolator]\nside_max = "10m"\n', "side_max = 10 m is implausible"),
    ("[sliding]\nmu_statue = 3\n", "mu_statue = 3 is implausible"),
    ("[pedestal]\nsize = [0.5, 0.5, 1.0]\nmass = 1e7\n", "mass"),
])
def test_impossible_values_stop_the_load_in_one_line(text, says):
    with pytest.raises(InputError) as exc:
        _load(text)
    msg = str(exc.value)
    assert says in msg and "\n" not in msg and msg.startswith("p.toml: "), msg


@pytest.mark.parametrize("text, says", [
    ("[isolator]\nmu = 0.2\n", "[isolator] mu = 0.2 is unusual for a rolling friction coefficient (0.001 to 0.05)"),
    ("[building]\nfloor = 1\nstoreys = 30\nheight = 100\nperiod = 1.5\n", "[building] storeys = 30 is unusual"),
    ('[dynamics]\npga = "0.05g:8g:10"\n', "a level of 8g is unusual for a ground acceleration"),
    ("[sliding]\nmu_statue = 1.2\n", "mu_statue = 1.2 is unusual"),
    ('[prototype]\nboard = "40mm"\n', "board = 0.04 m is unusual"),
])
def test_unusual_values_are_warnings(text, says):
    cfg = _load(text)
    assert any(says in w for w in cfg.warnings), cfg.warnings


def test_the_defaults_and_the_default_file_are_usual():
    assert validate(ProjectConfig()) == []
    text = default_toml()
    assert _load(text).warnings == ()
    assert 'storeys = "auto"    # usually 1 to 20; possible 1 to 200' in text


def test_every_physical_key_has_a_documented_range():
    doc = (ROOT / "docs" / "run.md").read_text()
    for (sec, key), quantity in RANGES.items():
        assert sec in SECTIONS and quantity in PLAUSIBLE
        assert f"| `[{sec}] {key}` |" in doc and range_text(sec, key) in doc, (sec, key)
    for key in GRID_RANGES:
        assert f"| `[dynamics] {key}` (each level) |" in doc


@pytest.mark.parametrize("argv, says", [
    (["isolator", "design", "p.json", "--spectrum", "ec8:ag=0.25g,ground=C", "--surface", "steel_race",
      "--ball-capacity", "1e12", "--json", "o.json"], "implausible"),
    (["isolator", "design", "p.json", "--spectrum", "ec8:ag=0.25g,ground=C", "--mu", "0.7", "--json", "o.json"],
     "implausible for a rolling friction"),
    (["isolator", "design", "p.json", "--spectrum", "ec8:ag=0.25g,ground=C", "--side-max", "20m", "--json", "o.json"],
     "implausible for a largest plate side"),
    (["isolator", "simulate", "--R", "0.3", "--r", "0.02", "--mass", "20", "--mu", "0.01", "--e-stop", "1.5",
      "--motion", "free:u0=0.01", "--json", "o.json"], "implausible for a coefficient of restitution"),
])
def test_cli_options_read_the_same_table(argv, says, capsys):
    with pytest.raises(SystemExit) as exc:
        build_parser().parse_args(argv)
    assert exc.value.code == 2 and says in capsys.readouterr().err


def test_cli_unusual_option_is_a_warning(capsys):
    args = build_parser().parse_args(["isolator", "design", "p.json", "--spectrum", "ec8:ag=0.25g,ground=C",
                                      "--mu", "0.2", "--json", "o.json"])
    assert args.mu == 0.2
    assert "statue2model: warning: --mu 0.2 is unusual for a rolling friction coefficient" in capsys.readouterr().err
