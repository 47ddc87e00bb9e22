#!/usr/bin/env python3
"""Plot the NEES curves written by vio_core_nees_test (CSV -> PNG).

Usage: plot_nees.py BUILD_DIR/vio_core_nees [OUT_DIR]
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main() -> int:
    src = pathlib.Path(sys.argv[1])
    out = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else src
    out.mkdir(parents=True, exist_ok=True)
    files = sorted(src.glob("nees_*.csv"))
    if not files:
        print(f"no nees_*.csv in {src}", file=sys.stderr)
        return 1
    for f in files:
        header = f.read_text().splitlines()[0].lstrip("# ").split()
        meta = dict(kv.split("=") for kv in header)
        d = np.genfromtxt(f, delimiter=",", skip_header=2)
        fig, ax = plt.subplots(figsize=(8, 4))
        for col, name in ((1, "orientation"), (2, "position"), (3, "F_ext")):
            if np.any(d[:, col] != 0):
                ax.plot(d[:, 0], d[:, col], label=name)
        for key in ("band_lo", "band_hi"):
            ax.axhline(float(meta[key]), color="k", ls="--", lw=0.8)
        ax.set_xlabel("t [s]")
        ax.set_ylabel(f"average NEES over {meta['runs']} runs (3 dof)")
        ax.set_title(f.stem)
        ax.legend()
        ax.grid(alpha=0.3)
        fig.tight_layout()
        png = out / (f.stem + ".png")
        fig.savefig(png, dpi=110)
        print(png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
