"""The assessment above the rocking engine and the isolator: fragility curves (fixed and
isolated), the run's fragility study over the design record set, and the verdict.

Modules: ``fragility`` (curves, fits, bands), ``study`` (the dynamics stage's study:
records matched to the design spectrum, fixed and isolated), ``verdict`` (the assessment
at the top of the report).
"""
