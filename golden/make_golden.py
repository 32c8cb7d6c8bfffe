#!/usr/bin/env python3
"""Golden traces for the joint-3 reducer load, from an independent reference.

The reference is Pinocchio's RNEA on a planar 3R arm built from the robot parameters: three revolute
joints about z, link lengths along each link's x axis, a point mass m3 at the end of link 3, links 1
and 2 with no body at all (exactly zero mass), gravity along +x so that t1 = 0 points link 1 down and
the gravity term is +m3 g l3 sin(t1+t2+t3). Beside it go the closed-form exact torque (tau3 of docs/equations.md)
and the paper's equation (6) as written; the script stops if RNEA and the closed form disagree by
more than 1e-9 N*m on any row, if any sample leaves the declared ranges, or if a trajectory's
velocities and accelerations are not the derivatives of its angles.

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
ANGLE_LIMIT = 4 * math.pi  # angles are any real number; the traces keep them in [-4 pi, 4 pi]
TOLERANCE = 1e-9  # N*m, RNEA against the closed form
SEED_REST_TO_REST, SEED_RANDOM = 7, 11
HERE = os.path.dirname(os.path.abspath(__file__))
COMMAND = (".venv-golden/bin/python golden/make_golden.py   (from the repository root; setup: "
           "python3 -m venv .venv-golden && .venv-golden/bin/pip install -r golden/requirements.txt)")
HEADER = ["t1", "t2", "t3", "d1", "d2", "d3", "dd1", "dd2", "dd3", "tau3_rnea", "tau3_exact", "tau3_paper"]
PI = math.pi


def fail(message):
    sys.exit(f"make_golden.py: FAILED: {message}")


# ----------------------------------------------------------------------------------------------
# The three torques.

def build_arm(r):
    model = pin.Model()
    model.gravity.linear = np.array([r["g"], 0.0, 0.0])
    parent = 0
    for name, offset in (("j1", 0.0), ("j2", r["l1"]), ("j3", r["l2"])):
        placement = pin.SE3(np.eye(3), np.array([offset, 0.0, 0.0]))
        parent = model.addJoint(parent, pin.JointModelRZ(), placement, name)
    # Point mass: all of m3 at (l3, 0, 0) in the frame of joint 3, no rotational inertia about it.
    point_mass = pin.Inertia(r["m3"], np.array([r["l3"], 0.0, 0.0]), np.zeros((3, 3)))
    model.appendBodyToJoint(parent, point_mass, pin.SE3.Identity())
    if model.nq != 3 or model.nv != 3:
        fail(f"the Pinocchio arm has nq={model.nq}, nv={model.nv}")
    return model, model.createData()


def rnea_tau3(model, data, s):
    return float(pin.rnea(model, data, np.array(s[0:3]), np.array(s[3:6]), np.array(s[6:9]))[2])


def tau3_exact(r, s):
    t1, t2, t3, d1, d2, d3, dd1, dd2, dd3 = s
    m3, l1, l2, l3, g = r["m3"], r["l1"], r["l2"], r["l3"], r["g"]
    return (m3 * l1 * l3 * dd1 * math.cos(t2 + t3) + m3 * l2 * l3 * (dd1 + dd2) * math.cos(t3)
            + m3 * l1 * l3 * d1 ** 2 * math.sin(t2 + t3) + m3 * l2 * l3 * (d1 + d2) ** 2 * math.sin(t3)
            + m3 * l3 ** 2 * (dd1 + dd2 + dd3) + m3 * g * l3 * math.sin(t1 + t2 + t3))


def tau3_paper(r, s):
    """The paper's equation (6), exactly as written (docs/equations.md)."""
    t1, t2, t3, d1, d2, d3, dd1, dd2, dd3 = s
    m3, l1, l2, l3, g = r["m3"], r["l1"], r["l2"], r["l3"], r["g"]
    return (m3 * l1 * l3 * dd1 * math.cos(t2 + t3) + (m3 * l2 * l3 * dd1 + 2 * m3 * l2 * l3 * dd2) * math.cos(t3)
            + m3 * l1 * l3 * d1 ** 2 * math.sin(t2 + t3) + m3 * g * l3 * math.sin(t1 + t2 + t3)
            + m3 * l2 * l3 * (d1 + d2) ** 2 * math.sin(t3) + m3 * l3 ** 2 * (dd1 + dd2 + dd3))


