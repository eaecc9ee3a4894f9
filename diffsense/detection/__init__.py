"""Detection theory: thresholds, exact detection probability for Swerling 0-4, required SNR,
approximations, binary (M-of-N) integration, losses (fluctuation, integration, beam shape, array scan, straddle, eclipsing,
MTI, STC, quantisation), blind speeds, cumulative detection probability,
CA-, OS-, GO- and SO-CFAR and matched-filter mismatch.

Public contract: :func:`threshold`, :func:`pd`, :func:`required_snr_db` (other tools call them).
``swerling`` and ``method`` are static arguments; every other argument may be an array and is
broadcast, and every function is jit/vmap/grad-able.
"""

from diffsense.detection.binary import optimum_m_binary, pd_binary, per_trial_pfa_binary, required_snr_binary_db
from diffsense.detection.cfar import cfar_loss_db, cfar_multiplier, cfar_pd
from diffsense.detection.cfar_greatest_smallest import (
    go_cfar_loss_db,
    go_cfar_multiplier,
    go_cfar_pd,
    go_cfar_pfa,
    go_cfar_required_snr_db,
    so_cfar_loss_db,
    so_cfar_multiplier,
    so_cfar_pd,
    so_cfar_pfa,
    so_cfar_required_snr_db,
)
from diffsense.detection.cfar_ordered import (
    os_cfar_loss_db,
    os_cfar_multiplier,
    os_cfar_pd,
    os_cfar_pfa,
    os_cfar_required_snr_db,
)
from diffsense.detection.chebyshev_snr import chebyshev_snr_db
from diffsense.detection.core import pd_given_threshold
from diffsense.detection.cumulative import closing_target_ranges_m, cumulative_pd, cumulative_pd_closing
from diffsense.detection.mti import (
    blind_speeds_mps,
    first_blind_speed_mps,
    mti_blind_phase_loss_db,
    mti_integration_loss_db,
    mti_noise_gain,
    mti_velocity_response,
)
from diffsense.detection.receiver_losses import quantisation_loss_db, quantisation_noise_db, stc_gain_db, stc_loss_db
from diffsense.detection.gaussian import gaussian_detection_probability, gaussian_required_deflection
from diffsense.detection.losses import fluctuation_loss_db, integration_gain_db, integration_loss_db
from diffsense.detection.matched_filter import matched_filter_loss_db, optimum_bandwidth_time_product
from diffsense.detection.scan_losses import (
    beam_shape_loss_db,
    doppler_straddle_loss_average_db,
    doppler_straddle_loss_db,
    eclipsing_loss_average_db,
    eclipsing_loss_db,
    range_straddle_loss_average_db,
    range_straddle_loss_db,
    scan_sector_loss_db,
)
from diffsense.detection.probability import db_to_linear, linear_to_db, pd, pd_coherent
from diffsense.detection.required_snr import (
    BOOK_SDLA_EXTRA_PULSES,
    albersheim_snr_db,
    book_integration_gain_db,
    book_pulses_for_integration_gain,
    required_snr_db,
    shnidman_snr_db,
)
from diffsense.detection.threshold import (
    false_alarm_time_s,
    pfa_from_false_alarm_time,
    pfa_from_threshold,
    threshold,
    voltage_threshold,
)

__all__ = [
    "pd_binary",
    "required_snr_binary_db",
    "optimum_m_binary",
    "per_trial_pfa_binary",
    "threshold",
    "pfa_from_threshold",
    "voltage_threshold",
    "pfa_from_false_alarm_time",
    "false_alarm_time_s",
    "pd",
    "pd_coherent",
    "pd_given_threshold",
    "required_snr_db",
    "albersheim_snr_db",
    "shnidman_snr_db",
    "chebyshev_snr_db",
    "book_integration_gain_db",
    "book_pulses_for_integration_gain",
    "BOOK_SDLA_EXTRA_PULSES",
    "fluctuation_loss_db",
    "integration_gain_db",
    "integration_loss_db",
    "cfar_multiplier",
    "cfar_pd",
    "cfar_loss_db",
    "os_cfar_multiplier",
    "os_cfar_pfa",
    "os_cfar_pd",
    "os_cfar_required_snr_db",
    "os_cfar_loss_db",
    "go_cfar_multiplier",
    "go_cfar_pfa",
    "go_cfar_pd",
    "go_cfar_required_snr_db",
    "go_cfar_loss_db",
    "so_cfar_multiplier",
    "so_cfar_pfa",
    "so_cfar_pd",
    "so_cfar_required_snr_db",
    "so_cfar_loss_db",
    "matched_filter_loss_db",
    "optimum_bandwidth_time_product",
    "beam_shape_loss_db",
    "scan_sector_loss_db",
    "range_straddle_loss_db",
    "range_straddle_loss_average_db",
    "doppler_straddle_loss_db",
    "doppler_straddle_loss_average_db",
    "eclipsing_loss_db",
    "eclipsing_loss_average_db",
    "cumulative_pd",
    "cumulative_pd_closing",
    "closing_target_ranges_m",
    "blind_speeds_mps",
    "first_blind_speed_mps",
    "mti_velocity_response",
    "mti_noise_gain",
    "mti_integration_loss_db",
    "mti_blind_phase_loss_db",
    "stc_gain_db",
    "stc_loss_db",
    "quantisation_noise_db",
    "quantisation_loss_db",
    "gaussian_detection_probability",
    "gaussian_required_deflection",
    "db_to_linear",
    "linear_to_db",
]
