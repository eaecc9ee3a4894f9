"""What a radar scene may hold: its parts, the groups of parts the chain treats alike, and its
static options with their defaults and allowed values.

The parts and options are static structure (:class:`diffsense.sensors.structure.Scene`): they
decide, at trace time, which terms the radar chain builds.

Options added to the book's set:

* ``sea_clutter_model``: ``"nrl"`` (default) — the NRL model (Gregers-Hansen & Mital 2012:
  0.5-35 GHz, sea state 0-6, grazing 0.1°-60°, continued as ψ⁴ below 0.1°, so it holds at the
  grazing angles of a ship radar); ``"constant_gamma"`` — the book's γ sin ψ with Barton's γ
  (§8.12.4), valid for grazing 1°-60° only (:mod:`diffsense.physics.sea_clutter`). Older specs,
  written for the constant-γ model, load unchanged and get the NRL model.
* ``noise_input``: ``"figure"`` (default; ``noise_figure_db``, N = k T0 β F L_rx) or
  ``"temperature"`` (``system_noise_temperature_k``, N = k Ts β L_rx with Ts = Ta + T0 (F − 1),
  IEEE Std 145 / Blake 1986: the two agree when Ta = T0).
* ``geometry``: ``"earth_surface"`` (the radar looks along the surface and through the
  atmosphere), ``"shaft"`` (down a vertical shaft, the ore pass) or ``"auto"`` (default: a shaft
  when the scene holds ``wall_clutter`` and no sea part); see :func:`looks_along_surface`.
"""

from __future__ import annotations

from diffsense.detection.matched_filter import FILTERS
from diffsense.sensors.radar.loss_models import loss_model_options

__all__ = ["PARTS", "OPTIONS", "ATTENUATION_PARTS", "CLUTTER_PARTS", "SURFACE_PARTS", "option",
           "clutter_parts_present", "looks_along_surface"]

PARTS = {
    "gas": "atmospheric gases on the whole path (ITU-R P.676-12, or a given specific attenuation)",
    "rain": "rain on the whole path (ITU-R P.838-3, or a given specific attenuation)",
    "fog": "fog / cloud liquid water on the whole path (ITU-R P.840-7)",
    "dust": "dust on the whole path, Rayleigh absorption, mass loading from visibility (book 7.2.6, 8.14.2)",
    "rain_clutter": "rain volume backscatter in the resolution cell (book 8.14, 9.9.3)",
    "dust_clutter": "dust volume backscatter in the resolution cell (book eq 8.45)",
    "sea_clutter": "sea-surface clutter at the 4/3-earth grazing angle: NRL model (Gregers-Hansen & Mital 2012, "
                   "continued as psi^4 below 0.1 deg) or the book's constant gamma (8.12.4, 8.13), option sea_clutter_model",
    "wall_clutter": "shaft-wall clutter of the ore pass in the range gate (the received echo's width) seen by the "
                    "beam and its sidelobes (book 8.16.6)",
    "multipath": "two-ray sea multipath on the target path, 40 log10|F| (Blake 1986)",
    "closing_target": "a target closing at a constant speed, seen once per scan from a first-look range: the "
                      "cumulative detection probability by range_m (Mallett & Brennan 1963)",
    "jammer": "noise jammer, self-screening or stand-off (book 9.10)",
    "tracking": "range (alpha-beta filter, split gate) and angle (type-2 servo, monopulse) tracking errors at range_m (book 13.4-13.6, 14.6-14.7)",
}
#: the looks a closing target may get (a static bound: the program evaluates Pd at this many ranges)
MAX_LOOKS = 64
#: parts that attenuate the path (one-way specific attenuation in dB/km, uniform along the path)
ATTENUATION_PARTS = ("gas", "rain", "fog", "dust")
#: parts that add clutter to the target's resolution cell
CLUTTER_PARTS = ("rain_clutter", "dust_clutter", "sea_clutter", "wall_clutter")
#: parts that need the radar to look along the earth's (sea) surface
SURFACE_PARTS = ("sea_clutter", "multipath")

OPTIONS = {
    "swerling": (0, (0, 1, 2, 3, 4)),
    "detector": ("square_law", ("square_law", "linear")),
    "integration": ("noncoherent", ("noncoherent", "coherent", "binary")),
    "detectability": ("exact", ("exact", "book", "given", "shnidman", "albersheim", "barton", "chebyshev")),
    "matched_filter": ("two_tuned", ("matched",) + tuple(FILTERS)),
    "antenna": ("circular_aperture", ("circular_aperture", "rectangular_aperture", "specified")),
    "gas_model": ("itu_p676", ("itu_p676", "itu_p676_approx", "specified")),
    "rain_model": ("itu_p838", ("itu_p838", "specified")),
    "rain_clutter_model": ("marshall_palmer", ("marshall_palmer", "specified")),
    "polarization": ("horizontal", ("horizontal", "vertical")),
    "jammer_type": ("self_screening", ("self_screening", "stand_off")),
    "wall_illumination": ("gaussian_beam", ("gaussian_beam", "filled")),
    "tracking_gains": ("benedict_bordner", ("benedict_bordner", "critically_damped")),
    "sea_clutter_model": ("nrl", ("nrl", "constant_gamma")),
    "noise_input": ("figure", ("figure", "temperature")),
    "geometry": ("auto", ("auto", "earth_surface", "shaft")),
    # the options of the modelled budget losses (scan_loss_model, cfar_model, misc_loss_model)
    **loss_model_options(),
}


def option(scene, name):
    """The value of the radar option ``name`` in ``scene``, or its default from :data:`OPTIONS`."""
    return scene.option(name, OPTIONS[name][0])


def clutter_parts_present(scene):
    """The clutter parts of ``scene``, in the order of :data:`CLUTTER_PARTS`."""
    return [c for c in CLUTTER_PARTS if scene.has(c)]


def looks_along_surface(scene):
    """True when the radar of ``scene`` looks along the earth's surface and through the
    atmosphere, False when it looks down a shaft. Option ``geometry``: ``"earth_surface"`` or
    ``"shaft"``; ``"auto"`` decides from the parts: a shaft when the scene holds ``wall_clutter``
    and none of :data:`SURFACE_PARTS` (sea clutter, multipath). Range-height coverage over the
    4/3 earth describes only the first."""
    geometry = option(scene, "geometry")
    if geometry == "auto":
        return not scene.has("wall_clutter") or any(scene.has(part) for part in SURFACE_PARTS)
    return geometry == "earth_surface"
