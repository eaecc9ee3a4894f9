"""The three kinds of requirement behind one protocol: rows, values and the row owner.

Every requirement of a spec is one of

* **point** — one output of one case at the case's parameters: one constraint row;
* **interval** — the worst value of an output over a box of parameters
  (:mod:`diffsense.design.intervals`): one row per slot (a candidate worst point, an input of the
  programs);
* **chance** — a smoothed quantile of an output over uncertain inputs
  (:mod:`diffsense.design.chance`): one row.

A kind says how many rows each of its requirements has and computes the value behind each row
(in the requirement's unit); :class:`RequirementKinds` lays the rows out in spec order, records
the requirement each row belongs to (``row_owner``) and takes each requirement's value as the
worst of its rows. Nothing else in the model branches on a requirement's kind.
"""

from __future__ import annotations

from typing import Dict, FrozenSet, List

import jax
import jax.numpy as jnp
import numpy as np


class PointKind:
    """Point requirements: the output of the case evaluation."""

    name = "point"

    def __init__(self, spec, indices: List[int]):
        self.spec = spec
        self.indices = indices

    def rows(self, j: int) -> int:
        return 1

    def outputs(self) -> Dict[str, FrozenSet[str]]:
        """The outputs each case must compute for these requirements."""
        out: Dict[str, set] = {}
        for j in self.indices:
            r = self.spec.requirements[j]
            out.setdefault(r.case, set()).add(r.output)
        return {c: frozenset(v) for c, v in out.items()}

    def row_values(self, params, evaluations, slots, inputs) -> Dict[int, jnp.ndarray]:
        out = {}
        for j in self.indices:
            r = self.spec.requirements[j]
            out[j] = jnp.reshape(jnp.asarray(evaluations[r.case].values[r.output], dtype=float), (1,))
        return out


class IntervalKind:
    """Interval requirements: the output at each slot (:class:`~diffsense.design.intervals.IntervalRequirements`),
    computed with the case's evaluation (:meth:`DesignModel.evaluate_with_slots`)."""

    name = "interval"

    def __init__(self, intervals):
        self.intervals = intervals
        self.indices = list(intervals.indices)

    def rows(self, j: int) -> int:
        return self.intervals.slots(j)

    def row_values(self, params, evaluations, slots, inputs) -> Dict[int, jnp.ndarray]:
        return {j: slots[j] for j in self.indices}


class ChanceKind:
    """Chance requirements: the smoothed quantile (:class:`~diffsense.design.chance.ChanceRequirements`)."""

    name = "chance"

    def __init__(self, chance):
        self.chance = chance
        self.indices = list(chance.indices)

    def rows(self, j: int) -> int:
        return 1

    def row_values(self, params, evaluations, slots, inputs) -> Dict[int, jnp.ndarray]:
        if not self.indices:
            return {}
        return {j: jnp.reshape(q, (1,)) for j, q in self.chance.values(params, inputs).items()}


class RequirementKinds:
    """The requirement kinds of a model, their rows in spec order and each requirement's value."""

    def __init__(self, model):
        spec = model.spec
        interval = IntervalKind(model.intervals)
        chance = ChanceKind(model.chance)
        taken = set(interval.indices) | set(chance.indices)
        point = PointKind(spec, [j for j in range(len(spec.requirements)) if j not in taken])
        self.kinds = (point, interval, chance)
        self.kind_of = {j: k for k in self.kinds for j in k.indices}
        self.n_requirements = len(spec.requirements)
        self.sign = np.asarray(model.sign, dtype=float)
        counts = [self.kind_of[j].rows(j) for j in range(self.n_requirements)]
        #: the requirement each constraint row belongs to
        self.row_owner = (np.concatenate([np.full(c, j, dtype=int) for j, c in enumerate(counts)])
                          if counts else np.zeros((0,), dtype=int))
        self.row_start = np.concatenate([[0], np.cumsum(counts)]).astype(int) if counts else np.zeros(1, int)
        self._point = point

    def point_outputs(self) -> Dict[str, FrozenSet[str]]:
        return self._point.outputs()

    def row_values(self, params, evaluations, slots, inputs) -> jnp.ndarray:
        """The value behind every row (the requirement's unit), rows in spec order: point
        requirements from ``evaluations``, interval requirements from ``slots`` (their outputs at
        their slots), chance requirements from the parameters ``params`` and the sample."""
        found = {}
        for kind in self.kinds:
            found.update(kind.row_values(params, evaluations, slots, inputs))
        if not found:
            return jnp.zeros((0,))
        return jnp.concatenate([found[j] for j in range(self.n_requirements)])

    def worst(self, rows) -> jnp.ndarray:
        """Each requirement's worst row value: the smallest for ``at_least``, else the largest."""
        if self.n_requirements == 0:
            return jnp.zeros((0,))
        out = []
        for j in range(self.n_requirements):
            seg = rows[self.row_start[j]:self.row_start[j + 1]]
            # the worst row by its index, not jnp.min/max: their derivative divides by the count
            # of entries equal to the result, which is 0 (NaN) where XLA computes the entries and
            # the result in different fusions that round differently
            k = jnp.argmin(seg) if self.sign[j] < 0 else jnp.argmax(seg)
            out.append(seg[jax.lax.stop_gradient(k)])
        return jnp.stack(out)


__all__ = ["RequirementKinds", "PointKind", "IntervalKind", "ChanceKind"]
