"""The assessment above the rocking engine and the isolator: the dynamics stage's analyses,
fragility curves (fixed and isolated), the run's fragility study over the design record set,
and the verdict.

Modules: ``analyses`` (the dynamics stage's spectra, variability and time histories, fixed
and isolated, and their numbers), ``fragility`` (curves, fits, bands), ``study`` (the dynamics
stage's study: records matched to the design spectrum, fixed and isolated), ``verdict`` (the
assessment at the top of the report).
"""
