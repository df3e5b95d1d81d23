"""benchmarks/same_outputs.py, the check behind "outputs unchanged": it must pass two runs
that differ only in what every writer stamps anew, and fail on one changed digit."""
from __future__ import annotations

import importlib.util
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("same_outputs", ROOT / "benchmarks" / "same_outputs.py")
S = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(S)

DXF = """  0\nSECTION\n  2\nCLASSES\n  0\nCLASS\n  1\n{a}\n  0\nCLASS\n  1\n{b}\n  0\nENDSEC\n  9\n$TDCREATE\n 40\n{date}\n"""


def _write(d: Path, value: float, order=("LAYOUT", "ACDBPLACEHOLDER"), date="2461370.97", secs=1.5):
    d.mkdir()
    (d / "run.json").write_text(json.dumps({"seconds": secs, "verdict": {"margin": value},
                                            "stages": {"params": {"key": str(secs)}}}))
    (d / "a.dxf").write_text(DXF.format(a=order[0], b=order[1], date=date))
    (d / "b.txt").write_text(f"written on 2026-11-25 23:24 in {secs} s\nmargin {value!r}\n")


def test_noise_is_not_a_difference(tmp_path):
    _write(tmp_path / "old", 0.96368)
    _write(tmp_path / "new", 0.96368, order=("ACDBPLACEHOLDER", "LAYOUT"), date="2461371.01", secs=2.5)
    rows = S.compare(tmp_path / "old", tmp_path / "new")
    assert {v for _, v, _ in rows} <= {"same", "same numbers", "same content"}, rows


def test_one_digit_is_a_difference(tmp_path):
    _write(tmp_path / "old", 0.96368)
    _write(tmp_path / "new", 0.96369)
    rows = dict((n, (v, d)) for n, v, d in S.compare(tmp_path / "old", tmp_path / "new"))
    assert rows["run.json"][0] == "DIFFERS" and "margin" in rows["run.json"][1]
    assert rows["b.txt"][0] == "DIFFERS"
    assert S.main([str(tmp_path / "old"), str(tmp_path / "new")]) == 1


def test_a_missing_or_new_file_is_a_difference_unless_expected(tmp_path):
    _write(tmp_path / "old", 1.0)
    _write(tmp_path / "new", 1.0)
    (tmp_path / "new" / "body.npz").write_bytes(b"x")
    assert S.main([str(tmp_path / "old"), str(tmp_path / "new")]) == 1
    assert S.main([str(tmp_path / "old"), str(tmp_path / "new"), "--expect-new", "body.npz"]) == 0
