"""Ground motions (MODEL.md section 5): pulses, SPEC strings, record files,
scaling, shake-table displacement.

References are closed forms written out here (not the module's code):
one-cosine a cos(w t), one-sine a sin(w t) and N-cycle sine trains on
[start, start + duration), rectangular pulses, linear interpolation of records,
Froude scaling (accelerations kept, times / sqrt(lambda)), PEER .AT2 in g with
g = 9.80665, and the double integrals of the pulses with the linear baseline
c0 + c1 t that brings the table back to rest.
"""
import math

import numpy as np
import pytest

from statue2model.hazard import motions as M
from statue2model.errors import InputError

G_FILE = 9.80665  # g of accelerogram files (PEER)
G_SPEC = 9.81  # g of the "0.3g" suffix in SPEC strings


# --- pulses: values at known times ---------------------------------------------------
def test_cosine_pulse_values():
    A, f = 2.5, 2.0
    m = M.cosine_pulse(A, f)
    assert m.end == 0.5 and m.start == 0.0
    # quarter periods: +A, 0, -A, 0; right-continuous: 0 at the end time and after
    t = np.array([0.0, 0.125, 0.25, 0.375, 0.5, 0.5 + 1e-12, 0.7, 10.0, -0.1])
    ref = np.array([A, 0.0, -A, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(m.acc(t), ref, rtol=0, atol=1e-14 * A)
    assert m.acc(0.0) == pytest.approx(A, rel=1e-15)  # starts at +amp
    assert m.acc(0.5 - 1e-9) == pytest.approx(A, rel=1e-12)  # left limit at the end: a cos(2 pi) = a
    tt = np.linspace(0.0, 0.5, 1001)[:-1]
    np.testing.assert_allclose(m.acc(tt), A * np.cos(2 * np.pi * f * tt), rtol=0, atol=1e-13 * A)


def test_sine_pulse_lasts_one_period():
    A, f = -1.7, 4.0
    m = M.sine_pulse(A, f)
    assert m.end == pytest.approx(1.0 / f, rel=1e-15)
    t = np.array([0.0, 1 / 16, 1 / 8, 3 / 16, 0.25, 0.3, -1e-9])
    np.testing.assert_allclose(m.acc(t), [0.0, A, 0.0, -A, 0.0, 0.0, 0.0], rtol=0, atol=1e-14)
    tt = np.linspace(0.0, 0.25, 777, endpoint=False)
    np.testing.assert_allclose(m.acc(tt), A * np.sin(2 * np.pi * f * tt), rtol=0, atol=1e-13)


def test_pulse_with_start_offset():
    A, f, s = 3.0, 2.0, 0.3
    m = M.cosine_pulse(A, f, start=s)
    assert m.end == pytest.approx(s + 0.5)
    assert m.acc(s - 1e-9) == 0.0  # at rest before the start
    assert m.acc(s) == pytest.approx(A)  # right-continuous at the start
    assert m.acc(s + 0.25) == pytest.approx(-A)
    assert m.acc(s + 0.5) == 0.0
    tt = s + np.linspace(0.0, 0.5, 101)[:-1]
    np.testing.assert_allclose(m.acc(tt), A * np.cos(2 * np.pi * f * (tt - s)), atol=1e-13)


def test_rect_pulse_values():
    A, d = -0.8, 0.25
    m = M.rect_pulse(A, d, start=0.1)
    assert m.end == pytest.approx(0.35)
    t = np.array([0.0, 0.1 - 1e-12, 0.1, 0.2, 0.35 - 1e-12, 0.35, 0.5])
    np.testing.assert_array_equal(m.acc(t), [0.0, 0.0, A, A, A, 0.0, 0.0])
    assert m.extremes() == (0.0, A) and m.pga == -A


def test_sine_train_values_and_end():
    A, f, n = 1.2, 2.0, 3
    m = M.sine_train(A, f, n)
    assert m.end == pytest.approx(1.5)
    tt = np.linspace(0.0, 1.5, 3001)[:-1]
    np.testing.assert_allclose(m.acc(tt), A * np.sin(2 * np.pi * f * tt), atol=1e-12)
    # peaks of every cycle; zero at and after the end
    for k in range(n):
        assert m.acc(k / f + 0.125) == pytest.approx(A)
        assert m.acc(k / f + 0.375) == pytest.approx(-A)
    assert m.acc(1.5) == 0.0 and m.acc(2.0) == 0.0


@pytest.mark.parametrize("make, hi, lo", [
    (lambda: M.cosine_pulse(2.0, 1.0), 2.0, -2.0),
    (lambda: M.cosine_pulse(-2.0, 1.0), 2.0, -2.0),
    (lambda: M.sine_pulse(3.5, 7.0), 3.5, -3.5),
    (lambda: M.sine_train(1.5, 2.0, 0.5), 1.5, 0.0),  # half a sine: never negative
    (lambda: M.sine_train(1.5, 2.0, 0.75), 1.5, -1.5),
    (lambda: M.sine_train(-1.5, 2.0, 0.25), 0.0, -1.5),  # a quarter, rising to its peak at the end
    (lambda: M.sine_train(1.0, 2.0, 10), 1.0, -1.0),
    (lambda: M.rect_pulse(0.4, 1.0), 0.4, 0.0),
    (lambda: M.free(), 0.0, 0.0),
    (lambda: M.record([0.0, 2.0, -3.0, 1.0], 0.01), 2.0, -3.0),
    (lambda: M.record([1.0, 2.0], 0.01), 2.0, 0.0),  # zero outside counts
])
def test_extremes_and_pga_exact(make, hi, lo):
    m = make()
    assert m.extremes() == (hi, lo)
    assert m.pga == max(hi, -lo)


def test_record_breakpoints_linear_and_right_continuous():
    m = M.record([1.0, 3.0, -2.0], 0.1, start=0.2)
    t = np.array([0.1, 0.2, 0.25, 0.3, 0.35, 0.4 - 1e-12, 0.4, 0.5])
    np.testing.assert_allclose(m.acc(t), [0.0, 1.0, 2.0, 3.0, 0.5, -2.0, 0.0, 0.0], atol=1e-9)
    assert m.end == pytest.approx(0.4)


def test_record_keeps_its_own_copy():
    a = np.array([0.0, 1.0, 2.0])
    m = M.record(a, 0.01)
    a[1] = 99.0
    assert m.samples[1] == 1.0
    with pytest.raises(ValueError):
        m.samples[0] = 5.0  # read-only


# --- scaling ---------------------------------------------------------------------------
def test_scaled_to_pga():
    m = M.cosine_pulse(-1.0, 2.0).scaled_to_pga(3.3)
    assert m.amp == pytest.approx(-3.3) and m.pga == pytest.approx(3.3)
    r = M.record([0.0, 0.5, -2.0, 1.0], 0.02).scaled_to_pga(1.0)
    np.testing.assert_allclose(r.samples, [0.0, 0.25, -1.0, 0.5])
    assert r.dt == 0.02 and r.pga == pytest.approx(1.0)
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(InputError, match="PGA"):
            M.sine_pulse(1.0, 1.0).scaled_to_pga(bad)
    with pytest.raises(InputError, match="zero"):
        M.free().scaled_to_pga(1.0)


@pytest.mark.parametrize("lam", [2.0, 4.0, 0.5])
def test_froude_scaling(lam):
    r = math.sqrt(lam)
    m = M.cosine_pulse(2.0, 1.5, start=0.2)
    p = m.froude(lam)
    assert p.amp == m.amp and p.extremes() == m.extremes()
    assert p.freq == pytest.approx(1.5 * r)
    assert p.start == pytest.approx(0.2 / r) and p.end == pytest.approx(m.end / r)
    t = np.linspace(0.0, 1.0, 301)
    np.testing.assert_allclose(p.acc(t / r), m.acc(t), atol=1e-12)  # same accelerations at times / sqrt(lam)
    rec = M.record([0.0, 1.0, -1.0, 0.5], 0.01, start=0.05)
    q = rec.froude(lam)
    np.testing.assert_array_equal(q.samples, rec.samples)
    assert q.dt == pytest.approx(0.01 / r) and q.start == pytest.approx(0.05 / r)
    assert q.end == pytest.approx(rec.end / r)
    rc = M.rect_pulse(1.0, 0.4).froude(lam)
    assert rc.end == pytest.approx(0.4 / r) and rc.amp == 1.0


def test_froude_rejects_bad_lambda():
    for bad in (0.0, -2.0, math.nan):
        with pytest.raises(InputError, match="lambda"):
            M.sine_pulse(1.0, 1.0).froude(bad)


# --- SPEC strings ---------------------------------------------------------------------
def test_parse_spec_pulses():
    m, th = M.parse_spec("free:theta0=0.05")
    assert m.kind == "none" and th == 0.05 and m.pga == 0.0
    m, th = M.parse_spec("cosine:amp=0.3g,freq=2")
    assert th == 0.0 and m.kind == "harmonic"
    assert m.amp == pytest.approx(0.3 * G_SPEC, rel=1e-15) and m.freq == 2.0 and m.end == 0.5
    assert m.acc(0.0) == pytest.approx(0.3 * G_SPEC)  # a cosine
    m, _ = M.parse_spec("COSINE: amp = 2.5 m/s^2 , freq = 2 , start = 0.1")
    assert m.amp == 2.5 and m.start == 0.1 and m.acc(0.1) == pytest.approx(2.5)
    m, _ = M.parse_spec("sine:amp=-1.2m/s2,freq=3")
    assert m.amp == -1.2 and m.end == pytest.approx(1 / 3) and m.acc(0.0) == 0.0
    assert m.acc(1 / 12) == pytest.approx(-1.2)
    m, _ = M.parse_spec("rect:amp=0.2G,dur=0.25")
    assert m.kind == "rect" and m.amp == pytest.approx(0.2 * G_SPEC) and m.end == 0.25
    m, _ = M.parse_spec("sines:amp=1M/S2,freq=2,cycles=3")
    assert m.end == pytest.approx(1.5) and m.acc(1.375) == pytest.approx(-1.0)


def _write_two_column(path, t, a, sep=",", header="time,acc"):
    lines = ([header] if header else []) + [f"{float(x)!r}{sep}{float(y)!r}" for x, y in zip(t, a)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_parse_spec_file_forms(tmp_path):
    t = 0.01 * np.arange(5)
    a = np.array([0.0, 1.0, -2.0, 0.5, 0.0])
    _write_two_column(tmp_path / "rec.csv", t, a)
    (tmp_path / "one.txt").write_text("\n".join(repr(float(x)) for x in a) + "\n")

    m, th = M.parse_spec("file:path=rec.csv", base_dir=tmp_path)
    assert th == 0.0 and m.kind == "record" and m.dt == pytest.approx(0.01)
    np.testing.assert_array_equal(m.samples, a)
    m, _ = M.parse_spec(f"file:path={tmp_path / 'one.txt'},dt=0.02")  # absolute path, one column
    assert m.dt == 0.02 and len(m.samples) == 5
    m, _ = M.parse_spec("file:path=rec.csv,pga=0.5g", base_dir=tmp_path)
    assert m.pga == pytest.approx(0.5 * G_SPEC)
    np.testing.assert_allclose(m.samples, a * 0.5 * G_SPEC / 2.0)
    m, _ = M.parse_spec("file:path=rec.csv,scale=1:2", base_dir=tmp_path)
    assert m.dt == pytest.approx(0.01 / math.sqrt(2)) and m.pga == 2.0
    m, _ = M.parse_spec("file:path=rec.csv,units=g", base_dir=tmp_path)
    np.testing.assert_allclose(m.samples, a * G_FILE, rtol=1e-15)
    m, _ = M.parse_spec("file:path=one.txt,dt=0.02,pga=1m/s2,scale=1:4,units=g", base_dir=tmp_path)
    assert m.pga == pytest.approx(1.0) and m.dt == pytest.approx(0.01)


def test_parse_spec_synthetic():
    m, th = M.parse_spec("synthetic:duration=5,dt=0.005,pga=0.2g,seed=3,fg=3")
    assert th == 0.0 and m.kind == "record"
    assert m.dt == 0.005 and len(m.samples) == 1001 and m.end == pytest.approx(5.0)
    assert m.pga == pytest.approx(0.2 * G_SPEC, rel=1e-12)
    d, _ = M.parse_spec("synthetic")
    assert d.dt == 0.01 and d.end == pytest.approx(20.0) and d.pga == pytest.approx(0.3 * G_SPEC)


@pytest.mark.parametrize("spec, word", [
    ("quake:amp=1", "unknown motion kind"),
    ("", "unknown motion kind"),
    ("cosine:amp=1", "missing freq"),
    ("cosine:freq=2", "missing amp"),
    ("cosine", "missing"),
    ("rect:amp=1", "missing dur"),
    ("sines:amp=1,freq=2", "missing cycles"),
    ("file:dt=0.01", "missing path"),
    ("free:", "missing theta0"),
    ("cosine:amp=1g,freq=2,dur=3", "unknown key"),
    ("free:theta0=0.1,amp=1", "unknown key"),
    ("synthetic:amp=1", "unknown key"),
    ("cosine:amp=1g,freq=2,amp=2g", "twice"),
    ("cosine:amp,freq=2", "key=value"),
    ("cosine:amp=abc,freq=2", "number"),
    ("cosine:amp=,freq=2", "number"),
    ("cosine:amp=1g,freq=two", "number"),
    ("free:theta0=x", "number"),
    ("cosine:amp=nan,freq=2", "finite"),
    ("cosine:amp=nang,freq=2", "finite"),
    ("cosine:amp=1g,freq=nan", "finite"),
    ("cosine:amp=1g,freq=inf", "finite"),
    ("free:theta0=nan", "finite"),
    ("cosine:amp=1g,freq=-2", "positive"),
    ("sine:amp=1g,freq=0", "positive"),
    ("rect:amp=1g,dur=-0.5", "positive"),
    ("rect:amp=1g,dur=0", "positive"),
    ("sines:amp=1g,freq=2,cycles=-1", "positive"),
    ("cosine:amp=1g,freq=2,start=-1", "start"),
    ("synthetic:seed=-1", "seed"),
    ("synthetic:seed=1.5", "seed"),
    ("synthetic:pga=-1g", "pga"),
    ("synthetic:dt=0", "positive"),
    ("synthetic:duration=0.05", "duration"),
    ("file:path=/nonexistent/statue2model/rec.csv", "not found"),
])
def test_parse_spec_rejects(spec, word):
    with pytest.raises(InputError, match=word):
        M.parse_spec(spec)


def test_parse_spec_file_rejects(tmp_path):
    _write_two_column(tmp_path / "rec.csv", 0.01 * np.arange(4), [0.0, 1.0, 2.0, 0.0])
    for spec, word in [("file:path=rec.csv,pga=-1m/s2", "PGA"), ("file:path=rec.csv,scale=0", "not a scale"), ("file:path=rec.csv,scale=2", "ambiguous"),
                       ("file:path=rec.csv,units=furlongs", "units"), ("file:path=rec.csv,dt=0.5", "contradicts"),
                       ("file:path=rec.csv,dt=-1", "positive")]:
        with pytest.raises(InputError, match=word):
            M.parse_spec(spec, base_dir=tmp_path)


def test_parse_accel():
    assert M.parse_accel("2.5m/s2") == M.parse_accel("2.5 m/s^2") == M.parse_accel("2.5M/S**2") == 2.5
    assert M.parse_accel("0") == 0.0                     # zero is zero in any unit
    assert M.parse_accel(" 0.3g ") == pytest.approx(0.3 * 9.81, rel=1e-15)
    assert M.parse_accel("-1e-1G") == pytest.approx(-0.981)
    for bad in ("g", "abc", "inf", "0.3gg"):
        with pytest.raises(InputError):
            M.parse_accel(bad)


# --- files ------------------------------------------------------------------------------
T5 = 0.005 * np.arange(8)
A5 = np.array([0.0, 0.12, -0.5, 1.25, -2.0, 0.75, 0.3125, 0.0])


@pytest.mark.parametrize("name, text", [
    ("comma.csv", "\n".join(f"{t},{a}" for t, a in zip(T5, A5))),
    ("header.csv", "time_s,acc_m_s2\n" + "\n".join(f"{t},{a}" for t, a in zip(T5, A5))),
    ("quoted.csv", '"time","acc"\n' + "\n".join(f"{t}, {a}" for t, a in zip(T5, A5))),
    ("semi.csv", "t [s];a [m/s2]\n" + "\n".join(f"{t};{a}" for t, a in zip(T5, A5))),
    ("ws.txt", "\n".join(f"{t} {a}" for t, a in zip(T5, A5))),
    ("tab.tsv", "time\tacc\n" + "\n".join(f"{t}\t{a}" for t, a in zip(T5, A5))),
    ("aligned.dat", "# recorded 2024\n   time        acc\n" + "\n".join(f"  {t:8.4f}   {a:12.5E}" for t, a in zip(T5, A5))),
    ("crlf.csv", "time,acc\r\n" + "\r\n".join(f"{t:.3f},{a}" for t, a in zip(T5, A5)) + "\r\n\r\n"),
])
def test_read_two_column(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text + "\n")
    m = M.read_record(p)
    assert m.kind == "record" and m.start == 0.0
    assert m.dt == pytest.approx(0.005, rel=1e-12)
    np.testing.assert_allclose(m.samples, A5, rtol=1e-12)
    np.testing.assert_allclose(m.acc(T5[:-1]), A5[:-1], atol=1e-12)


def test_read_two_column_offset_start_and_units(tmp_path):
    t = 1.0 + 0.01 * np.arange(5)
    a = np.array([0.1, 0.2, -0.3, 0.0, 0.05])
    m = M.read_record(_write_two_column(tmp_path / "late.csv", t, a), units="g")
    assert m.start == pytest.approx(1.0) and m.dt == pytest.approx(0.01)
    np.testing.assert_allclose(m.samples, a * G_FILE, rtol=1e-15)
    assert m.acc(0.5) == 0.0 and m.acc(1.0) == pytest.approx(0.1 * G_FILE)
    assert m.acc(1.015) == pytest.approx(-0.05 * G_FILE)
    # dt that agrees with the time column is accepted
    assert M.read_record(tmp_path / "late.csv", dt=0.01).dt == pytest.approx(0.01)


def test_read_one_column_with_dt(tmp_path):
    p = tmp_path / "acc.txt"
    p.write_text("acc_g\n" + "\n".join(f"{a:.6e}" for a in A5) + "\n")
    m = M.read_record(p, dt=0.02, units="g")
    assert m.dt == 0.02 and m.start == 0.0 and m.end == pytest.approx(0.02 * 7)
    np.testing.assert_allclose(m.samples, A5 * G_FILE, rtol=1e-12)


def _at2_text(values, header_line="NPTS=  {n}, DT=   .0050 SEC", fmt="{:15.7E}"):
    head = ["PEER NGA STRONG MOTION DATABASE RECORD",
            "Imperial Valley-06, 10/15/1979, El Centro Array #6, 230",
            "ACCELERATION TIME SERIES IN UNITS OF G",
            header_line.format(n=len(values))]
    body = ["".join(fmt.format(v) for v in values[i:i + 5]) for i in range(0, len(values), 5)]
    return "\n".join(head + body) + "\n"


def _at2_values(n=400):
    t = 0.005 * np.arange(n)
    return 0.2 * np.sin(2 * np.pi * 1.7 * t) * np.exp(-t) + 0.01 * np.cos(2 * np.pi * 9.0 * t)


def test_read_peer_at2(tmp_path):
    g = _at2_values(400)
    p = tmp_path / "RSN179_IMPVALL.H_H-E06230.AT2"
    p.write_text(_at2_text(g))
    assert "  " in p.read_text().splitlines()[4] and "E-0" in p.read_text()
    m = M.read_record(p)
    assert m.kind == "record" and len(m.samples) == 400
    assert m.dt == 0.005 and m.start == 0.0 and m.end == pytest.approx(0.005 * 399)
    np.testing.assert_allclose(m.samples, g * 9.80665, rtol=1e-6, atol=1e-9)  # 8 significant digits in the file
    assert m.acc(0.005 * 123) == pytest.approx(g[123] * 9.80665, rel=1e-6)
    # same through a SPEC string, with pga and Froude scale
    s, _ = M.parse_spec(f"file:path={p.name},pga=0.1g,scale=1:2", base_dir=tmp_path)
    assert s.pga == pytest.approx(0.981) and s.dt == pytest.approx(0.005 / math.sqrt(2))


def test_read_peer_at2_variants(tmp_path):
    g = _at2_values(53)  # last line holds 3 values
    old = tmp_path / "old.at2"  # NGA-West1 header: "  3000    .01000    NPTS, DT"
    old.write_text(_at2_text(g, header_line="   {n}    .01000    NPTS, DT"))
    m = M.read_record(old)
    assert m.dt == 0.01 and len(m.samples) == 53
    np.testing.assert_allclose(m.samples, g * G_FILE, rtol=1e-6, atol=1e-9)
    fortran = tmp_path / "d.AT2"  # Fortran D exponents, trailing comma after SEC
    fortran.write_text(_at2_text(g, header_line="NPTS=   {n}, DT=   0.0100 SEC,").replace("E", "D"))
    m2 = M.read_record(fortran)
    assert m2.dt == 0.01
    np.testing.assert_allclose(m2.samples, m.samples, rtol=1e-15)


@pytest.mark.parametrize("name, text, word", [
    ("irregular.csv", "t,a\n0,0\n0.01,1\n0.02,2\n0.035,1\n0.045,0\n", "irregular"),
    ("decreasing.csv", "0,0\n0.01,1\n0.02,2\n0.01,1\n0.03,0\n", "increase"),
    ("repeated.csv", "0,0\n0.01,1\n0.01,2\n0.02,0\n", "increase"),
    ("onecol.csv", "0\n1\n2\n0\n", "dt="),
    ("text.csv", "t,a\n0,0\n0.01,1\n0.02,oops\n0.03,0\n", "line 4"),
    ("nan.csv", "0,0\n0.01,1\n0.02,nan\n0.03,0\n", "finite"),
    ("nantime.csv", "0,0\nnan,1\n0.02,2\n0.03,0\n", "finite"),
    ("three.csv", "0,0,1\n0.01,1,1\n0.02,2,1\n", "column"),
    ("ragged.csv", "0,0\n0.01,1\n0.02\n0.03,0\n", "column"),
    ("header_only.csv", "time,acc\n", "numeric"),
    ("single.csv", "0,1\n", "2 samples"),
    ("negative.csv", "-0.01,0\n0,1\n0.01,0\n", "negative"),
    ("empty.csv", "", "empty"),
    ("blank.csv", "\n   \n", "numeric"),
    ("npts.AT2", _at2_text(_at2_values(20)).replace("NPTS=  20", "NPTS=  25"), "NPTS"),
    ("at2text.AT2", _at2_text(_at2_values(20)) + "  END OF DATA\n", "number"),
    ("at2nan.AT2", _at2_text(list(_at2_values(19)) + [float("nan")]), "finite"),
    ("noheader.AT2", "0.1 0.2 0.3\n0.4 0.5\n", "NPTS"),
    ("badheader.AT2", "PEER\nx\ny\nNPTS= lots, DT= soon\n0.1 0.2\n", "NPTS"),
])
def test_malformed_files(tmp_path, name, text, word):
    p = tmp_path / name
    p.write_text(text)
    with pytest.raises(InputError, match=word) as err:
        M.read_record(p)
    assert name in str(err.value)  # the message names the file
    assert "\n" not in str(err.value)


def test_file_argument_errors(tmp_path):
    with pytest.raises(InputError, match="not found"):
        M.read_record(tmp_path / "missing.csv")
    with pytest.raises(InputError, match="not found"):
        M.read_record(tmp_path)  # a directory
    at2 = tmp_path / "r.AT2"
    at2.write_text(_at2_text(_at2_values(10)))
    with pytest.raises(InputError, match="DT"):
        M.read_record(at2, dt=0.01)
    csv = _write_two_column(tmp_path / "r.csv", [0.0, 0.01, 0.02], [0.0, 1.0, 0.0])
    with pytest.raises(InputError, match="contradicts"):
        M.read_record(csv, dt=0.02)
    with pytest.raises(InputError, match="units"):
        M.read_record(csv, units="ft/s2")


# --- shake-table displacement -----------------------------------------------------------
def _max_rel_err(x, ref):
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def test_table_displacement_cosine_pulse_ends_at_rest():
    # a cos(w t): v = a/w sin(w t), u = a/w^2 (1 - cos(w t)); both vanish at T = 2 pi / w,
    # so the baseline correction must be (nearly) zero and the closed form is reproduced
    A, f = 0.3 * 9.81, 2.0
    w = 2 * np.pi * f
    t, a, v, u = M.table_displacement(M.cosine_pulse(A, f), dt=1e-4)
    assert t[0] == 0.0 and t[-1] == pytest.approx(0.5) and len(t) == 5001
    assert abs(v[-1]) < 1e-12 * A / w and abs(u[-1]) < 1e-12 * A / w**2
    assert _max_rel_err(u, A / w**2 * (1 - np.cos(w * t))) < 1e-6
    assert _max_rel_err(v, A / w * np.sin(w * t)) < 1e-6
    assert _max_rel_err(a, A * np.cos(w * t)) < 1e-6


def _corrected_sine(A, f, cycles, t):
    """a sin(w t) for N full cycles, T = N / f: v = a/w (1 - cos w t) ends at 0,
    u = a/w (t - sin(w t)/w) ends at a T / w. The baseline c0 + c1 t with
    c0 T + c1 T^2/2 = v(T) = 0 and c0 T^2/2 + c1 T^3/6 = u(T) gives
    c1 = -12 a / (w T^2), c0 = 6 a / (w T)."""
    w = 2 * np.pi * f
    T = cycles / f
    c0, c1 = 6 * A / (w * T), -12 * A / (w * T**2)
    acc = A * np.sin(w * t) - c0 - c1 * t
    vel = A / w * (1 - np.cos(w * t)) - c0 * t - c1 * t**2 / 2
    dis = A / w * (t - np.sin(w * t) / w) - c0 * t**2 / 2 - c1 * t**3 / 6
    return acc, vel, dis


@pytest.mark.parametrize("A, f, cycles", [(2.0, 2.0, 1), (-1.5, 2.5, 1), (1.0, 2.0, 3)])
def test_table_displacement_sine_closed_form(A, f, cycles):
    m = M.sine_pulse(A, f) if cycles == 1 else M.sine_train(A, f, cycles)
    t, a, v, u = M.table_displacement(m, dt=1e-4)
    assert t[-1] == pytest.approx(cycles / f)
    ra, rv, ru = _corrected_sine(A, f, cycles, t)
    assert abs(v[-1]) < 1e-12 and abs(u[-1]) < 1e-12
    assert _max_rel_err(u, ru) < 1e-6
    assert _max_rel_err(v, rv) < 1e-6
    assert _max_rel_err(a, ra) < 1e-6
    # sanity of the reference itself: at rest at both ends
    assert ru[0] == 0 and rv[0] == 0 and abs(ru[-1]) < 1e-12 and abs(rv[-1]) < 1e-12


def test_table_displacement_rect_pulse_is_all_baseline():
    # a constant a on [0, T): v = a t, u = a t^2/2; the baseline c0 = a, c1 = 0 takes it all
    t, a, v, u = M.table_displacement(M.rect_pulse(1.5, 0.4), dt=1e-3)
    assert t[-1] == pytest.approx(0.4)
    assert np.max(np.abs(a)) < 1e-12 and np.max(np.abs(v)) < 1e-12 and np.max(np.abs(u)) < 1e-12


def test_table_displacement_record_and_free():
    m = M.synthetic_record(duration=4.0, dt=0.01, pga=2.0, seed=5)
    t, a, v, u = M.table_displacement(m)
    assert len(t) == 401 and t[-1] == pytest.approx(4.0)
    assert abs(v[-1]) < 1e-10 * np.max(np.abs(v)) and abs(u[-1]) < 1e-10 * np.max(np.abs(u))
    # trapezoid integrals of the corrected acceleration are the returned histories
    h = np.diff(t)
    vv = np.concatenate([[0.0], np.cumsum(0.5 * h * (a[1:] + a[:-1]))])
    uu = np.concatenate([[0.0], np.cumsum(0.5 * h * (vv[1:] + vv[:-1]))])
    np.testing.assert_allclose(v, vv, atol=1e-12)
    np.testing.assert_allclose(u, uu, atol=1e-12)
    late = M.record([0.0, 1.0, -1.0, 0.0], 0.1, start=0.3)
    t, a, v, u = M.table_displacement(late)
    assert t[0] == pytest.approx(0.3) and abs(u[-1]) < 1e-15
    t, a, v, u = M.table_displacement(M.free())
    assert not np.any(u) and not np.any(v)
    with pytest.raises(InputError, match="positive"):
        M.table_displacement(M.sine_pulse(1.0, 1.0), dt=0.0)
    with pytest.raises(InputError, match="3 samples"):
        M.table_displacement(M.record([1.0, 2.0], 0.01))


# --- sampling and the CSV round trip ----------------------------------------------------------
def test_sampled_grid_holds_the_last_value():
    m = M.cosine_pulse(2.0, 2.0)
    t, u = m.sampled(0.01)
    np.testing.assert_allclose(t, 0.01 * np.arange(51), atol=1e-15)
    np.testing.assert_allclose(u, 2.0 * np.cos(4 * np.pi * t), atol=1e-12)  # u[-1] = a cos(2 pi) = a
    t, u = M.rect_pulse(-1.0, 0.05, start=0.02).sampled(0.01)
    np.testing.assert_allclose(u, [0, 0, -1, -1, -1, -1, -1, -1])
    t, u = M.free().sampled()
    assert len(t) >= 2 and not np.any(u)


def test_write_read_round_trip_record(tmp_path):
    rng = np.random.default_rng(7)
    for start in (0.0, 0.75):
        acc = rng.normal(0.0, 1.5, 300)
        m = M.record(acc, 0.005, start=start)
        p = M.write_record_csv(tmp_path / f"r{start}.csv", m)
        back = M.read_record(p)
        assert back.dt == pytest.approx(0.005, rel=1e-9)
        assert back.start == pytest.approx(start, abs=1e-12)
        np.testing.assert_allclose(back.samples, acc, rtol=1e-8, atol=1e-12)
        tt = np.linspace(0.0, m.end + 0.1, 997)
        np.testing.assert_allclose(back.acc(tt), m.acc(tt), rtol=1e-7, atol=1e-8)


def test_write_read_round_trip_pulse(tmp_path):
    A, f = 1.3, 2.5
    p = M.write_record_csv(tmp_path / "pulse.csv", M.sine_pulse(A, f), dt=1e-3)
    assert p.read_text().splitlines()[0].startswith("time")
    back = M.read_record(p)
    assert back.dt == pytest.approx(1e-3) and len(back.samples) == 401
    t = 1e-3 * np.arange(401)
    np.testing.assert_allclose(back.samples, A * np.sin(2 * np.pi * f * t), atol=1e-8)
    r = M.read_record(M.write_record_csv(tmp_path / "rect.csv", M.rect_pulse(0.7, 0.2), dt=0.01))
    np.testing.assert_allclose(r.samples, 0.7)  # the re-read record is the same pulse
    assert r.end == pytest.approx(0.2)


# --- synthetic records ------------------------------------------------------------------------
def test_synthetic_record():
    a = M.synthetic_record(duration=10.0, dt=0.01, pga=2.5, seed=11)
    b = M.synthetic_record(duration=10.0, dt=0.01, pga=2.5, seed=11)
    c = M.synthetic_record(duration=10.0, dt=0.01, pga=2.5, seed=12)
    np.testing.assert_array_equal(a.samples, b.samples)
    assert not np.allclose(a.samples, c.samples)
    assert a.kind == "record" and a.dt == 0.01 and a.start == 0.0
    assert len(a.samples) == 1001 and a.end == pytest.approx(10.0)
    assert np.max(np.abs(a.samples)) == pytest.approx(2.5, rel=1e-12) and a.pga == pytest.approx(2.5, rel=1e-12)
    assert a.samples[0] == 0.0 and a.acc(0.0) == 0.0
    assert np.all(np.isfinite(a.samples)) and np.std(a.samples) > 0.05 * 2.5
    # the envelope: quiet start, strong middle
    assert np.max(np.abs(a.samples[:20])) < np.max(np.abs(a.samples[200:450]))


@pytest.mark.parametrize("kw, word", [
    ({"pga": -1.0}, "pga"), ({"pga": 0.0}, "pga"), ({"dt": 0.0}, "dt"), ({"duration": -5.0}, "duration"),
    ({"seed": -3}, "seed"), ({"seed": 1.5}, "seed"), ({"f_g": math.nan}, "f_g"), ({"duration": 0.05}, "duration"),
])
def test_synthetic_record_rejects(kw, word):
    with pytest.raises(InputError, match=word):
        M.synthetic_record(**kw)
