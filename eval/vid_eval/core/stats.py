"""Summary statistics of an error vector (the set evo and rpg_trajectory_evaluation report)."""
from __future__ import annotations

from typing import Dict

import numpy as np


def error_stats(err: np.ndarray) -> Dict[str, float]:
    """rmse, mean, median, std, min, max and count of a 1-D error array."""
    e = np.asarray(err, dtype=float).ravel()
    if e.size == 0:
        return {"rmse": float("nan"), "mean": float("nan"), "median": float("nan"),
                "std": float("nan"), "min": float("nan"), "max": float("nan"), "count": 0}
    return {
        "rmse": float(np.sqrt(np.mean(e * e))),
        "mean": float(np.mean(e)),
        "median": float(np.median(e)),
        "std": float(np.std(e)),
        "min": float(np.min(e)),
        "max": float(np.max(e)),
        "count": int(e.size),
    }
