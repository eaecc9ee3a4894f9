"""What sets a design: its active requirements, the variables on a bound, the catalog choice,
and the requirements no variable can move.

A requirement is *active* at a design when it is an equality, or when it is met with (almost)
zero slack: scaled slack s/σ ≤ ``tol`` (σ the requirement's scale, :attr:`DesignModel.scales`;
slack ≥ 0 when met, the exact re-evaluation's slack: for an interval requirement the worst
value over its interval, its dense re-check), or when the optimiser's multiplier of the
requirement is positive and the scaled slack is at most :data:`MULTIPLIER_SLACK`. By
complementary slackness a positive multiplier belongs to a constraint with zero slack, so the
multiplier clause only admits requirements the solver converged onto to within its tolerance;
a requirement with visible slack is never listed whatever its multiplier says.

Multipliers arrive per requirement (:meth:`DesignModel.inequality_multipliers` sums the rows
of a requirement — an interval requirement has one row per worst point — through
:attr:`DesignModel.row_owner`): :func:`active_mask` is the one place that turns rows and
slacks into the active set; the optimiser's record, the trade front, the report and the
explorer all call it.

A requirement *depends on no variable* when its value is the same at the design, at the design
with each variable moved to either bound, and at the design under every other catalog
combination (:func:`fixed_requirements`, one batched call of the model's check program): it is
a check of the fixed parameters, not a constraint the optimiser can act on.
"""

from __future__ import annotations

from typing import List, Optional, Sequence

import numpy as np

#: scaled slack (slack / scale) at or below which a met requirement is active
ACTIVE_SLACK = 1e-6
#: a requirement with a positive multiplier is active when its scaled slack is at most this
MULTIPLIER_SLACK = 1e-4
#: relative change of a requirement's value below which it does not depend on the variables
FIXED_REL = 1e-12


def scaled_slacks(model, rows: Sequence[dict]) -> np.ndarray:
    """Slack / scale of each requirement row (:meth:`DesignModel.requirement_rows`)."""
    return np.array([r["slack"] for r in rows], dtype=float) / np.asarray(model.scales, dtype=float)


def active_mask(model, rows: Sequence[dict], multipliers=None, tol: float = ACTIVE_SLACK) -> np.ndarray:
    """Per requirement (spec order): active at the design of ``rows`` (module docstring).

    ``multipliers``: per requirement (:meth:`DesignModel.inequality_multipliers`), or None.

    >>> class M:  # two inequalities and an equality, scale 1
    ...     scales = np.ones(3); is_equality = np.array([False, False, True])
    >>> rows = [{"slack": 0.0}, {"slack": 10.5}, {"slack": -1e-12}]
    >>> active_mask(M(), rows, multipliers=[0.0, 0.3, 0.0]).tolist()
    [True, False, True]
    """
    s = scaled_slacks(model, rows)
    active = np.asarray(model.is_equality, dtype=bool) | (s <= tol)
    if multipliers is not None:
        lam = np.asarray(multipliers, dtype=float)
        active |= (lam > 0.0) & (s <= MULTIPLIER_SLACK)
    return active


def active_names(model, rows: Sequence[dict], multipliers=None, tol: float = ACTIVE_SLACK) -> List[str]:
    """The names of the active requirements (:func:`active_mask`), in spec order."""
    return [r["name"] for r, a in zip(rows, active_mask(model, rows, multipliers, tol)) if a]


def requirement_status(met: bool, scaled_slack: float, tol: float = ACTIVE_SLACK) -> str:
    """Stoplight of one requirement: "unmet", "active" (met with scaled slack ≤ ``tol``) or "met".

    >>> requirement_status(True, 0.5), requirement_status(True, 0.0), requirement_status(False, -1.0)
    ('met', 'active', 'unmet')
    """
    if not met:
        return "unmet"
    return "active" if scaled_slack <= tol else "met"


