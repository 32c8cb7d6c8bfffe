#!/usr/bin/env python3
"""Plot for the arm sweep (./sbt "run sweep --arms"): usage plot_arms.py ARMS_CSV OUT_DIR.

arms_pareto.png: per robot, estimated logic elements and 18x18 multipliers against samples/s (both
axes logarithmic), the Pareto front (no other point has at least the rate with fewer LEs and fewer
multipliers) joined by a line, the EP4CE30's 28,848 LEs and 66 multipliers as dashed lines.
Runs itself inside tools/sweep/.venv (pinned requirements.txt), created on first use.
"""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot import ensure_venv  # noqa: E402


def pareto(rows):
    """Rows no other row dominates: at least the rate, at most the LEs and the multipliers, one strictly better."""
    def dominates(a, b):
        ge = a["rate"] >= b["rate"] and a["les"] <= b["les"] and a["mult"] <= b["mult"]
        gt = a["rate"] > b["rate"] or a["les"] < b["les"] or a["mult"] < b["mult"]
        return ge and gt
    return [r for r in rows if not any(dominates(o, r) for o in rows)]


def main():
    ensure_venv()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    src, out = sys.argv[1], sys.argv[2]
    with open(src, newline="") as f:
        rows = [dict(robot=r["robot"], name=r["schedule"], rate=float(r["samples_per_s"]), les=int(r["est_les"]),
                     mult=int(r["est_mult18x18"])) for r in csv.DictReader(f)]
    robots = sorted({r["robot"] for r in rows}, key=[r["robot"] for r in rows].index)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for ax, key, label, limit in ((axes[0], "les", "estimated logic elements", 28848), (axes[1], "mult", "18x18 multipliers", 66)):
        for robot in robots:
            pts = [r for r in rows if r["robot"] == robot]
            line = ax.scatter([p["rate"] for p in pts], [p[key] for p in pts], label=robot)
            front = sorted(pareto(pts), key=lambda p: p["rate"])
            ax.plot([p["rate"] for p in front], [p[key] for p in front], color=line.get_facecolor()[0], linewidth=1)
            for p in pts:
                ax.annotate(p["name"], (p["rate"], p[key]), fontsize=6, xytext=(3, 3), textcoords="offset points")
        ax.axhline(limit, linestyle="--", color="grey", linewidth=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("samples/s")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    fig.suptitle("Arm datapaths over the schedule (lines: Pareto front; dashed: EP4CE30)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "arms_pareto.png"), dpi=120)


if __name__ == "__main__":
    main()
