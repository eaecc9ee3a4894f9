"""The radar sensor chain (kind ``"radar"``): pulsed monostatic radar link budget, detection,
clutter, jamming, detection range and tracking, built from a static
:class:`~diffsense.sensors.structure.Scene`.

:meth:`RadarChain.compute` runs named stages, each in its own module:

1. link budget (:mod:`~diffsense.sensors.radar.link_budget`) — the book's link-budget table
   (Brooker §9.9.1 and §8.16.11), every term a signed dB contribution whose total is the
   single-pulse SNR ``snr_db`` at ``range_m``::

       peak_power_dbw        10 log10 Pt
       transmit_loss_db      −L_tx
       two_way_gain_db       +2 G
       wavelength_db         10 log10(λ² / (4π)³)
       rcs_dbsm              10 log10 σ
       range_db              −40 log10 R
       scan_loss_db, matched_filter_loss_db, cfar_loss_db, misc_loss_db      −L each
       gas/rain/fog/dust_attenuation_db     −2 α_i R / 1000   (parts present only)
       multipath_db          +40 log10 |F|                     (part present only)
       boltzmann_db          −10 log10(k T0)      (dBW/Hz)
       bandwidth_db          −10 log10 β
       noise_figure_db       −NF
       receive_loss_db       −L_rx

   The terms down to ``multipath_db`` sum to the received power Pr (dBW), the last four to
   minus the noise power N = k T0 β F L_rx. A practical IF filter is charged with its mismatch
   loss relative to the matched filter (detection.matched_filter_loss_db of β τ), as the book
   does; the option ``matched_filter="matched"`` drops the term (ideal matched filter, book
   §8.16.9.3). The waveform outputs (c W/2, c/(2 f_p), f_p/N, τ f_p) come from
   :mod:`diffsense.physics.waveforms`, with W the half-amplitude width of the echo after the IF
   filter (τ for the matched filter, :mod:`diffsense.physics.received_pulse`); the range gate,
   the clutter cells and the tracker's split gate are c W/2 long too. With
   ``noise_input="temperature"`` the noise-figure line is −10 log10(Ts/T0).
2. interference (:mod:`~diffsense.sensors.radar.interference`) — clutter parts give ``scr_db``
   = 10 log10(σ F⁴ / Σ σ_clutter) (book §8.16.6); sea clutter at the 4/3-earth grazing angle
   (the multipath geometry's relation) with the model of option ``sea_clutter_model``; the wall
   clutter seen through the beam on its sidelobe floor; a noise jammer adds J to N (book §9.10).
3. detection (:mod:`~diffsense.sensors.radar.detectability`) — the required SNR of option
   ``detectability`` ("exact", "book", "given", or the closed forms "shnidman", "albersheim",
   "barton"), Pd, and the detection margin

       m(R) = −10 log10( 10^((SNR_req − SJNR(R))/10) + 10^((SCR_req − SCR(R))/10) )   (dB),

   i.e. S ≥ SNR_req (N + J) + SCR_req C, never optimistic and at most 3 dB pessimistic where
   both limits coincide.
4. ranges (here) — ``detection_range_m`` solves m(R) = 0 (book §9.9.1.4: a nonlinear equation
   once attenuation enters) with :func:`diffsense.numerics.rootfind.decreasing_root_log` in
   [1 m, 10,000 km] (inside 0.99 × the radar horizon with multipath; above the antenna height
   with sea clutter), differentiable implicitly; ``detection_range_found`` is 1 where a crossing
   exists. With multipath the SNR oscillates with range and the solver returns one crossing
   inside the bracket, not necessarily the farthest. A self-screening jammer's burn-through
   range solves S − J = SNR_req the same way.
5. tracking (:mod:`~diffsense.sensors.radar.tracking`, part ``"tracking"``) — α-β range
   tracking and servo angle tracking at ``range_m`` (book §13.4-13.6, §14.6-14.7).

With ``wanted`` (see :class:`diffsense.sensors.chain.Chain`) the exact detectability solves, the
Pd series and the range root finds that no wanted output needs are left out of the trace.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from diffsense.detection.cumulative import cumulative_pd_of_looks
from diffsense.errors import DomainError
from diffsense.numerics.checks import is_concrete
from diffsense.numerics.rootfind import decreasing_root_log
from diffsense.physics.antennas import wavelength_m
from diffsense.sensors.chain import Chain, Evaluation, needs
from diffsense.sensors.radar.detectability import (
    check_binary_counts,
    detection_margin_db,
    pd_at,
    pd_outputs,
    range_bracket,
    required_snr,
    requirement_outputs,
)
from diffsense.sensors.radar.interference import Interference, check_sea_clutter_domain
from diffsense.sensors.radar.link_budget import Link, antenna, check_inside_horizon, link_outputs
from diffsense.sensors.radar import parts
from diffsense.sensors.radar.parameters import radar_outputs, radar_parameters
from diffsense.sensors.radar.loss_models import loss_model_refusals
from diffsense.sensors.radar.structure import (
    ATTENUATION_PARTS,
    CLUTTER_PARTS,
    OPTIONS,
    PARTS,
    MAX_LOOKS,
    SURFACE_PARTS,
    clutter_parts_present,
    looks_along_surface,
    option,
)
from diffsense.sensors.radar.tracking import TRACKING_OUTPUTS, tracking_outputs

#: outputs that read the clutter (whose cell follows the received pulse's width) when it is present
CLUTTER_OUTPUTS = ("scr_db", "scr_margin_db", "sinr_db", "detection_margin_db", "detection_range_m",
                   "detection_range_found", "pd", "burn_through_range_m", "pulses_needed")

__all__ = ["RadarChain", "PARTS", "OPTIONS", "ATTENUATION_PARTS", "CLUTTER_PARTS"]


class RadarChain(Chain):
    """Pulsed monostatic radar: link budget, detection, clutter, jamming, detection range."""

    kind = "radar"
    description = "pulsed monostatic radar (Brooker ch. 8-9): SNR budget, Pd, clutter, jamming, detection range"
    parts = PARTS
    options = OPTIONS
    draws_coverage = True

    def validate_scene(self, scene):
        super().validate_scene(scene)
        if option(scene, "integration") == "coherent" and option(scene, "swerling") in (2, 4):
            raise DomainError(
                "radar scene: coherent integration needs echoes that keep their phase over the pulses; "
                "Swerling 2 and 4 decorrelate from pulse to pulse (use integration='noncoherent')"
            )
        if scene.has("closing_target") and option(scene, "detectability") == "given":
            raise DomainError("radar scene: the part closing_target needs a detection model for Pd at each look; "
                              "detectability='given' writes only the required SNR (use 'exact')")
        if option(scene, "integration") == "binary":
            if option(scene, "detectability") != "exact":
                raise DomainError(
                    f"radar scene: integration='binary' is the exact M-of-N law of pd and pfa; detectability="
                    f"'{option(scene, 'detectability')}' is another detection model (use detectability='exact')")
        for reason in loss_model_refusals(scene, option):
            raise DomainError(f"radar scene: {reason}")
        surface = [part for part in SURFACE_PARTS if scene.has(part)]
        if surface and not looks_along_surface(scene):
            raise DomainError(f"radar scene: the parts {surface} need a radar looking along the sea surface; "
                              "option geometry='shaft' says it looks down a shaft")

    def check_values(self, scene, p):
        check_binary_counts(scene, p)

    def coverage_chart_reason(self, scene):
        if looks_along_surface(scene):
            return None
        return ("a Blake range-height chart describes a radar looking along the earth's surface through the "
                "atmosphere; this scene looks down a shaft (radar option geometry, or the part wall_clutter)")

    def parameters(self, scene):
        return radar_parameters(scene)

    def outputs(self, scene):
        return radar_outputs(scene)

    def compute(self, scene, p, wanted=None):
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the exact detectability solves, Pd series and range root finds that no wanted output
        needs are not traced (see :class:`diffsense.sensors.chain.Chain`)."""
        check_inside_horizon(scene, p)
        check_sea_clutter_domain(scene, p)
        self.check_values(scene, p)
        r0 = p["range_m"]
        lam = wavelength_m(p["freq_hz"])
        ant = antenna(scene, p, lam)
        clutter = clutter_parts_present(scene)
        need_width = needs(wanted, "range_resolution_m", *TRACKING_OUTPUTS) or (clutter and needs(wanted, *CLUTTER_OUTPUTS))
        link = Link(scene, p, lam, ant, need_width)
        interference = Interference(scene, p, link, lam, ant)
        req = required_snr(scene, p, wanted)
        req_scr = p["required_scr_db"] if interference.clutter_present else None

        def margin_db(r):
            s, mp = link.signal_dbw(r)
            scr = interference.scr_db(r, mp) if interference.clutter_present else None
            return detection_margin_db(req.per_pulse_db, interference.sjnr_db(r, s), req_scr, scr)

        budget = link.budget(r0)
        snr = budget.total
        s0, mp0 = link.signal_dbw(r0)
        values = link_outputs(p, link, ant, lam, snr, s0, wanted)
        if req.per_pulse_db is not None:
            margin0 = margin_db(r0) if needs(wanted, "detection_margin_db") else None
            values.update(requirement_outputs(p, snr, req.per_pulse_db, margin0))
        values.update(self._ranges(scene, p, wanted, link, interference, margin_db, req.per_pulse_db))
        sjnr0 = interference.sjnr_db(r0, s0) if needs(wanted, "pd") else None
        values.update(pd_outputs(scene, p, wanted, snr, sjnr0, req))
        values.update(interference.outputs(r0, s0, mp0, req_scr, wanted))
        if scene.has("closing_target") and needs(wanted, "cumulative_pd"):
            values["cumulative_pd"] = self._cumulative_pd(scene, p, link, interference, req)
        if scene.has("tracking") and needs(wanted, *TRACKING_OUTPUTS):
            values.update(tracking_outputs(scene, p, snr, ant.beamwidth_az_rad, link.received_width_s))
        return Evaluation(budget, {name: values[name] for name in radar_outputs(scene) if name in values})

    @staticmethod
    def _cumulative_pd(scene, p, link, interference, req):
        """1 − Π(1 − Pd(R_i)) over the looks R_i = range_m + i v T ≤ first_look_range_m (at most
        :data:`MAX_LOOKS`; :func:`diffsense.detection.cumulative.cumulative_pd_closing`)."""
        r0, v, t, first = p["range_m"], p["closing_speed_mps"], p["scan_period_s"], p["first_look_range_m"]
        if all(is_concrete(x) for x in (r0, v, t, first)):
            with jax.ensure_compile_time_eval():
                looks = jnp.floor((jnp.asarray(first) - r0) / (jnp.asarray(v) * t)) + 1
                worst = float(jnp.max(looks))
            if worst > MAX_LOOKS:
                raise DomainError(f"radar chain, closing_target: {worst:.0f} looks from first_look_range_m to range_m "
                                  f"at closing_speed_mps x scan_period_s; at most {MAX_LOOKS}")
            if bool(jnp.any(jnp.asarray(first) < r0)):
                raise DomainError("radar chain, closing_target: 'first_look_range_m' must not be less than 'range_m'")

        looks = parts.closing_target_looks(r0, v, t, first)
        r = looks.ranges_m
        return cumulative_pd_of_looks(pd_at(scene, p, interference.sjnr_db(r, link.signal_dbw(r)[0]), req), looks)

    @staticmethod
    def _ranges(scene, p, wanted, link, interference, margin_db, required_snr_db):
        """Detection range (margin 0) and, for a self-screening jammer, burn-through range
        (S − J = SNR_req), each solved only when a wanted output needs it."""
        values = {}
        lo, hi = range_bracket(scene, p)
        if needs(wanted, "detection_range_m", "detection_range_found"):
            root = decreasing_root_log(margin_db, lo, hi)
            values["detection_range_m"] = root.root
            values["detection_range_found"] = jnp.where(root.bracketed, 1.0, 0.0)
        if interference.has_jammer and interference.self_screening and needs(wanted, "burn_through_range_m"):
            excess = lambda r: link.signal_dbw(r)[0] - interference.jamming_dbw(r) - required_snr_db
            values["burn_through_range_m"] = decreasing_root_log(excess, lo, hi).root
        return values