def bound_names(model, x) -> List[tuple]:
    """``(variable, "lower" | "upper")`` for every continuous variable of ``x`` on a bound (the
    optimiser's own test, :func:`diffsense.optimize.bounds.variables_on_bounds`)."""
    from diffsense.design.runner import bounds_problem
    from diffsense.optimize.bounds import variables_on_bounds

    on_lo, on_hi = variables_on_bounds(bounds_problem(model), np.asarray(x, dtype=float))
    out = []
    for name, lo, hi, integer in zip(model.variable_names, on_lo, on_hi, model.integer):
        if integer:
            continue
        if lo:
            out.append((name, "lower"))
        elif hi:
            out.append((name, "upper"))
    return out


def probe_designs(model, x, combo_index: int):
    """``(V, inputs)``: the input vectors and per-row inputs of :func:`fixed_requirements`'
    probe — the design, each variable at its lower and at its upper bound, and the design under
    every other catalog combination."""
    from diffsense.design.programs import stack

    x = np.asarray(x, dtype=float)
    points = [(x, combo_index)]
    for i in range(x.size):
        for edge in (model.lower[i], model.upper[i]):
            moved = x.copy()
            moved[i] = edge
            points.append((moved, combo_index))
    points += [(x, c) for c in range(len(model.combinations)) if c != combo_index]
    V = np.stack([model.design_values(p, c) for p, c in points])
    return V, stack([model.inputs(c) for _, c in points])


def fixed_requirements(model, x, combo_index: int) -> List[int]:
    """Indices of the requirements whose value no variable and no catalog choice changes over
    the probe of :func:`probe_designs` (relative change ≤ :data:`FIXED_REL`)."""
    V, inputs = probe_designs(model, x, combo_index)
    values = np.asarray(model.programs.values_rows(V, per_row_inputs=inputs)[2], dtype=float)
    ref = values[0]
    spread = np.max(np.abs(values - ref[None, :]), axis=0)
    return [j for j in range(ref.size)
            if np.isfinite(spread[j]) and spread[j] <= FIXED_REL * max(1.0, abs(ref[j]))]


def design_findings(model, x, combo_index: int, rows: Sequence[dict], multipliers=None,
                    fixed: Optional[Sequence[int]] = None) -> dict:
    """What sets the design at ``x`` (catalog row ``combo_index``) with requirement ``rows``:
    ``active`` (names), ``bounds`` ((variable, side) pairs), ``choice`` (the catalog options
    when the spec has a catalog), ``fixed`` (names of the requirements that depend on no
    variable; ``fixed``: their indices when already known, else probed) and ``warnings`` —
    one sentence each for a design set by its bounds alone and for every requirement that
    no variable moves; ``status`` per requirement ("met", "active", "unmet"); ``tightest``: the
    index of the requirement some variable moves with the smallest scaled slack."""
    mask = active_mask(model, rows, multipliers)
    active = [r["name"] for r, a in zip(rows, mask) if a]
    bounds = bound_names(model, x)
    fixed_idx = list(fixed_requirements(model, x, combo_index) if fixed is None else fixed)
    choice = dict(model.combinations[combo_index].options) if model.spec.choices else {}
    warnings = []
    constraint_active = [r["name"] for j, (r, a) in enumerate(zip(rows, mask)) if a and j not in fixed_idx]
    if bounds and not constraint_active and all(r["met"] for r in rows):
        where = ", ".join(f"{n} at its {side} bound" for n, side in bounds)
        warnings.append(f"{where}; every requirement has slack: the bound sets the design, not a requirement")
    for j in fixed_idx:
        warnings.append(f"requirement '{rows[j]['name']}' does not depend on any variable: it is a check, "
                        "not a constraint")
    slacks = scaled_slacks(model, rows)
    movable = [j for j in range(len(rows)) if j not in fixed_idx] or list(range(len(rows)))
    tightest = min(movable, key=lambda j: slacks[j]) if rows else None
    return {"active": active, "bounds": bounds, "choice": choice,
            "fixed": [rows[j]["name"] for j in fixed_idx], "warnings": warnings,
            "status": [requirement_status(r["met"], float(sl)) if not a or not r["met"] else "active"
                       for r, sl, a in zip(rows, slacks, mask)],
            "tightest": tightest}


__all__ = ["ACTIVE_SLACK", "MULTIPLIER_SLACK", "active_mask", "active_names", "requirement_status", "bound_names",
           "fixed_requirements", "probe_designs", "design_findings", "scaled_slacks"]
