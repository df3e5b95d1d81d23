"""One vocabulary for the limit states (issue [21]): the registry in assessment/states.py is the only
place that lists them; every module reads it. A rule with a test that proves it can fail."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

from statue2model.assessment import states
from statue2model.assessment.fragility import ADAPT_ORDER, FIXED, ISOLATED, LABELS, LIMIT_STATE_CURVES

ROOT = Path(__file__).resolve().parents[1] / "statue2model"
REGISTRY_FILE = ROOT / "assessment" / "states.py"
SPELLINGS = set(states.IDS) | set(states.CURVE_LABELS)
"""What a module may not list on its own: the limit states' identifiers and the curve keys."""
RETIRED = {"uplift_isolated", "overturn_isolated", "failure_isolated"}
"""Spellings of a limit state's curve before the registry: none may come back."""


def stray_lists(source: str) -> list[tuple[int, list[str]]]:
    """(line, spellings) of every tuple, list, set or dict literal of ``source`` that holds two or more
    limit-state spellings (a module listing the states itself instead of reading the registry), and of
    every retired spelling."""
    out = []
    for node in ast.walk(ast.parse(source)):
        elts = node.keys if isinstance(node, ast.Dict) else node.elts if isinstance(
            node, (ast.Tuple, ast.List, ast.Set)) else None
        if elts:
            found = [e.value for e in elts if isinstance(e, ast.Constant) and e.value in SPELLINGS]
            if len(found) >= 2:
                out.append((node.lineno, found))
        if isinstance(node, ast.Constant) and node.value in RETIRED:
            out.append((node.lineno, [node.value]))
    return out


def test_the_rule_can_fail():
    bad = 'TITLES = {"full_contact": "full contact", "overturning": "overturning"}\nx = "failure_isolated"\n'
    assert stray_lists(bad) == [(1, ["full_contact", "overturning"]), (2, ["failure_isolated"])]
    assert stray_lists('for s in ("full_contact", "rocking"):\n    pass\n')
    assert not stray_lists('row = {"name": "full_contact", "base": "fixed"}\nTITLES = {s.id: s.title for s in R}\n')


def test_no_module_lists_the_limit_states_itself():
    hits = {}
    for p in sorted(ROOT.rglob("*.py")):
        if p == REGISTRY_FILE:
            continue
        found = stray_lists(p.read_text(encoding="utf-8"))
        if found:
            hits[str(p.relative_to(ROOT.parent))] = found
    assert not hits, f"spell the limit states through assessment/states.py, not here: {hits}"


def test_the_registry_is_coherent():
    assert states.IDS == ("full_contact", "sliding", "rocking", "overturning", "pedestal_sliding",
                          "pedestal_overturning", "capacity", "bearing")
    for s in states.REGISTRY:
        assert set(s.bases) <= set(states.BASES) and s.title and s.noun and s.exceeded_words
        for base, key in s.curves.items():
            assert base in s.bases and key == f"{s.id}_{base}"
    # every fragility curve is named <limit state>_<base> (or its component, overturning alone)
    assert set(FIXED) | set(ISOLATED) == set(LABELS) == set(states.STATE_OF_CURVE)
    for key, (sid, base) in states.STATE_OF_CURVE.items():
        assert key.startswith(sid + "_") and key.endswith("_" + base)
    assert LIMIT_STATE_CURVES == {s.id: s.curves for s in states.REGISTRY if s.curves}
    assert set(ADAPT_ORDER) <= set(LABELS)
    assert states.CLASSIFIED == ("full_contact", "overturning", "capacity")
    with pytest.raises(KeyError, match="unknown limit state 'uplift'"):
        states.get("uplift")


def test_one_g_written_once():
    """g is written in one place (statue2model/quantities.py: G for what the tool computes and prints,
    G_STANDARD for accelerogram files in g and the codes' spectra); no module types 9.81 or 9.80665 in
    its code (a doctest may). Issue [21]: reports printed g with either value."""
    import re

    hits = []
    for p in sorted(ROOT.rglob("*.py")):
        if p.name == "quantities.py":
            continue
        for k, line in enumerate(p.read_text(encoding="utf-8").splitlines(), start=1):
            code = line.split("#", 1)[0]
            if ">>>" in line or line.lstrip().startswith("..."):
                continue
            if re.search(r"(?<![\d.])9\.8(1|0665)(?!\d)", code) and '("kgf", 9.80665)' not in code:
                hits.append(f"{p.relative_to(ROOT.parent)}:{k}")
    assert not hits, f"use quantities.G or G_STANDARD: {hits}"
