"""Everything a person reads: every figure, the stages' tables and text, and the HTML pages.

report/ sits above the analyses (geometry to crosscheck) and below the pipeline: the
stages hand it plain data, it never computes. Modules: ``tables``, ``plots``
(footprint, rose), ``dynamics_plots``, ``fragility_plots``, ``hazard_plots`` (record
sets against their target), ``isolator_plots`` (the plates' section), ``fabrication_plots``
(sheet previews), ``crosscheck_plots``, ``pipeline_plots``; ``stage_sections``,
``dynamics_section``, ``fragility_section``, ``crosscheck_section`` (each stage's tables and
text); ``figure_paths`` (which figures of a manifest may be embedded), ``page`` (the run's
report.html), ``html`` (the self-contained page), ``browser`` (the headless-Chromium check).
"""
