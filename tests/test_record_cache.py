"""The record sets kept between runs (pipeline/record_cache.py): read back bit for bit, keyed by
their matching arguments, a bad file matched again, switched off by the environment."""
import dataclasses

import numpy as np
import pytest

from statue2model.hazard.code_spectra import parse_spectrum
from statue2model.pipeline import record_cache as C
from statue2model.pipeline.stages import _match_now, _match_task

TARGET = parse_spectrum("ntc2018:ag=0.1g,F0=2.5,Tc=0.3,soil=C")


def _args(seed=1):
    return (TARGET, 2, 10.0, None, None, seed, "NTC")


class Counted:
    def __init__(self):
        self.calls = 0

    def __call__(self, args):
        self.calls += 1
        return _match_now(args)


def _same(a, b):
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if f.name == "records":
            assert len(x) == len(y)
            for u, v in zip(x, y):
                assert u.samples.dtype == v.samples.dtype and np.array_equal(u.samples, v.samples)
                for g in dataclasses.fields(u):
                    if g.name != "samples":
                        assert repr(getattr(u, g.name)) == repr(getattr(v, g.name)), g.name
        elif isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and np.array_equal(x, y), f.name
        else:
            assert repr(x) == repr(y) and type(x) is type(y), f.name


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(C.ENV, str(tmp_path / "sets"))
    return tmp_path / "sets"


def test_a_kept_set_is_read_back_bit_for_bit_without_matching(cache):
    match = Counted()
    a = C.matched(_args(), match)
    assert match.calls == 1 and len(list(cache.glob("*.npz"))) == 1
    b = C.matched(_args(), match)
    assert match.calls == 1            # read, not matched again
    _same(a, b)
    _same(_match_now(_args()), b)      # and it is the set matching gives
    assert a.to_dict() == b.to_dict()


def test_other_arguments_are_another_set(cache):
    match = Counted()
    a = C.matched(_args(1), match)
    b = C.matched(_args(11), match)
    assert match.calls == 2 and len(list(cache.glob("*.npz"))) == 2
    assert a.seeds != b.seeds
    assert C.set_key(_args(1)) != C.set_key(_args(11))


def test_a_bad_or_foreign_file_is_matched_again(cache):
    match = Counted()
    a = C.matched(_args(), match)
    (path,) = cache.glob("*.npz")
    path.write_bytes(b"not an npz")
    _same(a, C.matched(_args(), match))
    assert match.calls == 2
    # a valid file under another set's name: its key does not match, so it is not taken
    other = C.set_key(_args(11))
    path.replace(cache / f"{other}.npz")
    _same(C.matched(_args(11), match), _match_now(_args(11)))
    assert match.calls == 3


def test_off_keeps_nothing(tmp_path, monkeypatch):
    monkeypatch.setenv(C.ENV, "off")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    match = Counted()
    C.matched(_args(), match)
    C.matched(_args(), match)
    assert match.calls == 2 and not any(tmp_path.rglob("*.npz"))


def test_the_pipeline_task_goes_through_the_cache(cache):
    a = _match_task(_args())
    assert len(list(cache.glob("*.npz"))) == 1
    _same(a, _match_task(_args()))


def test_every_field_of_the_set_is_kept(cache):
    """A floor set's ``pga_cap`` (a field added after the cache was written) was dropped: a warm
    run read the set back with ``pga_cap`` None. Every RecordSet field is now kept by its name."""
    a = dataclasses.replace(_match_now(_args()), pga_cap=1.05, d_g=0.0123, sd_plateau=0.5)
    key = C.set_key(_args())
    C._to_file(cache / f"{key}.npz", key, a)
    b = C._from_file(cache / f"{key}.npz", key)
    assert b.pga_cap == 1.05
    _same(a, b)