# ----------------------------------------------------------------------------------------------
# Checks on the stimulus.

def check_derivatives(name, q, d, dd, dt):
    """Central differences of the sampled angles and velocities against the written derivatives."""
    q, d, dd = np.asarray(q), np.asarray(d), np.asarray(dd)
    d_err = np.max(np.abs((q[2:] - q[:-2]) / (2 * dt) - d[1:-1]))
    dd_err = np.max(np.abs((d[2:] - d[:-2]) / (2 * dt) - dd[1:-1]))
    # Truncation error of a central difference is dt^2/6 * (third derivative): tiny at these steps.
    if d_err > 1e-2 or dd_err > 5e-2:
        fail(f"{name}: velocities/accelerations are not the derivatives of the angles "
             f"(max |diff| {d_err:.2e} rad/s, {dd_err:.2e} rad/s^2)")


def check_full_circle(name, q):
    q = np.asarray(q)
    spans = np.max(q, axis=0) - np.min(q, axis=0)
    if np.any(spans < 2 * PI):
        fail(f"{name}: an angle does not cover the full circle (spans {spans})")


# ----------------------------------------------------------------------------------------------
# The traces.

def multiturn():
    """Constant speed plus two sinusoids per joint, 10 s at 5 ms: every angle turns more than once."""
    n, dt = 2000, 0.005
    # per joint: constant speed, (amplitude rad, frequency rad/s, phase) of two sinusoids
    joints = [
        (1.3, (0.40, 2.0, 0.0), (0.055, 12.0, 0.5)),
        (-1.6, (0.25, 3.0, 1.0), (0.045, 13.0, 2.0)),
        (2.0, (0.25, 2.0, 2.0), (0.035, 12.0, -1.0)),
    ]
    centre = (0.3, -0.5, 0.2)  # angle at t = 5 s, the middle of the trace (keeps |angle| <= 4 pi)
    for omega, (a1, w1, _), (a2, w2, _) in joints:  # analytic bounds, before sampling
        if abs(omega) + a1 * w1 + a2 * w2 > DMAX or a1 * w1 ** 2 + a2 * w2 ** 2 > DDMAX:
            fail("multiturn: sinusoid parameters exceed the declared ranges")
    q, d, dd = [], [], []
    for k in range(n):
        t = k * dt
        qk, dk, ddk = [], [], []
        for i, (omega, (a1, w1, p1), (a2, w2, p2)) in enumerate(joints):
            qk.append(centre[i] + omega * (t - 5.0) + a1 * math.sin(w1 * t + p1) + a2 * math.sin(w2 * t + p2))
            dk.append(omega + a1 * w1 * math.cos(w1 * t + p1) + a2 * w2 * math.cos(w2 * t + p2))
            ddk.append(-a1 * w1 ** 2 * math.sin(w1 * t + p1) - a2 * w2 ** 2 * math.sin(w2 * t + p2))
        q.append(qk), d.append(dk), dd.append(ddk)
    check_derivatives("multiturn", q, d, dd, dt)
    check_full_circle("multiturn", q)
    return [q[k] + d[k] + dd[k] for k in range(n)]


