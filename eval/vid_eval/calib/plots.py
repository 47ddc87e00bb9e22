"""Plots of the calibration tools: thrust-fit residuals and Allan deviations."""
from __future__ import annotations

from pathlib import Path
from typing import Dict

import numpy as np

from ..plots.style import ERR_COLOR, EST_COLOR, GT_COLOR, new_figure, save
from .thrust_fit import FitInput, ThrustFit


def plot_thrust_residuals(data: FitInput, fit: ThrustFit, path: Path, t0_ns: int, unit: str) -> Path:
    """Three panels: measured vs predicted a_z over time, the residual over time (with its 1 s
    mean: slow structure means bias drift or an unmodelled force), and the residual's mean
    per bin of predicted thrust (a slope or bend means the n^2 model or the mass is off)."""
    fig, axes = new_figure(3, 1, width=11, height=9)
    t = (data.t_ns - t0_ns) * 1e-9
    ax = axes[0]
    ax.plot(t, data.accel_z, color=GT_COLOR, lw=0.4, alpha=0.5, label="accelerometer z")
    ax.plot(t, fit.predicted, color=EST_COLOR, lw=1.0, label="fit: sum k_i n_i² / m + b_z")
    ax.set_ylabel("a_z [m/s²]")
    ax.set_title(f"{fit.model} thrust fit, k = " + ", ".join(f"{k:.4e}" for k in np.unique(fit.coefficients))
                 + f" N/({unit})², residual RMS {fit.rms:.3f} m/s²")
    ax.legend(loc="upper right")
    ax = axes[1]
    ax.plot(t, fit.residuals, color=ERR_COLOR, lw=0.3, alpha=0.4, label="residual")
    n = max(1, int(round(1.0 / max(np.median(np.diff(t)), 1e-6))))
    if len(t) >= n:
        smooth = np.convolve(fit.residuals, np.ones(n) / n, mode="valid")
        ax.plot(t[n - 1:], smooth, color=GT_COLOR, lw=1.2, label="1 s mean")
    ax.set_ylabel("residual [m/s²]")
    ax.set_xlabel("time [s]")
    ax.legend(loc="upper right")
    ax = axes[2]
    edges = np.quantile(fit.predicted, np.linspace(0, 1, 21))
    idx = np.clip(np.searchsorted(edges, fit.predicted, side="right") - 1, 0, 19)
    mean = np.array([fit.residuals[idx == b].mean() if np.any(idx == b) else np.nan for b in range(20)])
    sem = np.array([fit.residuals[idx == b].std() / np.sqrt(max(np.sum(idx == b), 1)) for b in range(20)])
    centers = 0.5 * (edges[1:] + edges[:-1])
    ax.errorbar(centers, mean, yerr=3 * sem, fmt="o", color=EST_COLOR, label="mean residual per bin ±3 s.e.")
    ax.axhline(0.0, color=GT_COLOR, lw=0.8)
    ax.set_xlabel("predicted a_z [m/s²]")
    ax.set_ylabel("residual [m/s²]")
    ax.legend(loc="upper right")
    return save(fig, path.parent if str(path.parent) else Path("."), path.name)


def plot_allan(taus: Dict[str, np.ndarray], adevs: Dict[str, np.ndarray], models: Dict[str, np.ndarray],
               path: Path) -> Path:
    """Allan deviation per axis (gyroscope and accelerometer panels) with the fitted model
    sigma^2 = N^2/tau + K^2 tau/3 + (2 ln2/pi) B^2."""
    fig, axes = new_figure(1, 2, width=12, height=5)
    colors = ("tab:red", "tab:green", "tab:blue")
    for ax, sensor, unit in ((axes[0], "gyroscope", "rad/s"), (axes[1], "accelerometer", "m/s²")):
        for a, axis in enumerate("xyz"):
            key = f"{sensor}_{axis}"
            ax.loglog(taus[key], adevs[key], "o", ms=3, color=colors[a], label=f"{axis}")
            ax.loglog(taus[key], models[key], "-", lw=1, color=colors[a])
        ax.set_xlabel("τ [s]")
        ax.set_ylabel(f"Allan deviation [{unit}]")
        ax.set_title(f"{sensor}: measured (points), fitted model (lines)")
        ax.legend(loc="upper right")
    return save(fig, path.parent if str(path.parent) else Path("."), path.name)
