#!/usr/bin/env python3
"""Golden traces for the joint-3 reducer load, from an independent reference.

The reference is Pinocchio's RNEA on a planar 3R arm built from the robot parameters (point mass m3
at the end of link 3, massless links 1 and 2, gravity along +x so that t1 = 0 points link 1 down).
The closed-form exact torque (SPEC.md tau3) and the paper's equation (6) are written beside it; the
script stops if RNEA and the closed form disagree by more than 1e-9 N*m on any row.

Regenerate (from the repository root):
    python3 -m venv .venv-golden && .venv-golden/bin/pip install -r golden/requirements.txt
    .venv-golden/bin/python golden/make_golden.py
"""
import math
import os
import sys

import numpy as np
import pinocchio as pin

ROBOT = dict(m3=10.0, l1=0.4, l2=0.35, l3=0.3, g=9.81)
DMAX, DDMAX = 3.0, 10.0
HERE = os.path.dirname(os.path.abspath(__file__))
COMMAND = ".venv-golden/bin/python golden/make_golden.py   (setup: python3 -m venv .venv-golden && .venv-golden/bin/pip install -r golden/requirements.txt)"
HEADER = ["t1", "t2", "t3", "d1", "d2", "d3", "dd1", "dd2", "dd3", "tau3_rnea", "tau3_exact", "tau3_paper"]


def build_arm(r):
    model = pin.Model()
    model.gravity.linear = np.array([r["g"], 0.0, 0.0])
    parent = 0
    for name, offset in (("j1", 0.0), ("j2", r["l1"]), ("j3", r["l2"])):
        placement = pin.SE3(np.eye(3), np.array([offset, 0.0, 0.0]))
        parent = model.addJoint(parent, pin.JointModelRZ(), placement, name)
    point_mass = pin.Inertia(r["m3"], np.array([r["l3"], 0.0, 0.0]), np.zeros((3, 3)))
    model.appendBodyToJoint(parent, point_mass, pin.SE3.Identity())
    return model, model.createData()


def closed_form(r, s, dd2_weight):
    t1, t2, t3, d1, d2, d3, dd1, dd2, dd3 = s
    m3, l1, l2, l3, g = r["m3"], r["l1"], r["l2"], r["l3"], r["g"]
    return (m3 * l1 * l3 * dd1 * math.cos(t2 + t3)
            + m3 * l2 * l3 * (dd1 + dd2_weight * dd2) * math.cos(t3)
            + m3 * l1 * l3 * d1 ** 2 * math.sin(t2 + t3)
            + m3 * l2 * l3 * (d1 + d2) ** 2 * math.sin(t3)
            + m3 * l3 ** 2 * (dd1 + dd2 + dd3)
            + m3 * g * l3 * math.sin(t1 + t2 + t3))


def multiturn():
    """Constant speed plus a sinusoid: every joint angle covers the full circle (10 s, 5 ms steps)."""
    rows = []
    omega, phase = (1.2, -1.6, 2.0), (0.3, -2.0, 1.0)
    amp, freq = 0.4, 2.5  # |d| <= |omega| + amp*freq <= 3, |dd| <= amp*freq^2 = 2.5
    for k in range(2000):
        t = k * 0.005
        q = [phase[i] + omega[i] * t + amp * math.sin(freq * t + i) for i in range(3)]
        d = [omega[i] + amp * freq * math.cos(freq * t + i) for i in range(3)]
        dd = [-amp * freq ** 2 * math.sin(freq * t + i) for i in range(3)]
        rows.append(q + d + dd)
    return rows


def rest_to_rest(rng):
    """Quintic point-to-point moves between random poses, at rest at both ends of every move."""
    rows, pose = [], rng.uniform(-math.pi, math.pi, 3)
    for _ in range(5):
        target = rng.uniform(-math.pi, math.pi, 3)
        delta = target - pose
        span = max(np.max(np.abs(delta)), 1e-3)
        duration = max(1.875 * span / (0.9 * DMAX), math.sqrt(5.7735 * span / (0.9 * DDMAX)), 0.5)
        for k in range(200):
            tau = k / 199.0
            s = 10 * tau ** 3 - 15 * tau ** 4 + 6 * tau ** 5
            sd = (30 * tau ** 2 - 60 * tau ** 3 + 30 * tau ** 4) / duration
            sdd = (60 * tau - 180 * tau ** 2 + 120 * tau ** 3) / duration ** 2
            rows.append(list(pose + s * delta) + list(sd * delta) + list(sdd * delta))
        pose = target
    return rows


