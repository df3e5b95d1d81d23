"""The dynamics stage's analyses of one statue, on a fixed base and (with a passing isolator
design) on the isolator: stability spectra over pulses, variability over PGA levels of one
motion, and time histories under it; and the numbers of them that the verdict, the report
and the collection table read (:meth:`DynamicsResults.data`, m/s^2 for PGAs).

On the isolator a run that passes the isolator's capacity stops there ('isolator capacity
exceeded'), a failure as bad as overturning: the isolated 'overturn fraction' and 'first
failing PGA' count both (the conservative values, under the keys the collection table reads),
with the separate ones beside them.

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel
>>> model = RockingModel.housner(RockingParams.rectangular_block(0.0384, 0.2, 1.286))
>>> motion = motions.sine_pulse(0.3 * 9.81, 2.0)
>>> freqs, amps, pgas = np.array([1.0, 2.0]), np.array([1.0, 4.0]), np.linspace(1.0, 6.0, 3)
>>> sp, spi = spectra(model, None, freqs, amps, "cosine", 1e-7)
>>> sw, swi, acc = variabilities(model, None, motion, pgas, 1e-7)
>>> fixed, plate, coupled = histories(model, None, motion, 1e-7)
>>> r = DynamicsResults(model, motion, None, None, "cosine", freqs, amps, pgas,
...                     sp, spi, sw, swi, acc, fixed, plate, coupled)
>>> d = r.data()
>>> sorted(d)[:3], d["first_overturn_pga_isolated"]
(['first_capacity_pga_isolated', 'first_failure_pga_isolated', 'first_overturn_only_pga_isolated'], None)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

DT_OUT = 0.005
"""Sampling step of the time histories, s."""


def spectra(model, iso, freqs, amps, pulse: str, rtol: float, executor=None, iso_model=None) -> tuple:
    """(the fixed-base StabilitySpectrum, the IsolatedSpectrum on ``iso`` or None) over
    ``freqs`` (Hz) x ``amps`` (m/s^2) of one-``pulse`` pulses; ``iso_model``: the body on the isolator
    (None: ``model``; with the pedestal on the device, the stack as one body)."""
    iso_model = model if iso_model is None else iso_model
    from ..isolator.sweeps import isolated_spectrum
    from ..rocking.spectrum import stability_spectrum

    sp = stability_spectrum(model, freqs, amps, pulse=pulse, rtol=rtol, executor=executor)
    spi = None if iso is None else isolated_spectrum(iso, iso_model, freqs, amps, pulse=pulse, rtol=rtol,
                                                     executor=executor)
    return sp, spi


def variabilities(model, iso, motion, pgas, rtol: float, executor=None, iso_model=None) -> tuple:
    """(the fixed-base SweepResult, the IsolatedSweep on ``iso`` or None, its plate's peak
    absolute accelerations or None) of ``motion`` scaled to each of ``pgas`` (m/s^2); ``iso_model``
    as :func:`spectra`'s."""
    iso_model = model if iso_model is None else iso_model
    from ..isolator.sweeps import isolated_variability
    from ..rocking.sweeps import variability

    sw = variability(model, motion, pgas, rtol=rtol, executor=executor)
    swi = acc_i = None
    if iso is not None:
        swi, acc_i = isolated_variability(iso, iso_model, motion, pgas, rtol=rtol, executor=executor)
    return sw, swi, acc_i


def histories(model, iso, motion, rtol: float, iso_model=None) -> tuple:
    """(the fixed-base response, the plate alone on ``iso`` or None, the statue coupled to
    the plate or None) under ``motion``, sampled every DT_OUT s; ``iso_model`` as :func:`spectra`'s."""
    iso_model = model if iso_model is None else iso_model
    from ..isolator.coupled import simulate_coupled
    from ..isolator.time_history import simulate as plate_run
    from ..rocking.engine import simulate as rock

    fixed = rock(model, motion, rtol=rtol, dt_out=DT_OUT)
    plate = coupled = None
    if iso is not None:
        plate = plate_run(iso, motion, dt_out=DT_OUT)
        coupled = simulate_coupled(iso, iso_model, motion, t_end=float(plate.t[-1]), dt_out=DT_OUT, rtol=rtol)
    return fixed, plate, coupled


