"""Make docs/img/closed_loop.png (the figure of the README and the documentation's front page):
the drogue's displacement in the paper's turbulence case with the controller off, the paper's PID
and the paper's LQR, from the shipped scenarios. Run it after a change that moves these runs:

    .venv/bin/python docs/img/closed_loop.py
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import hosedrogue as hd  # noqa: E402

RUNS = (("paper-turbulence-150", "controller off"), ("paper-turbulence-pid", "PID (paper gains)"),
        ("paper-turbulence-lqr", "LQR (paper Q, R)"))


def main(path=Path(__file__).with_suffix(".png")):
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 4.8), constrained_layout=True)
    for name, label in RUNS:
        res = hd.run(hd.load_scenario(name))
        off = res.drogue_offset_m
        axes[0].plot(res.t_s, off[:, 1], lw=1, label=label)
        axes[1].plot(res.t_s, off[:, 2], lw=1, label=label)
    axes[0].set_ylabel("lateral displacement y [m]")
    axes[1].set_ylabel("vertical displacement z [m]\n(positive down)")
    axes[1].set_xlabel("time t [s]")
    axes[0].set_title("150 m/s, 8000 m, Dryden 1.5 m/s from t = 10 s to 30 s", fontsize=10)
    axes[0].legend(fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.savefig(path, dpi=90)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