def random_samples(rng):
    """Uniform over the declared ranges."""
    q = rng.uniform(-math.pi, math.pi, (2000, 3))
    d = rng.uniform(-DMAX, DMAX, (2000, 3))
    dd = rng.uniform(-DDMAX, DDMAX, (2000, 3))
    return [list(q[i]) + list(d[i]) + list(dd[i]) for i in range(2000)]


def edge_cases():
    """Quadrant boundaries (and just either side), angle sums on boundaries, extremes of both signs, rest."""
    rows = []
    bounds = [0.0, math.pi / 2, math.pi, 3 * math.pi / 2, 2 * math.pi]
    for b in bounds:
        for eps in (0.0, 1e-9, -1e-9, 1e-6, -1e-6):
            a = b + eps
            rows.append([a, a, a] + [0.0] * 6)
            rows.append([0.0, 0.0, a] + [DMAX, -DMAX, DMAX] + [DDMAX, -DDMAX, DDMAX])
    for b in bounds[:4]:  # t2+t3 and t1+t2+t3 exactly on boundaries with t2, t3 off them
        rows.append([b - 0.7, 0.7 - 0.3, 0.3 + b - b] + [-DMAX, DMAX, 0.0] + [-DDMAX, DDMAX, -DDMAX])
        rows.append([0.25, b - 0.25 - 0.4, 0.4] + [DMAX, DMAX, DMAX] + [DDMAX, DDMAX, DDMAX])
    for signs in range(64):  # every sign combination of the six extremes, at a fixed pose
        sv = [1.0 if signs >> j & 1 else -1.0 for j in range(6)]
        rows.append([0.9, -2.1, 2.6] + [sv[0] * DMAX, sv[1] * DMAX, sv[2] * DMAX] + [sv[3] * DDMAX, sv[4] * DDMAX, sv[5] * DDMAX])
    rows.append([0.0] * 9)
    rows.append([1.0, 2.0, 3.0] + [0.0] * 6)
    return rows


def write(name, description, seed, rows, model, data):
    worst, max_load, max_paper_gap = 0.0, 0.0, 0.0
    lines = []
    for s in rows:
        for v, lim in zip(s[3:], [DMAX] * 3 + [DDMAX] * 3):
            if abs(v) > lim * (1 + 1e-12):
                sys.exit(f"{name}: value {v} beyond the declared range {lim}")
        tau = pin.rnea(model, data, np.array(s[:3]), np.array(s[3:6]), np.array(s[6:9]))
        rnea = float(tau[2])
        exact = closed_form(ROBOT, s, 1)
        paper = closed_form(ROBOT, s, 2)
        worst = max(worst, abs(rnea - exact))
        max_load = max(max_load, abs(exact))
        max_paper_gap = max(max_paper_gap, abs(paper - exact))
        lines.append(",".join(repr(float(v)) for v in list(s) + [rnea, exact, paper]))
    if worst > 1e-9:
        sys.exit(f"{name}: Pinocchio RNEA and the closed-form torque disagree by {worst:.3e} N*m")
    robot = " ".join(f"{k}={v:g}" for k, v in ROBOT.items())
    header = [
        f"# {name}: {description}",
        f"# regenerate: {COMMAND}",
        f"# reference: Pinocchio {pin.__version__} RNEA (tau3_rnea); closed forms tau3_exact (SPEC.md) and tau3_paper (equation (6)); |rnea - exact| <= {worst:.1e}",
        f"# seed: {seed}",
        f"# robot: {robot}",
        f"# ranges: dmax={DMAX:g} ddmax={DDMAX:g}",
        "# units: t1,t2,t3 rad; d1,d2,d3 rad/s; dd1,dd2,dd3 rad/s^2; tau3_rnea,tau3_exact,tau3_paper N*m",
    ]
    with open(os.path.join(HERE, name + ".csv"), "w") as f:
        f.write("\n".join(header + [",".join(HEADER)] + lines) + "\n")
    print(f"| {name}.csv | {len(rows)} | {worst:.1e} | {max_load:.3f} | {max_paper_gap:.3f} |")


def main():
    model, data = build_arm(ROBOT)
    print("| file | rows | max abs(rnea - exact) N*m | max abs(tau3) N*m | max abs(paper - exact) N*m |")
    print("| --- | --- | --- | --- | --- |")
    write("multiturn", "smooth multi-turn trajectory, every angle covers the full circle", "none", multiturn(), model, data)
    write("rest_to_rest", "five quintic point-to-point moves between random poses", 7, rest_to_rest(np.random.default_rng(7)), model, data)
    write("random", "uniform random samples over the declared ranges", 11, random_samples(np.random.default_rng(11)), model, data)
    write("edge_cases", "quadrant boundaries, angle sums on boundaries, extremes of both signs, rest", "none", edge_cases(), model, data)


if __name__ == "__main__":
    main()
