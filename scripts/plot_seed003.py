#!/usr/bin/python3
"""Figs. 5-8 of seed 003 (TTCSN) from `trackassoc experiment seed003 --output R.h5`.

usage: scripts/plot_seed003.py R.h5 [OUTDIR]
Writes fig5_accuracy.png, fig6_time.png, fig7_recall.png, fig8_precision.png (means over runs,
bars = standard deviation).
"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LABELS = {"ttcsn": "TTCSN (Siamese BiLSTM)", "weighted": "weighted test", "nn": "nearest neighbour",
          "lstm": "LSTM (concatenated)", "bilstm": "BiLSTM (concatenated)"}


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.dirname(os.path.abspath(sys.argv[1]))
    os.makedirs(out, exist_ok=True)
    with h5py.File(sys.argv[1], "r") as f:
        g = f["experiment/seed003"]
        dens = g["densities"][:]
        methods = [k for k in g.keys() if k != "densities"]
        figs = [("accuracy", "Fig. 5: correct association rate", "accuracy [%]", 100, "fig5_accuracy.png"),
                ("seconds", "Fig. 6: time per association", "time [ms]", 1000, "fig6_time.png"),
                ("recall", "Fig. 7: recall", "recall [%]", 100, "fig7_recall.png"),
                ("precision", "Fig. 8: precision", "precision [%]", 100, "fig8_precision.png")]
        for key, title, ylabel, scale, name in figs:
            plt.figure(figsize=(6, 4))
            for m in methods:
                v = g[m][key][:] * scale
                plt.errorbar(dens, v.mean(axis=1), yerr=v.std(axis=1), marker="o", capsize=3, label=LABELS.get(m, m))
            plt.xlabel("track density (targets per scene)")
            plt.ylabel(ylabel)
            plt.title(title)
            plt.grid(alpha=0.3)
            plt.legend()
            plt.tight_layout()
            plt.savefig(os.path.join(out, name), dpi=120)
            plt.close()
            print(os.path.join(out, name))


if __name__ == "__main__":
    main()