def rest_to_rest(rng):
    """Quintic (minimum-jerk) point-to-point moves between random poses, at rest at both ends of each."""
    rows, pose = [], rng.uniform(-PI, PI, 3)
    for move in range(5):
        target = rng.uniform(-PI, PI, 3)
        delta = target - pose
        span = max(np.max(np.abs(delta)), 1e-3)
        # quintic peaks: velocity 1.875 span/T, acceleration 5.7735 span/T^2; use 90 % of the ranges
        duration = max(1.875 * span / (0.9 * DMAX), math.sqrt(5.7735 * span / (0.9 * DDMAX)), 0.5)
        q, d, dd = [], [], []
        for k in range(200):
            tau = k / 199.0
            s = 10 * tau ** 3 - 15 * tau ** 4 + 6 * tau ** 5
            sd = (30 * tau ** 2 - 60 * tau ** 3 + 30 * tau ** 4) / duration
            sdd = (60 * tau - 180 * tau ** 2 + 120 * tau ** 3) / duration ** 2
            q.append(list(pose + s * delta)), d.append(list(sd * delta)), dd.append(list(sdd * delta))
        check_derivatives(f"rest_to_rest move {move}", q, d, dd, duration / 199.0)
        if any(v != 0.0 for v in d[0] + dd[0] + d[-1] + dd[-1]):
            fail(f"rest_to_rest move {move} does not start and end at rest")
        rows += [q[k] + d[k] + dd[k] for k in range(200)]
        pose = target
    return rows


def random_samples(rng):
    """Uniform over the declared ranges, angles in [-pi, pi)."""
    q = rng.uniform(-PI, PI, (2000, 3))
    d = rng.uniform(-DMAX, DMAX, (2000, 3))
    dd = rng.uniform(-DDMAX, DDMAX, (2000, 3))
    return [list(q[i]) + list(d[i]) + list(dd[i]) for i in range(2000)]


def worst_case_samples(r):
    """Samples at the largest |tau3| (exact and paper) the declared ranges allow, found by a grid search.

    tau3 is linear in dd, grows with d1^2 and (d1+d2)^2, and t1 only moves the gravity term: so the
    maximum has |dd_i| = DDMAX with the sign of its coefficient, d1 = d2 = DMAX, sin(t1+t2+t3) = 1, and
    only a = t2+t3 and b = t3 to search. The minimum is the mirror image (all signs and angles negated).
    """
    m3, l1, l2, l3, g = r["m3"], r["l1"], r["l2"], r["l3"], r["g"]
    rows = []
    for dd2_weight in (1.0, 2.0):  # exact, paper
        def coefficients(a, b):
            return (l1 * np.cos(a) + l2 * np.cos(b) + l3, dd2_weight * l2 * np.cos(b) + l3, l3 + 0 * a)

        def value(a, b):
            c1, c2, c3 = coefficients(a, b)
            return m3 * l3 * (DDMAX * (np.abs(c1) + np.abs(c2) + np.abs(c3)) + DMAX ** 2 * l1 * np.sin(a)
                              + (2 * DMAX) ** 2 * l2 * np.sin(b) + g)

        ca, cb, half = 0.0, 0.0, PI
        for _ in range(12):  # coarse grid over the full circle, then finer grids around the best point
            a = np.linspace(ca - half, ca + half, 801)[:, None]
            b = np.linspace(cb - half, cb + half, 801)[None, :]
            v = value(a, b)
            i, j = np.unravel_index(np.argmax(v), v.shape)
            ca, cb, half = float(a[i, 0]), float(b[0, j]), half / 50
        c1, c2, c3 = coefficients(ca, cb)
        t3, t2 = cb, ca - cb
        t1 = PI / 2 - ca
        dd = [math.copysign(DDMAX, float(c)) for c in (c1, c2, c3)]
        rows.append([t1, t2, t3, DMAX, DMAX, 0.0] + dd)
        rows.append([-t1, -t2, -t3, -DMAX, -DMAX, 0.0] + [-x for x in dd])
    return rows


