"""The exact re-evaluation of an answer found with ``[options] fidelity = "fast"``.

A design optimised with the fast model choices (:mod:`diffsense.design.spec.fidelity`) is
re-evaluated with the exact ones — the same design values and catalog row, every requirement
re-checked (interval requirements densely) by the exact spec's own model — and each
requirement's value under both is reported with the difference. The verdict (met or not) is
the exact model's.
"""

from __future__ import annotations

from typing import List

import numpy as np

from diffsense.design.model import DesignModel
from diffsense.design.spec.fidelity import exact_spec


def exact_recheck(model: DesignModel, x, combo_index: int, fast_rows: List[dict]) -> dict:
    """``{"switched": {option: fast value}, "requirements": [...], "met": bool,
    "largest_difference": float}`` for design ``x`` (catalog row ``combo_index``) of a
    fast-fidelity ``model`` whose requirement rows are ``fast_rows``; each requirement entry
    has ``name``, ``unit``, ``fast``, ``exact``, ``difference`` (exact − fast) and ``met``
    (under the exact model). Empty ``switched`` (and nothing re-evaluated) for an exact spec."""
    switched = dict(model.spec.fidelity_switched)
    if not switched:
        return {"switched": {}, "requirements": [], "met": all(r["met"] for r in fast_rows),
                "largest_difference": 0.0}
    exact = DesignModel(exact_spec(model.spec))
    _, rows, _ = exact.programs.assess(np.asarray(x, dtype=float)[None, :], [combo_index])[0]
    reqs = [{"name": e["name"], "unit": e["unit"], "fast": f["value"], "exact": e["value"],
             "difference": e["value"] - f["value"], "met": e["met"]} for f, e in zip(fast_rows, rows)]
    diffs = [abs(r["difference"]) for r in reqs if np.isfinite(r["difference"])]
    return {"switched": switched, "requirements": reqs, "met": all(r["met"] for r in reqs),
            "largest_difference": max(diffs) if diffs else 0.0}


__all__ = ["exact_recheck"]
