#!/usr/bin/env python3
"""Plots for the design-space sweep (./sbt "run sweep"): usage plot.py SWEEP_CSV OUT_DIR.

error_vs_les.png: max load error against estimated logic elements, Pareto front marked, paper's
point beside them. memory_vs_precision.png: constant-storage bits against sin/cos precision for a
CORDIC (its arctan table) and a plain quarter-wave lookup table, as in the paper's table 3.
Runs itself inside tools/sweep/.venv (pinned requirements.txt), created on first use.
"""
import csv
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
VENV = os.path.join(HERE, ".venv")


def ensure_venv():
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
        subprocess.run([os.path.join(VENV, "bin", "pip"), "install", "-q", "-r", os.path.join(HERE, "requirements.txt")], check=True)
    os.execv(py, [py] + sys.argv)


def main():
    ensure_venv()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    src, out = sys.argv[1], sys.argv[2]
    rows = list(csv.DictReader(open(src)))
    les = [int(r["est_les"]) for r in rows]
    err = [float(r["max_error_nm"]) for r in rows]
    front = [i for i in range(len(rows)) if not any(les[j] <= les[i] and err[j] <= err[i] and (les[j], err[j]) != (les[i], err[i]) for j in range(len(rows)))]
    front.sort(key=lambda i: les[i])

    fig, ax = plt.subplots(figsize=(8, 5.5))
    kinds = (("classic", "o", "classic CORDIC"), ("residual", "s", "residual-rotation CORDIC"), ("table", "^", "table + residual CORDIC"))
    kind = lambda r: "table" if "+table" in r["cordic"] else r["cordic"]
    for arch, marker, label in kinds:
        idx = [i for i, r in enumerate(rows) if kind(r) == arch]
        ax.scatter([les[i] for i in idx], [err[i] for i in idx], marker=marker, label=label)
    ax.plot([les[i] for i in front], [err[i] for i in front], "k--", lw=1, label="Pareto front")
    # One label per spot: configurations with the same error and LEs within 2 % share it.
    spots = []
    for i, r in enumerate(rows):
        spot = next((sp for sp in spots if err[sp[0]] == err[i] and abs(les[sp[0]] - les[i]) <= 0.02 * les[i]), None)
        if spot is None:
            spots.append([i])
        else:
            spot.append(i)
    right_edge = max(les) / 1.6  # labels of the rightmost points go below left, inside the axes
    for spot in spots:
        x = les[spot[0]]
        right = x > right_edge
        ax.annotate("\n".join(rows[i]["config"] for i in spot), (x, err[spot[0]]), fontsize=7, va="top" if right else "bottom",
                    ha="right" if right else "left", xytext=(-4, -3) if right else (4, 3), textcoords="offset points")
    ax.scatter([4330], [1e-3], marker="*", s=160, c="red", label="paper (4,330 LEs, < 1e-3 N·m)")
    ax.axhline(1e-4, color="gray", lw=0.8, ls=":")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("estimated Cyclone IV E logic elements (open-tool estimate)")
    ax.set_ylabel("max |load error| over golden traces (N·m)")
    ax.set_title("Load error against size")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "error_vs_les.png"), dpi=120)

    # Constant storage against precision (paper, table 3): a CORDIC stores one arctan per iteration
    # (iterations ~ precision bits, each ~precision+guard bits wide); a quarter-wave table of sin
    # with the same precision needs 2^(bits-2) entries of `bits` bits (angle step ~ value step).
    bits = list(range(8, 25))
    cordic = [b * (b + 4) for b in bits]
    table = [2 ** (b - 2) * b for b in bits]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(bits, cordic, "o-", label="CORDIC arctan table (iterations x width)")
    ax.plot(bits, table, "s-", label="quarter-wave lookup table")
    ax.set_yscale("log")
    ax.set_xlabel("sin/cos precision (bits)")
    ax.set_ylabel("memory bits")
    ax.set_title("Memory for sin/cos: CORDIC against a lookup table")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "memory_vs_precision.png"), dpi=120)
    print(f"plots: {os.path.join(out, 'error_vs_les.png')}, {os.path.join(out, 'memory_vs_precision.png')}")


if __name__ == "__main__":
    main()