def edge_cases(r):
    """Quadrant boundaries and just either side, angle sums on boundaries, extremes, rest, worst case.

    Angles meant to sit on or sum to a boundary are multiples of pi/16, so their sums land on the
    boundary in double arithmetic (up to an ulp) and exactly in binary angles (turns) as well.
    """
    rows = []
    extreme = [DMAX, -DMAX, DMAX, DDMAX, -DDMAX, DDMAX]
    extreme_pos = [DMAX] * 3 + [DDMAX] * 3
    extreme_neg = [-DMAX] * 3 + [-DDMAX] * 3
    rest = [0.0] * 6
    # 1. every joint on a boundary and +-1e-9, +-1e-6 beside it
    for k in range(5):  # 0, pi/2, pi, 3pi/2, 2pi
        for eps in (0.0, 1e-9, -1e-9, 1e-6, -1e-6):
            a = k * PI / 2 + eps
            rows.append([a, a, a] + rest)                # all three, and the sums 2a, 3a on boundaries too
            rows.append([0.0, 0.0, a] + extreme)         # t3 alone (t2+t3 and the total follow it)
            rows.append([a, 0.0, 0.0] + extreme_pos)     # t1 alone: only the gravity angle moves
            rows.append([0.0, a, 0.0] + extreme_neg)     # t2 alone: t2+t3 and the total move
    # 2. negative boundaries and the ends of the angle range
    for a0 in (-PI / 2, -PI, -3 * PI / 2, -2 * PI, 4 * PI, -4 * PI):
        for eps in (0.0, 1e-9, -1e-9):
            a = a0 + eps
            if abs(a) > ANGLE_LIMIT:
                continue
            rows.append([a, a / 2, a / 4] + extreme)
            rows.append([a / 4, a / 2, a] + extreme_pos)
    # 3. the angle sums on boundaries while the single angles are off them
    motions = [rest, extreme, extreme_pos, extreme_neg]
    for k in range(-2, 5):  # B = -pi .. 2pi
        for j, eps in enumerate((0.0, 1e-9, -1e-9)):
            m = motions[(k + j) % 4]
            big_b = k * PI / 2
            # t2+t3 on the boundary, the total (t1 = 5pi/16) off it
            rows.append([5 * PI / 16, big_b - 3 * PI / 8, 3 * PI / 8 + eps] + m)
            # t1+t2+t3 on the boundary, t2+t3 = 7pi/16 off it
            rows.append([big_b - 7 * PI / 16, 5 * PI / 16, PI / 8 + eps] + m)
            # both sums on boundaries (t2+t3 = B, total = B + pi/2), t2 and t3 off them
            rows.append([PI / 2, big_b - 5 * PI / 16, 5 * PI / 16 + eps] + m)
    # 4. every sign combination of the six extremes at one pose; at a second, the accelerations' signs
    for signs in range(64):
        sv = [1.0 if signs >> j & 1 else -1.0 for j in range(6)]
        rows.append([0.9, -2.1, 2.6] + [sv[0] * DMAX, sv[1] * DMAX, sv[2] * DMAX, sv[3] * DDMAX, sv[4] * DDMAX, sv[5] * DDMAX])
    for signs in range(16):
        sv = [1.0 if signs >> j & 1 else -1.0 for j in range(4)]
        rows.append([-2.5, 1.2, -0.7] + [sv[3] * DMAX] * 3 + [sv[0] * DDMAX, sv[1] * DDMAX, sv[2] * DDMAX])
    # 5. rest (gravity only), including the largest gravity load, and zero motion at zero angles
    rows.append([0.0] * 9)
    for pose in ([1.0, 2.0, 3.0], [PI / 2, 0.0, 0.0], [0.0, PI / 4, PI / 4], [PI, -PI / 4, -PI / 4]):
        rows.append(pose + rest)
    # 6. the largest |tau3| the declared ranges allow (exact and paper), both signs
    rows += worst_case_samples(r)
    return rows


# ----------------------------------------------------------------------------------------------

