"""Print the measured errors of the rocking engine against the references of MODEL.md section 3
(the same oracles as tests/test_rocking_accuracy.py, with the numbers shown instead of asserted).

    python3 benchmarks/accuracy_rocking.py     # about 30 s
"""
import math
import sys
sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parents[1] / "tests"))
import test_rocking_accuracy as T
from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate
A1, ST, G = T.A1, T.STATUE, 9.81
worst = 0
for params in (A1, ST):
    m = RockingModel.housner(params, e_L=0.8, e_R=0.8)
    for ratio in (0.05, 0.3, 0.7, 0.95):
        for side in (1, -1):
            d = params.delta_R if side > 0 else params.delta_L; p = params.p_R if side > 0 else params.p_L
            r = simulate(m, motions.free(), theta0=side*ratio*d, rtol=1e-12, t_end=5)
            ref = T.quarter_period_quadrature(p, d, ratio*d)
            worst = max(worst, abs(r.impact_times[0]/ref - 1))
print(f"quarter period vs quadrature: max rel err {worst:.1e} (16 cases)")
m = RockingModel.housner(ST, e_L=0.93, e_R=0.81)
r = simulate(m, motions.free(), theta0=0.8*ST.delta_R, rtol=1e-12, t_end=4)
delta = {"R": ST.delta_R, "L": ST.delta_L}; d = {"R": ST.d_R, "L": ST.d_L}; I = {"R": ST.I_R, "L": ST.I_L}; e = {"R": .93, "L": .81}
w = 0
for i in range(r.peak_values.size-1):
    a, b = r.peak_sides[i], r.peak_sides[i+1]
    lhs = d[b]/I[b]*2*math.sin(delta[b]-r.peak_values[i+1]/2)*math.sin(r.peak_values[i+1]/2)
    rhs = e[a]**2*d[a]/I[a]*2*math.sin(delta[a]-r.peak_values[i]/2)*math.sin(r.peak_values[i]/2)
    w = max(w, abs(lhs/rhs-1))
print(f"peak decay vs energy law (asymmetric statue, e_L 0.93, e_R 0.81): max rel err {w:.1e} over {r.peak_values.size-1} impacts")
m = RockingModel.housner(A1, e_L=1, e_R=1, linearised=True); w = 0
for ratio in (0.1, 0.5, 0.9, 0.99):
    r = simulate(m, motions.free(), theta0=ratio*A1.delta_R, rtol=1e-12, t_end=3)
    Tp = 4/A1.p_R*math.acosh(1/(1-ratio)); w = max(w, abs(4*r.impact_times[0]/Tp-1), abs(2*(r.impact_times[1]-r.impact_times[0])/Tp-1))
print(f"linearised period vs Housner: max rel err {w:.1e}")
ml = RockingModel.housner(A1, e_L=0.9, e_R=0.9, linearised=True)
for pt1 in (0.5, 1, 2, 4):
    t1 = pt1/A1.p_R
    A = T._boundary(lambda a: motions.rect_pulse(-a, t1), ml, 1.0001, 1/(1-math.exp(-pt1))*1.2, tol=1e-9)
    ref = 1/(1-math.exp(-pt1)); print(f"rect p t1={pt1}: A={A:.6f} ref {ref:.6f} rel err {abs(A/ref-1):.1e}")
for beta, Aref in [(0.5, 1.1120), (1, 1.3569), (2, 2.0564), (4, 4.2503), (8, 12.139)]:
    f = beta*A1.p_R/(2*math.pi)
    A = T._boundary(lambda a: motions.sine_pulse(-a, f), ml, Aref*0.97, Aref*1.03, tol=1e-9)
    print(f"one-sine beta={beta}: A={A:.5f} ref {Aref} rel diff {abs(A/Aref-1):.1e}")
for e in (0.5, 0.8, 0.95):
    m = RockingModel.housner(A1, e_L=e, e_R=e, linearised=True); p, d0 = A1.p_R, A1.delta_R; th0 = 0.6*d0
    r = simulate(m, motions.free(), theta0=th0, rtol=1e-10, t_end=60)
    t = math.acosh(1/(1-0.6))/p; w = p*math.sqrt(d0**2-(d0-th0)**2); k = 1
    while e**k*w > 1e-15:
        t += 2/p*math.atanh(e**k*w/(p*d0)); k += 1
    print(f"Zeno e={e}: t_rest {r.t_rest:.6f} predicted {t:.6f} rel err {abs(r.t_rest/t-1):.1e}; {r.n_impacts} impacts, {r.stats['n_steps']} steps + {r.stats['n_rejected']} rejected")
