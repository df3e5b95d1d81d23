"""The 3D cross-check: the same scenes as the 2D models, run as PyBullet contact simulations
(the ``[physics]`` extra, loaded only when a scene runs), and where the two agree.

Scenes: ``world`` (DIRECT client, ground motion), ``contact``, ``statue_scene``, ``grooves``,
``isolator_scene``, ``stack_scene`` (a statue on a free pedestal). Cases: ``case`` (Case,
Comparison), ``screen`` (the one validity screen), ``boundary`` (the one bisection),
``restitution``, ``statue_cases``, ``isolator_cases``, ``imperfect``, ``ensemble``; ``compare``
runs them all into one Comparison, ``output`` writes crosscheck.json (figures and tables are
drawn in :mod:`statue2model.report`).
"""
