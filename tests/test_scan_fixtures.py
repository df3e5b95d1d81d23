"""Every defect fixture of scan_fixtures gives its closed-form answer, or is refused
with a line that names the defect; the warnings a fixture must raise are raised."""
import pytest

from scan_fixtures import defect_cases, expected_a_min
from statue2model.errors import InputError
from statue2model.geometry.body import body_from_mesh

CASES = defect_cases()


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=[c.defect for c in CASES])
def test_defect_fixture(case):
    if case.expect == "refused":
        with pytest.raises(InputError, match=case.refusal):
            body_from_mesh(case.vertices, case.faces, **case.options)
        return
    body = body_from_mesh(case.vertices, case.faces, **case.options)
    rose = body.rose()
    p = body.rocking(rose.weakest_deg)
    got = {"volume": body.mass.volume, "h": p.h, "b_L": p.b_L, "b_R": p.b_R, "I_G": p.I_G, "a_min": rose.a_min}
    for key, want in case.reference.items():
        assert got[key] == pytest.approx(want, rel=case.tolerance), key
    closed_form = expected_a_min(case, body)
    if closed_form is not None:
        assert rose.a_min == pytest.approx(closed_form, rel=0.15)
    if case.warns:
        assert any(case.warns in w for w in body.warnings), body.warnings
    else:
        assert not any("uncertain base contact" in w for w in body.warnings), body.warnings
