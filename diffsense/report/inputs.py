"""The numeric inputs of a design and their values at a design.

A report differentiates the requirement outputs with respect to *every* number the design
depends on, not only the design variables: the input vector of the design model
(:mod:`diffsense.design.layout`) lists them —

* ``variable`` — the spec's continuous and integer design variables (value at the design),
* ``catalog`` — every parameter set by the chosen catalog option (e.g. ``freq_hz``),
* ``fixed`` — every other numeric parameter of every case: the spec's ``[fixed]`` values and
  the chain defaults it did not override (one input for the cases sharing it, one per case
  that sets its own, named ``<case>.<parameter>``).

:func:`design_inputs` gives them with their values at a design; the model's evaluation program
(:class:`~diffsense.report.batch.BatchEvaluator`) evaluates any vector of them.
"""

from __future__ import annotations

from typing import List

import numpy as np

from diffsense.design.layout import KINDS, Input
from diffsense.design.model import DesignModel


def design_inputs(model: DesignModel, x, combo_index: int) -> List[Input]:
    """All numeric inputs at design ``x`` (variables, their units) and catalog row ``combo_index``."""
    return model.layout.valued(model.design_values(np.asarray(x, dtype=float), combo_index))


def input_vector(inputs: List[Input]) -> np.ndarray:
    """The values of ``inputs`` as a float64 vector."""
    return np.array([i.value for i in inputs], dtype=float)


__all__ = ["Input", "KINDS", "design_inputs", "input_vector"]
