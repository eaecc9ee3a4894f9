"""Detection figures: Pd versus SNR (Brooker's figure style) and ROC curves."""

from __future__ import annotations

import numpy as np

from diffsense.detection.probability import pd as _pd

__all__ = ["pd_vs_snr_figure", "roc_figure"]

_SWERLING_LABEL = {0: "Swerling 0 (steady)", 1: "Swerling 1", 2: "Swerling 2", 3: "Swerling 3", 4: "Swerling 4"}


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def pd_vs_snr_figure(pfa=1e-6, n=1, swerlings=(0, 1, 2, 3, 4), snr_db=(-5.0, 30.0)):
    """Figure of Pd against mean single-pulse SNR (dB) for several Swerling cases."""
    plt = _pyplot()
    x = np.linspace(snr_db[0], snr_db[1], 351)
    fig, ax = plt.subplots(figsize=(7.5, 5.0), dpi=120)
    for sw in swerlings:
        ax.plot(x, np.asarray(_pd(x, pfa, float(n), sw)), label=_SWERLING_LABEL[sw])
    ax.set_xlabel("Mean single-pulse SNR (dB)")
    ax.set_ylabel("Probability of detection Pd")
    ax.set_title(f"Square-law detector, N = {n:g} pulses noncoherent, Pfa = {pfa:.0e}")
    ax.set_ylim(0.0, 1.0)
    ax.set_xlim(x[0], x[-1])
    ax.grid(True, alpha=0.4)
    ax.legend(loc="lower right")
    fig.tight_layout()
    return fig


def roc_figure(snr_db_values=(3.0, 6.0, 9.0, 12.0, 15.0), n=1, swerling=0, pfa_range=(1e-12, 0.5)):
    """Receiver operating characteristics: Pd against Pfa (log axis) for several SNRs (dB)."""
    plt = _pyplot()
    pfa = np.logspace(np.log10(pfa_range[0]), np.log10(pfa_range[1]), 300)
    fig, ax = plt.subplots(figsize=(7.5, 5.0), dpi=120)
    snr = np.asarray(snr_db_values, dtype=float)[:, None]
    curves = np.asarray(_pd(snr, pfa[None, :], float(n), swerling))
    for s, curve in zip(snr_db_values, curves):
        ax.semilogx(pfa, curve, label=f"SNR = {s:g} dB")
    ax.set_xlabel("Probability of false alarm Pfa")
    ax.set_ylabel("Probability of detection Pd")
    ax.set_title(f"ROC, {_SWERLING_LABEL[swerling]}, N = {n:g}")
    ax.set_ylim(0.0, 1.0)
    ax.grid(True, which="both", alpha=0.4)
    ax.legend(loc="center left", bbox_to_anchor=(0.01, 0.5), framealpha=0.9)
    fig.tight_layout()
    return fig
