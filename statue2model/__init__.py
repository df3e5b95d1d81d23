"""statue2model: from a 3D scan of a statue to its rocking model, scaled prototype and isolator.

Pipeline (one sub-package per stage):
    geometry/   scan -> Body (repaired, oriented, SI) -> RockingParams, rose
    report/     tables and plots

Example
-------
>>> from statue2model import load_body
>>> from statue2model.io.paths import default_scan
>>> round(load_body(default_scan()).rocking().h, 3)
0.732
"""
__version__ = "0.1.0"

from .errors import InputError  # noqa: E402
from .geometry.body import Body, body_from_mesh, load_body  # noqa: E402
from .geometry.rocking_params import RockingParams  # noqa: E402

__all__ = ["Body", "InputError", "RockingParams", "body_from_mesh", "load_body", "__version__"]
