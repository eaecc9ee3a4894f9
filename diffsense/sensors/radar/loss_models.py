"""The radar budget's modelled losses, declared in one place.

Each :class:`LossModel` is one signed term of the link budget (``-L`` dB, :mod:`diffsense.sensors.
radar.link_budget`) whose value a spec chooses how to obtain: the static option that picks the
model, the allowed models, and for each model the parameters it reads and the function that
computes the loss from them. The option table (:data:`diffsense.sensors.radar.structure.OPTIONS`,
what ``diffsense describe radar`` prints), the parameter table and the budget all read these
declarations, so a new way to compute a loss is a new :class:`Choice` here (plus its test), and a
new modelled loss a new :class:`LossModel` in :data:`LOSS_MODELS`.

Declared losses (budget order):

* ``scan_loss_db`` (option ``scan_loss_model``): ``"given"`` — the spec's number (book 9.9.1:
  1.6 dB for a 1-D scan); ``"beam_shape_1d"`` / ``"beam_shape_2d"`` — the Gaussian beam's
  SNR-averaged beam-shape loss at a beam spacing of ``beam_spacing`` beamwidths in one or two
  scanned axes (:func:`diffsense.detection.beam_shape_loss_db`; 1.672 / 3.343 dB contiguous).
* ``cfar_loss_db`` (option ``cfar_model``): ``"given"`` — the spec's number (book 9.9.1: 0.7 dB);
  ``"cell_averaging"`` — the exact CA-CFAR loss for the scene's Swerling case, Pd, Pfa and
  integrated pulses with ``cfar_reference_cells`` reference cells (Finn & Johnson 1968;
  :func:`diffsense.detection.cfar_loss_db`: the SNR the CFAR detector needs minus the known-noise
  requirement, both for N noncoherently integrated pulses; N = 1 with coherent integration);
  ``"ordered_statistic"`` — the exact OS-CFAR loss (Rohling 1983), the noise estimated by the k-th
  smallest of ``cfar_reference_cells`` cells, k = ceil(``cfar_rank_fraction`` n), one sample per
  cell (so only with coherent integration; :func:`diffsense.detection.os_cfar_loss_db`);
  ``"greatest_of"`` / ``"smallest_of"`` — the exact GO/SO-CFAR losses with two half windows of
  ``cfar_half_window_cells`` cells (:func:`diffsense.detection.go_cfar_loss_db`, ``so_cfar_loss_db``).
  The cell counts are integers; an optimizer's relaxed count interpolates the loss linearly
  between the integers around it.
* ``misc_loss_db`` (option ``misc_loss_model``): ``"given"`` only (book 9.9.1: 1.3 dB).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping, Optional, Tuple

import jax
import jax.numpy as jnp

from diffsense import detection as _det
from diffsense.detection import cfar_greatest_smallest as _gs
from diffsense.detection import cfar_ordered as _os
from diffsense.sensors.chain import Param
from diffsense.sensors.radar.integer_counts import between_integer_counts

__all__ = ["Choice", "LossModel", "LOSS_MODELS", "loss_model_options", "loss_model_parameters", "modelled_losses_db",
           "loss_model_refusals", "loss_models_markdown"]


@dataclass(frozen=True)
class Choice:
    """One way to obtain a loss: the parameters it reads, ``loss_db(scene, p, option) -> dB``
    (``option(scene, name)``: the scene's value of a radar option) and what it computes, with its
    source (``doc``, the generated documentation's text)."""

    parameters: Tuple[Param, ...]
    loss_db: Callable
    doc: str
    #: ``refusal(scene, option) -> str | None``: why the scene cannot use this choice (checked when
    #: the scene is validated), or None
    refusal: Optional[Callable] = None


@dataclass(frozen=True)
class LossModel:
    """A budget term (``term``, entered as ``-loss``) and the option ``option`` choosing among
    ``choices`` (the first is the default)."""

    term: str
    option: str
    choices: Mapping[str, Choice]

    @property
    def default(self) -> str:
        return next(iter(self.choices))


def _given(term: str, meaning: str) -> Choice:
    return Choice((Param(term, "dB", meaning, 0.0, 0.0, 60.0),), lambda scene, p, option: p[term],
                  f"the spec's number `{term}`")


def _beam_shape(dims: int) -> Choice:
    spacing = Param("beam_spacing", "1", "spacing of the beam positions (or the scan swept during the integrated "
                    "pulses) in one-way 3 dB beamwidths; the Gaussian beam's SNR-averaged beam-shape loss follows "
                    "(1: contiguous beams, 1.67 dB per scanned axis)", 1.0, 0.0, 10.0)
    return Choice((spacing,), lambda scene, p, option: _det.beam_shape_loss_db(p["beam_spacing"], dims=dims),
                  f"SNR-averaged loss of a Gaussian beam sampled every `beam_spacing` beamwidths along "
                  f"{('one scanned axis', 'two scanned axes')[dims - 1]} (Blake 1986; "
                  "`diffsense.detection.beam_shape_loss_db`)")


def _binary_integration(name, option, scene):
    """The refusal of a modelled CFAR loss beside M-of-N integration, or None."""
    if option(scene, "integration") == "binary":
        return (f"cfar_model='{name}' sets a threshold on one integrated sample; M-of-N integration thresholds "
                "every pulse at the per-pulse false-alarm probability (use cfar_model='given' with the loss at "
                "that level)")
    return None


def _needs_detection_model(name):
    def refusal(scene, option):
        binary = _binary_integration(name, option, scene)
        if binary:
            return binary
        if option(scene, "detectability") == "given":
            return (f"cfar_model='{name}' computes the CFAR loss for the scene's pd and pfa; "
                    "detectability='given' has neither (use detectability='exact' or cfar_model='given')")
        return None
    return refusal


def _single_sample_detector(name):
    def refusal(scene, option):
        if option(scene, "integration") == "noncoherent":
            return (f"cfar_model='{name}' is exact for one sample per cell; noncoherent integration puts N "
                    f"pulses in each cell (use integration='coherent' or cfar_model='cell_averaging')")
        return _needs_detection_model(name)(scene, option)
    return refusal


def _ordered_statistic_loss_db(scene, p, option):
    def loss_at(n):
        rank = jnp.ceil(p["cfar_rank_fraction"] * n - 1e-9)  # k = ceil(f n): 1 <= k <= n
        return _os.os_cfar_loss_db_traced(p["pd"], p["pfa"], n, jax.lax.stop_gradient(rank), option(scene, "swerling"))
    return between_integer_counts(loss_at, p["cfar_reference_cells"])


def _split_window_loss_db(greatest: bool):
    def loss_db(scene, p, option):
        return between_integer_counts(
            lambda m: _gs.split_window_cfar_loss_db_traced(p["pd"], p["pfa"], m, greatest, option(scene, "swerling")),
            p["cfar_half_window_cells"])
    return loss_db


def _cell_averaging_loss_db(scene, p, option):
    coherent = option(scene, "integration") == "coherent"
    n = 1.0 if coherent else p["n_pulses"]
    return _det.cfar_loss_db(p["pd"], p["pfa"], p["cfar_reference_cells"], n, option(scene, "swerling"))


_CELLS = Param("cfar_reference_cells", "1", "reference cells M averaged by the CA-CFAR noise estimate (each "
               "holding the N integrated pulses); the loss is exact for the scene's Swerling case, pd, pfa and "
               "n_pulses", 16.0, 1.0, 1e4, integer=True)

_OS_CELLS = Param("cfar_reference_cells", "1", "reference cells n ranked by the OS-CFAR noise estimate (one "
                  "sample each)", 24.0, 1.0, float(_os.TRACED_MAX_CELLS), integer=True)
_OS_RANK = Param("cfar_rank_fraction", "1", "rank of the OS-CFAR noise estimate as a fraction f of the reference "
                 "cells: the k-th smallest, k = ceil(f n) (Rohling 1983: about 3/4)", 0.75, 0.01, 1.0)

_HALF_WINDOW = Param("cfar_half_window_cells", "1", "reference cells m in each of the two half windows (leading and "
                     "lagging) whose sums the GO/SO-CFAR estimate compares, one sample each", 8.0, 1.0,
                     float(_gs.TRACED_MAX_HALF_WINDOW), integer=True)

LOSS_MODELS: Tuple[LossModel, ...] = (
    LossModel("scan_loss_db", "scan_loss_model", {
        "given": _given("scan_loss_db", "beam-shape / scanning loss (book 9.9.1: 1.6 dB for 1-D scan)"),
        "beam_shape_1d": _beam_shape(1),
        "beam_shape_2d": _beam_shape(2),
    }),
    LossModel("cfar_loss_db", "cfar_model", {
        "given": _given("cfar_loss_db", "CFAR loss (book 9.9.1: 0.7 dB)"),
        "cell_averaging": Choice((_CELLS,), _cell_averaging_loss_db,
                                 "exact CA-CFAR loss for the scene's Swerling case, `pd`, `pfa` and `n_pulses` "
                                 "with `cfar_reference_cells` cells (Finn & Johnson 1968; "
                                 "`diffsense.detection.cfar_loss_db`)", _needs_detection_model("cell_averaging")),
        "ordered_statistic": Choice((_OS_CELLS, _OS_RANK), _ordered_statistic_loss_db,
                                    "exact OS-CFAR loss (one sample per cell: coherent integration) for the scene's "
                                    "Swerling case, `pd` and `pfa`, the noise taken as the k-th smallest of "
                                    "`cfar_reference_cells` cells, k = ceil(`cfar_rank_fraction` n) (Rohling 1983; "
                                    "`diffsense.detection.os_cfar_loss_db`)",
                                    _single_sample_detector("ordered_statistic")),
        "greatest_of": Choice((_HALF_WINDOW,), _split_window_loss_db(True),
                              "exact GO-CFAR loss (one sample per cell: coherent integration), the noise taken as "
                              "the greater of two half-window sums of `cfar_half_window_cells` cells (Hansen & "
                              "Sawyers 1980; `diffsense.detection.go_cfar_loss_db`)",
                              _single_sample_detector("greatest_of")),
        "smallest_of": Choice((_HALF_WINDOW,), _split_window_loss_db(False),
                              "exact SO-CFAR loss (one sample per cell: coherent integration), the noise taken as "
                              "the smaller of two half-window sums of `cfar_half_window_cells` cells (Weiss 1982; "
                              "`diffsense.detection.so_cfar_loss_db`)", _single_sample_detector("smallest_of")),
    }),
    LossModel("misc_loss_db", "misc_loss_model", {
        "given": _given("misc_loss_db", "miscellaneous losses (book 9.9.1: 1.3 dB)"),
    }),
)


def loss_model_options() -> dict:
    """``{option: (default, allowed values)}`` of the declared losses (the option table's rows)."""
    return {m.option: (m.default, tuple(m.choices)) for m in LOSS_MODELS}


def _chosen(scene, model: LossModel) -> Choice:
    return model.choices[scene.option(model.option, model.default)]


def loss_model_parameters(scene) -> list:
    """The parameters the scene's chosen loss models read (budget order, no repeats)."""
    out, seen = [], set()
    for model in LOSS_MODELS:
        for param in _chosen(scene, model).parameters:
            if param.name not in seen:
                seen.add(param.name)
                out.append(param)
    return out


def loss_model_refusals(scene, option) -> list:
    """Why the scene's chosen loss models cannot be used with its other options (empty: they can)."""
    reasons = [_chosen(scene, m).refusal for m in LOSS_MODELS]
    return [r for r in (fn(scene, option) for fn in reasons if fn is not None) if r]


def modelled_losses_db(scene, p, option) -> list:
    """``[(term, loss dB)]`` of the declared losses in budget order, each from the scene's model."""
    return [(m.term, _chosen(scene, m).loss_db(scene, p, option)) for m in LOSS_MODELS]


def loss_models_markdown() -> str:
    """The declarations as a Markdown table (``docs/models/radar_losses.md`` is this text; a test keeps
    the two equal)."""
    lines = ["# Radar budget losses and how a spec computes them", "",
             "Generated from `diffsense.sensors.radar.loss_models.LOSS_MODELS`; each term enters the budget "
             "as −L dB. Pick a model with the option in `[options]` (the first is the default).", "",
             "| budget term | option | model | parameters | what it computes |", "|---|---|---|---|---|"]
    for model in LOSS_MODELS:
        for name, choice in model.choices.items():
            params = ", ".join(f"`{q.name}` ({q.unit})" for q in choice.parameters)
            lines.append(f"| `{model.term}` | `{model.option}` | `{name}` | {params} | {choice.doc} |")
    return "\n".join(lines) + "\n"
