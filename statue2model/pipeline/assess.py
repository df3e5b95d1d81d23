"""The verdict's adapter: the stages' manifests and files -> typed inputs -> the verdict.

:func:`assess` reads what the stages wrote (their manifests' data, the isolator's design.json, the
dynamics stage's limit states, the 3D classification) into
:class:`statue2model.assessment.verdict.VerdictInputs` and hands them to
:func:`statue2model.assessment.verdict.verdict`: the verdict itself never reads a manifest, a file
or the configuration. A file that does not hold what a record needs is refused with the field named
(a file in an output folder is input).

Example
-------
>>> v = assess({"params": {"status": "done", "data": {"a_min": 2.71, "a_L": 4.16, "a_R": 2.71, "h": 0.73,
...            "b_L": 0.31, "b_R": 0.20}}}, {}, None)
>>> v["code"], v["fixed"]["lifts"]
('RUN_ISOLATOR_STAGE', True)
"""
from __future__ import annotations

import json
from pathlib import Path

from ..assessment.limit_states import LimitStates
from ..assessment.records import DesignRecord
from ..assessment.verdict import VerdictInputs, hazard, verdict


def _data(stages: dict, name: str) -> dict | None:
    """The data of stage ``name``'s manifest when it completed (done or taken from the cache), else None."""
    man = stages.get(name) or {}
    if man.get("status") not in ("done", "cached"):
        return None
    return man.get("data") or {}


def inputs(stages: dict, dirs: dict, cfg) -> VerdictInputs:
    """The typed inputs of the verdict from the stages' manifests ``stages`` (name -> manifest with
    status and data), their folders ``dirs`` and the configuration ``cfg`` (None: the defaults)."""
    model = getattr(cfg, "model", None) if cfg is not None else None
    kind = getattr(model, "kind", "housner") if model is not None else "housner"
    alpha = min(model.alpha_L, model.alpha_R) if model is not None and kind == "imperfect" else 1.0
    dyn = _data(stages, "dynamics")
    ls = (dyn or {}).get("limit_states")
    design = None
    if _data(stages, "isolator") is not None and "isolator" in dirs:
        path = Path(dirs["isolator"]) / "design.json"
        if path.is_file():
            design = DesignRecord.from_dict(json.loads(path.read_text()))
    dynamics_cfg = getattr(cfg, "dynamics", None) if cfg is not None else None
    return VerdictInputs(
        hazard=hazard(cfg), params=_data(stages, "params"), alpha=alpha, model_kind=kind,
        mu_static=cfg.sliding.mu_statue if cfg is not None else None, dynamics=dyn,
        limit_states=LimitStates.from_dict(ls) if ls else None, design=design,
        classification=(_data(stages, "crosscheck") or {}).get("classification"),
        record=getattr(dynamics_cfg, "motion", None) if dynamics_cfg is not None else None)


def assess(stages: dict, dirs: dict, cfg) -> dict:
    """The verdict of a run: :func:`inputs`, then assessment.verdict.verdict."""
    return verdict(inputs(stages, dirs, cfg))
