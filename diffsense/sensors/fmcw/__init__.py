"""FMCW radar: the registered chain, kind ``"fmcw"`` (:mod:`.chain`), its window table
(:mod:`.windows`), the leakage phase-noise floor (:mod:`.leakage`) and its parameter tables
(:mod:`.parameters`)."""

from diffsense.sensors.fmcw.chain import OPTIONS, PARTS, FmcwChain, noise_bandwidth_factor
from diffsense.sensors.fmcw.leakage import leakage_noise_dbw, phase_noise_dbc_hz, range_correlation_db
from diffsense.sensors.fmcw.windows import WINDOWS, noise_bandwidth_bins, scalloping_loss_db

__all__ = ["FmcwChain", "PARTS", "OPTIONS", "noise_bandwidth_factor", "leakage_noise_dbw", "phase_noise_dbc_hz",
           "range_correlation_db", "WINDOWS", "noise_bandwidth_bins", "scalloping_loss_db"]