def write(name, description, seed, rows, model, data):
    worst, max_load, max_paper, max_paper_gap = 0.0, 0.0, 0.0, 0.0
    lines = []
    for i, s in enumerate(rows):
        s = [float(v) + 0.0 for v in s]  # plain floats, and -0.0 written as 0.0
        if any(not math.isfinite(v) for v in s):
            fail(f"{name} row {i}: not finite: {s}")
        if any(abs(v) > ANGLE_LIMIT for v in s[0:3]):
            fail(f"{name} row {i}: angle beyond +-4 pi: {s[0:3]}")
        if any(abs(v) > DMAX for v in s[3:6]) or any(abs(v) > DDMAX for v in s[6:9]):
            fail(f"{name} row {i}: beyond the declared ranges: {s[3:9]}")
        rnea, exact, paper = rnea_tau3(model, data, s), tau3_exact(ROBOT, s), tau3_paper(ROBOT, s)
        if not abs(rnea - exact) < TOLERANCE:
            fail(f"{name} row {i}: Pinocchio RNEA {rnea!r} and the closed form {exact!r} differ by "
                 f"{abs(rnea - exact):.3e} N*m (> {TOLERANCE:g}); sample {s}")
        worst = max(worst, abs(rnea - exact))
        max_load, max_paper = max(max_load, abs(exact)), max(max_paper, abs(paper))
        max_paper_gap = max(max_paper_gap, abs(paper - exact))
        lines.append(",".join(repr(v + 0.0) for v in s + [rnea, exact, paper]))
    robot = " ".join(f"{k}={v:g}" for k, v in ROBOT.items())
    header = [
        f"# {name}: {description}",
        f"# regenerate: {COMMAND}",
        f"# reference: Pinocchio {pin.__version__} RNEA (tau3_rnea); closed forms tau3_exact (docs/equations.md) and "
        f"tau3_paper (the paper's equation (6)); max |rnea - exact| = {worst:.1e} N*m",
        f"# seed: {seed}",
        f"# robot: {robot}",
        f"# ranges: dmax={DMAX:g} ddmax={DDMAX:g}",
        "# units: t1,t2,t3 rad; d1,d2,d3 rad/s; dd1,dd2,dd3 rad/s^2; tau3_rnea,tau3_exact,tau3_paper N*m",
    ]
    with open(os.path.join(HERE, name + ".csv"), "w") as f:
        f.write("\n".join(header + [",".join(HEADER)] + lines) + "\n")
    print(f"| {name}.csv | {len(rows)} | {worst:.1e} | {max_load:.3f} | {max_paper:.3f} | {max_paper_gap:.3f} |")


def main():
    model, data = build_arm(ROBOT)
    print(f"Pinocchio {pin.__version__}, numpy {np.__version__}; robot {ROBOT}; |d| <= {DMAX:g}, |dd| <= {DDMAX:g}")
    print("| file | rows | max abs(rnea - exact) N*m | max abs(tau3_exact) N*m | max abs(tau3_paper) N*m "
          "| max abs(paper - exact) N*m |")
    print("| --- | --- | --- | --- | --- | --- |")
    write("multiturn", "smooth multi-turn trajectory (10 s at 5 ms, constant speed plus two sinusoids per joint); "
          "every angle covers the full circle", "none (deterministic, no random numbers)", multiturn(), model, data)
    write("rest_to_rest", "five quintic point-to-point moves between random poses, each from rest to rest "
          "(200 samples per move)", f"{SEED_REST_TO_REST} (numpy.random.default_rng)",
          rest_to_rest(np.random.default_rng(SEED_REST_TO_REST)), model, data)
    write("random", "uniform random samples: angles in [-pi, pi), d in [-dmax, dmax], dd in [-ddmax, ddmax]",
          f"{SEED_RANDOM} (numpy.random.default_rng)", random_samples(np.random.default_rng(SEED_RANDOM)), model, data)
    write("edge_cases", "angles on quadrant boundaries and +-1e-9, +-1e-6 beside them, angle sums on boundaries, "
          "extremes of both signs, rest, the largest |tau3| the ranges allow", "none (deterministic, no random numbers)",
          edge_cases(ROBOT), model, data)


if __name__ == "__main__":
    main()
