"""statue2model: from a 3D scan of a statue to its rocking model, scaled prototype and isolator.

Sub-packages, bottom to top (each imports only those below it; tests/test_import_layers.py):
    errors, quantities, version   input errors; values with units; the version
    io/, compute/                 files and output folders; executors, budgets, compiled kernels
    geometry/                     scan -> Body (repaired, oriented, SI) -> RockingParams, rose
    fabrication/                  the stacked-board prototype and its CNC files
    hazard/                       code and floor spectra, ground motions, record sets
    rocking/                      the rocking model and its engine, sweeps, identification
    isolator/                     the rolling-ball isolator: device, design, plates, dynamics
    assessment/                   fragility, the run's fragility study, the verdict
    crosscheck/                   the 3D contact simulations (PyBullet) against the 2D models
    report/                       every figure, table and HTML page
    pipeline/                     the stages of a run, their cache, the project file
    cli/                          the command line (argument parsing only)

Example
-------
>>> from statue2model import load_body
>>> from statue2model.io.paths import default_scan
>>> round(load_body(default_scan()).rocking().h, 3)
0.732
"""
from .errors import InputError
from .version import __version__

__all__ = ["Body", "InputError", "RockingParams", "body_from_mesh", "load_body", "__version__"]

# The geometry (numpy, scipy) is imported on first use of these names, not with the package: the
# command line (``statue2model``, ``python -m statue2model``) imports this package before its first
# line runs, and must install its Ctrl-C handling before any heavy import (cli.main).
_LAZY = {"Body": ".geometry.body", "body_from_mesh": ".geometry.body", "load_body": ".geometry.body",
         "RockingParams": ".geometry.rocking_params"}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
