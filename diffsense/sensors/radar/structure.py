"""What a radar scene may hold: its parts, the groups of parts the chain treats alike, and its
static options with their defaults and allowed values.

The parts and options are static structure (:class:`diffsense.sensors.structure.Scene`): they
decide, at trace time, which terms the radar chain builds.
"""

from __future__ import annotations

from diffsense.detection.matched_filter import FILTERS

__all__ = ["PARTS", "OPTIONS", "ATTENUATION_PARTS", "CLUTTER_PARTS", "option", "clutter_parts_present"]

PARTS = {
    "gas": "atmospheric gases on the whole path (ITU-R P.676-12, or a given specific attenuation)",
    "rain": "rain on the whole path (ITU-R P.838-3, or a given specific attenuation)",
    "fog": "fog / cloud liquid water on the whole path (ITU-R P.840-7)",
    "dust": "dust on the whole path, Rayleigh absorption, mass loading from visibility (book 7.2.6, 8.14.2)",
    "rain_clutter": "rain volume backscatter in the resolution cell (book 8.14, 9.9.3)",
    "dust_clutter": "dust volume backscatter in the resolution cell (book eq 8.45)",
    "sea_clutter": "sea-surface clutter, Barton's constant gamma (book 8.12.4, 8.13)",
    "wall_clutter": "shaft-wall clutter of the ore pass in the range gate c tau/2 seen by the beam (book 8.16.6)",
    "multipath": "two-ray sea multipath on the target path, 40 log10|F| (Blake 1986)",
    "jammer": "noise jammer, self-screening or stand-off (book 9.10)",
    "tracking": "range (alpha-beta filter, split gate) and angle (type-2 servo, monopulse) tracking errors at range_m (book 13.4-13.6, 14.6-14.7)",
}
#: parts that attenuate the path (one-way specific attenuation in dB/km, uniform along the path)
ATTENUATION_PARTS = ("gas", "rain", "fog", "dust")
#: parts that add clutter to the target's resolution cell
CLUTTER_PARTS = ("rain_clutter", "dust_clutter", "sea_clutter", "wall_clutter")

OPTIONS = {
    "swerling": (0, (0, 1, 2, 3, 4)),
    "detector": ("square_law", ("square_law", "linear")),
    "integration": ("noncoherent", ("noncoherent", "coherent")),
    "detectability": ("exact", ("exact", "book", "given")),
    "matched_filter": ("two_tuned", ("matched",) + tuple(FILTERS)),
    "antenna": ("circular_aperture", ("circular_aperture", "specified")),
    "gas_model": ("itu_p676", ("itu_p676", "specified")),
    "rain_model": ("itu_p838", ("itu_p838", "specified")),
    "rain_clutter_model": ("marshall_palmer", ("marshall_palmer", "specified")),
    "polarization": ("horizontal", ("horizontal", "vertical")),
    "jammer_type": ("self_screening", ("self_screening", "stand_off")),
    "wall_illumination": ("gaussian_beam", ("gaussian_beam", "filled")),
    "tracking_gains": ("benedict_bordner", ("benedict_bordner", "critically_damped")),
}


def option(scene, name):
    """The value of the radar option ``name`` in ``scene``, or its default from :data:`OPTIONS`."""
    return scene.option(name, OPTIONS[name][0])


def clutter_parts_present(scene):
    """The clutter parts of ``scene``, in the order of :data:`CLUTTER_PARTS`."""
    return [c for c in CLUTTER_PARTS if scene.has(c)]
