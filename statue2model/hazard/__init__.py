"""What the ground or the floor does: code spectra (EC8, NTC 2018), floor spectra, ground
motions (pulses, records, SPEC strings), spectrum-compatible record sets and the elastic
response spectra of records. Both the rocking engine and the isolator take their input here.

Modules: ``code_spectra`` (elastic design spectra), ``building`` (the building an object
stands in), ``floor`` (floor spectra, EC8 / NTC Circolare), ``site`` (the run's design target:
ground or floor), ``record_measures`` (PGA, PGV, PGD, Arias, D5-95 of a record; d_g),
``motions`` (GroundMotion, its constructors, files, SPEC strings), ``motion_kernel`` (the
compiled form of a motion that every kernel reads), ``matching`` (spectrum-compatible
sets), ``response_spectra`` (elastic response spectra of records).
"""
