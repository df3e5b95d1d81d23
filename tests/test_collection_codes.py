"""The collection shows a device as passing, and counts its plates and price, only where the object's
recommendation code makes the isolator its protection (recommendation.CodeInfo.device): over every Code,
the row, the summary, collection.csv and the collection page agree (issue #24, item 7)."""
from __future__ import annotations

import csv
import io

import pytest

from statue2model.assessment.collection import csv_rows, object_row, rank, summary
from statue2model.assessment.recommendation import CODES, DEVICE_ROLES, Code, info
from statue2model.report.collection_page import render_collection_page

DEVICE = {"passed": True, "conditional": False, "R": 1.8, "r": 0.04, "n_grooves": 4, "T": 3.76, "cost": 1500.0}


def _result(code: Code) -> dict:
    name = code.value.lower()
    return {"scan": f"{name}.ply", "out": f"/m/out/{name}", "report": f"/m/out/{name}/report.html",
            "status": {"params": "done", "isolator": "done"}, "warnings": [],
            "data": {"params": {"a_min": 2.0, "weakest_deg": 0.0, "m": 100.0, "h": 0.5, "b_L": 0.2, "b_R": 0.2},
                     "isolator": {"passed": True}},
            "verdict": {"recommendation": "words", "code": code.value, "headline": f"headline {name}",
                        "fixed": {"lifts": True}, "isolated": dict(DEVICE), "hazard": {"pga": 2.5}}}


def test_every_code_has_a_device_role():
    assert set(CODES) == set(Code)
    assert all(c.device in DEVICE_ROLES for c in CODES.values())
    # a device counts only where the code asks for protection
    assert all(c.needs_protection for c in CODES.values() if c.device_counts)


@pytest.mark.parametrize("code", list(Code), ids=lambda c: c.value)
def test_a_device_passes_and_costs_only_where_the_code_counts_it(code):
    counted = info(code).device_counts
    row = rank([object_row(_result(code), "/m/out")])[0]
    assert row["code"] == code.value
    assert (row["device_state"] == "passed") is counted, row["device"]
    assert ("passes" in row["device"]) is counted, row["device"]
    assert row["cost"] == (1500.0 if counted else None)
    s = summary([row])
    assert s["devices_passed"] == int(counted) and s["isolator_plates"] == (2 if counted else 0)
    assert s["devices_cost"] == (1500.0 if counted else 0.0)
    if code in (Code.SLIDES, Code.PEDESTAL_OVERTURNS):        # a restraint or an anchorage, not "no device in range"
        assert row["device_state"] == "not applicable" and s["no_device"] == 0
    header, body = csv_rows([row])
    cells = dict(zip(header, next(csv.reader(io.StringIO(",".join(f'"{c}"' for c in body[0]))))))
    assert (cells["isolator"] == "passed") is counted and cells["isolator cost [EUR]"] == ("1500" if counted else "")
    page = render_collection_page([row], s, title="t")
    assert (": passes" in page) is counted


def test_the_summary_over_every_code_counts_the_counted_devices_only():
    rows = rank([object_row(_result(c), "/m/out") for c in Code])
    n = sum(info(c).device_counts for c in Code)
    s = summary(rows)
    assert n == 2                                   # ISOLATE, RUN_ISOLATED_DYNAMICS
    assert s["devices_passed"] == n and s["isolator_plates"] == 2 * n and s["devices_cost"] == 1500.0 * n
    assert f'id="sum-devices_cost"><span class="n">{1500 * n}</span>' in render_collection_page(rows, s, title="t")