def variability_dict(sw, swi, acc_i) -> dict:
    """variability.json: the fixed-base sweep ``sw`` and the isolated one ``swi`` with its plate's
    peak accelerations ``acc_i`` (or None), as :func:`variabilities` returns them."""
    return {"fixed": sw.to_dict(), "isolated": None if swi is None else {**swi.to_dict(), "plate_acc_abs_max": acc_i}}


def first_overturn(sw) -> float | None:
    """The lowest swept value at which ``sw`` overturned, or None."""
    i = np.flatnonzero(sw.overturned)
    return float(sw.values[i[0]]) if i.size else None


@dataclass(frozen=True)
class DynamicsResults:
    """The analyses of the module docstring: the ``model``, the ``motion``, the Isolator ``iso``
    (None: fixed base only) and its design ``period`` (s, or None), the ``pulse`` of the spectra
    and the grids (``freqs`` Hz, ``amps`` and ``pgas`` m/s^2); the spectra, the variability sweeps
    (with the plate's peak accelerations on the isolator) and the time histories (the plate alone
    and the statue coupled to it on the isolator)."""

    model: object
    motion: object
    iso: object
    period: float | None
    pulse: str
    freqs: np.ndarray
    amps: np.ndarray
    pgas: np.ndarray
    spectrum: object
    spectrum_isolated: object
    variability: object
    variability_isolated: object
    plate_acc_isolated: object
    history: object
    history_plate: object
    history_coupled: object

    def history_dict(self) -> dict:
        """history.json: the fixed-base history and, on the isolator, the coupled one."""
        hist = {"fixed": self.history.to_dict()}
        if self.iso is not None:
            hist["isolated"] = self.history_coupled.to_dict()
        return hist

    def data(self) -> dict:
        """The stage's numbers: overturning fractions of the spectra, first overturning (and,
        on the isolator, failing and capacity) PGAs of the variability, the outcomes of the
        time histories; on the isolator its capacity (m, None if not checked), the capacity
        exceeded counts and the efficiency (module docstring)."""
        from ..isolator.sweeps import CAPACITY, is_failure

        iso, sp, spi = self.iso, self.spectrum, self.spectrum_isolated
        sw, swi, coupled = self.variability, self.variability_isolated, self.history_coupled
        data = {}
        if iso is not None:
            cap = iso.capacity
            data["capacity_isolator"] = cap if np.isfinite(cap) else None
            n_cap_sp = int(np.sum(spi.codes == CAPACITY))
            # conservative: overturning or capacity exceeded (the key the collection table reads)
            data["spectrum_overturn_fraction_isolated"] = float(np.mean(is_failure(spi.codes)))
            data["spectrum_failure_fraction_isolated"] = data["spectrum_overturn_fraction_isolated"]
            data["spectrum_overturn_only_fraction_isolated"] = float(np.mean(spi.codes >= 3))
            data["capacity_exceeded_fraction_isolated"] = float(n_cap_sp / spi.codes.size)
        data["spectrum_overturn_fraction_fixed"] = float(np.mean(sp.codes >= 3))
        ot_i = cap_i = fail_i = None
        if swi is not None:
            ot_i, cap_i, fail_i = first_overturn(swi), swi.first_capacity_pga(), swi.first_failure_pga()
        # first_overturn_pga_isolated: the conservative value (overturning or capacity exceeded),
        # the key the collection table reads; the separate ones beside it
        data.update(first_overturn_pga_fixed=first_overturn(sw), first_overturn_pga_isolated=fail_i,
                    first_failure_pga_isolated=fail_i, first_overturn_only_pga_isolated=ot_i,
                    first_capacity_pga_isolated=cap_i)
        if swi is not None:
            data["capacity_exceeded_points_isolated"] = {
                "spectrum": n_cap_sp, "variability": int(np.sum((swi.codes == CAPACITY) & swi.run)),
                "variability_not_run": int((~swi.run).sum())}
        if iso is not None:
            data.update(efficiency=coupled.efficiency, outcome_isolated=coupled.outcome,
                        capacity_exceeded_history=coupled.capacity_exceeded, t_capacity_history=coupled.t_capacity,
                        u_max_history=coupled.u_max)
        data.update(outcome_fixed=self.history.outcome, theta_max_over_delta_fixed=self.history.theta_max_over_delta)
        return data
