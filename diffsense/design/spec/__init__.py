"""Requirement specifications (``designs/*.toml``): reading and validation.

A spec says what a sensor must achieve and what the designer may change::

    name = "ore_pass"
    title = "Ore-pass level radar (Brooker 8.16)"
    sensor = "radar"                       # a chain kind (diffsense.scene.CHAINS)
    parts = ["dust"]                       # scene parts present in every case
    [options]                              # static scene options
    swerling = 1
    [fixed]                                # parameter values, with units
    range_m = "300 m"
    [variables.antenna_diameter_m]         # a continuous design variable
    lower = "100 mm"
    upper = "600 mm"
    initial = "250 mm"                     # optional; scale = "log" | "linear" (optional)
    [variables.n_pulses]                   # integer variable (relaxed, then rounded)
    lower = 1
    upper = 64
    integer = true
    [variables.freq_hz]                    # a catalog choice of one parameter
    choices = ["35 GHz", "94 GHz"]
    [choices.transmitter]                  # a catalog choice setting several parameters at once
    options = [ { name = "Gunn", peak_power_w = "20 dBm", cost = 1.0 },
                { name = "IMPATT", peak_power_w = "30 dBm", cost = 3.0 } ]
    [cases.sea_skimmer]                    # optional evaluation cases (override fixed values,
    parts = ["multipath"]                  # add parts); without cases there is one case "main"
    rcs_m2 = "0.1 m^2"
    [uncertain]                            # optional: inputs known by a distribution (:mod:`.uncertain`)
    noise_figure_db = { normal = "5 dB", sigma = "0.5 dB" }
    [[requirements]]
    output = "snr_margin_db"               # "<case>.<output>" when there are several cases
    at_least = "0 dB"                      # or at_most / equals
    probability = 0.95                     # optional: met with this probability over [uncertain]
    goal = "3 dB"                          # optional: the objective beyond the threshold (PASS/WARN/FAIL)
    [objective]
    minimize = "antenna_diameter_m"        # a parameter, an output, "cost", or a weighted sum
                                           # { antenna_diameter_m = 1.0, cost = 0.1 }

Every problem is reported as one :class:`SpecError` naming the file, the key and what is
wrong; nothing is silently dropped or clamped.

One module per section (:mod:`.cases`, :mod:`.variables`, :mod:`.choices`, :mod:`.fixed`,
:mod:`.requirements`, :mod:`.objective`); :mod:`.parse` reads them in order and :mod:`.types`
holds the validated result. :mod:`diffsense.design.evaluable` checks, once, that the chain has a finite answer
at the initial design and the corners of the box (the command line runs it after loading).
"""

from diffsense.design.spec.parse import load_spec, parse_spec
from diffsense.design.spec.types import DEFAULT_CASE, SENSES, Choice, Objective, Requirement, Spec, Variable

__all__ = ["load_spec", "parse_spec", "Spec", "Variable", "Choice", "Requirement", "Objective", "SENSES",
           "DEFAULT_CASE"]
