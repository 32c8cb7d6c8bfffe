#!/usr/bin/env python3
"""Golden inverse-dynamics traces of the UR5 and the Panda carrying a payload, and of the UR5 mounted on the
ceiling and tilted, from an independent reference (Pinocchio's pin.rnea), beside make_golden_arms.py.

Robots, joints, declared velocity and acceleration ranges, the URDFs and the own Newton-Euler are exactly
those of make_golden_arms.py (imported from it); see its docstring.

Payload (golden/arms/payload/<robot>_<kind>.csv). A rigid body given as robot controllers state load data:
mass m (kg), centre of mass c (m, in the payload frame) and inertia tensor I about the centre of mass
(kg m^2, in the payload frame's axes). The payload frame is the chain's tip link of the existing traces:
tool0 for the UR5, panda_hand for the Panda; both are fixed to the last moving joint. In Pinocchio the
payload is added to the last joint's body at the payload frame's placement:
    model.inertias[last] = inertia_without_payload + frame.placement.act(pin.Inertia(m, c, I)).
Declared ranges (machine-readable line '# payload: frame=... max-mass=... com-radius=... max-inertia=...'):
  max-mass     UR5 5 kg, Panda 3 kg (the robots' rated payloads);
  com-radius   0.1 m: |c| <= 0.1 m (to rounding: 1e-12 m) from the payload frame's origin;
  max-inertia  max-mass x (0.1 m)^2 per element: |I_ij| <= 0.05 kg m^2 (UR5), 0.03 kg m^2 (Panda).
Every tensor is physical: I = tr(S) E - S for the second moments S = m R diag(s) R^T of the payload's mass
about its centre (R a random rotation, s_i in [1e-4, 4.9e-3] m^2), so symmetric, positive definite and
obeying the triangle inequalities (checked, as are all the ranges, on every row); zero when m = 0.
Kinds:
  random           1000 rows: q in [-pi, pi), qd, qdd uniform within the declared ranges (as the arms'
                   random kind) and a payload per row: rows 10k: no payload (all ten values 0); 10k+1: the
                   maximum mass; 10k+2: the centre of mass on the sphere's edge (|c| = 0.1 m); 10k+3: the
                   maximum mass, the centre of mass on the edge and I = max-inertia x identity (the largest
                   tensor the bound allows); otherwise mass uniform in [0, max-mass], c uniform in the ball.
  pick_and_place   600 rows: six quintic rest-to-rest moves of 100 samples (as the arms' rest_to_rest kind),
                   carrying nothing, part A, nothing, part B, nothing, part C: the payload changes five
                   times mid-stream, each time between two moves (the arm at rest, the gripper closing or
                   opening). Part A: the maximum mass with the centre of mass on the edge; B and C random.

Mounting (golden/arms/mounting/ur5_<mounting>_<kind>.csv). The robot base's orientation in the world is
the URDF roll-pitch-yaw R = Rz(yaw) Ry(pitch) Rx(roll) (base to world); the world's gravity is (0, 0, -9.81)
m/s^2, so in the base frame, where Pinocchio works, it is R^T (0, 0, -9.81): model.gravity is set to that,
with R from pin.rpy.rpyToMatrix (machine-readable line '# mounting: name=... base-rpy=roll,pitch,yaw').
  ceiling  base-rpy = (pi, 0, 0): upside down, gravity (0, -1.2e-15, +9.81) in the base frame;
  tilt30   base-rpy = (0, pi/6, 0): the base tilted 30 degrees about its y axis, gravity
           (4.905, 0, -8.496) in the base frame.
Kinds: random (1000 rows, seed 11) and rest_to_rest (600 rows, seed 7): the same samples as
golden/arms/ur5_random.csv and ur5_rest_to_rest.csv, only the gravity differs.

Seeds (numpy.random.default_rng, a new generator per robot and file): payload random 17, pick_and_place 19
(the moves first, then the parts from the same generator); mounting as make_golden_arms.py. Output is
bit-for-bit reproducible with the pinned versions (golden/requirements-arms.txt).

Independent checks (on every row; the script stops on any failure, tolerance 1e-9 N*m):
  1. the own Newton-Euler of make_golden_arms.py on the model its own URDF parser reads, with the payload
     merged into the last body by own code (the payload frame's pose from the URDF text: the fixed joints
     from the last moving joint's link to the frame) and the gravity rotated by the own rpy matrix;
  2. Pinocchio's M(q) qdd + nle(q, qd) (pin.crba + pin.nonLinearEffects) on the same model.
  Also: the payload frame's pose from the URDF text against Pinocchio's frame placement (1e-12), every
  sample and payload within the declared ranges, the required rows present (zero payload, maximum mass,
  centre of mass on the edge), the pick-and-place payload changing at least three times.

Format: as make_golden_arms.py, with the payload columns between qdd and tau:
q1..qn,qd1..qdn,qdd1..qddn[,payload_mass,payload_cx,payload_cy,payload_cz,payload_ixx,payload_ixy,payload_ixz,
payload_iyy,payload_iyz,payload_izz],tau1..taun. Every number is the Python repr of the double, never -0.0.

Regenerate (from the repository root; about ten seconds):
    python3 -m venv .venv-golden && .venv-golden/bin/pip install -r golden/requirements-arms.txt
    .venv-golden/bin/python golden/make_golden_payload.py
"""
import copy
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import make_golden_arms as arms  # noqa: E402  (robots, own Newton-Euler, trajectories, number format)

PAYLOAD_DIR = os.path.join(HERE, "arms", "payload")
MOUNTING_DIR = os.path.join(HERE, "arms", "mounting")
PI = math.pi
TOLERANCE = arms.TOLERANCE
SEED_PAYLOAD_RANDOM, SEED_PICK_AND_PLACE = 17, 19
COM_RADIUS = 0.1  # m
COM_SLACK = 1e-12  # m: a centre of mass scaled onto the sphere is 0.1 m to rounding
SPREAD = (1e-4, 4.9e-3)  # m^2, second moments of the payload's mass about its centre along its principal axes
COMMAND = (".venv-golden/bin/python golden/make_golden_payload.py   (from the repository root; setup: "
           "python3 -m venv .venv-golden && .venv-golden/bin/pip install -r golden/requirements-arms.txt)")
PAYLOAD_COLUMNS = ["payload_mass", "payload_cx", "payload_cy", "payload_cz", "payload_ixx", "payload_ixy",
                   "payload_ixz", "payload_iyy", "payload_iyz", "payload_izz"]

# frame: the chain's tip link of the existing traces; max_inertia = max_mass x (0.1 m)^2, written exactly.
PAYLOADS = {
    "ur5": dict(frame="tool0", max_mass=5.0, max_inertia=0.05, note="UR5 rated payload 5 kg"),
    "panda": dict(frame="panda_hand", max_mass=3.0, max_inertia=0.03, note="Panda rated payload 3 kg"),
}
MOUNTINGS = [
    dict(name="ceiling", rpy=(PI, 0.0, 0.0), what="ceiling-mounted (upside down)"),
    dict(name="tilt30", rpy=(0.0, PI / 6, 0.0), what="tilted 30 degrees about the base's y axis"),
]
WORLD_GRAVITY = np.array([0.0, 0.0, -9.81])


def fail(message):
    sys.exit(f"make_golden_payload.py: FAILED: {message}")


# ----------------------------------------------------------------------------------------------
# Payloads.

def random_rotation(rng):
    """A uniformly random rotation, from a normalised Gaussian quaternion."""
    w, x, y, z = (lambda v: v / np.linalg.norm(v))(rng.normal(size=4))
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def random_inertia(rng, mass):
    """A physical inertia about the centre of mass: I = tr(S) E - S, S = m R diag(s) R^T; exactly symmetric."""
    r = random_rotation(rng)
    s = mass * (r @ np.diag(rng.uniform(SPREAD[0], SPREAD[1], 3)) @ r.T)
    i = np.trace(s) * np.eye(3) - s
    return (i + i.T) / 2


def random_com(rng, on_edge):
    u = rng.normal(size=3)
    u = u / np.linalg.norm(u)
    return COM_RADIUS * u if on_edge else COM_RADIUS * rng.uniform() ** (1 / 3) * u


def payload_values(mass, com, inertia):
    """The ten payload columns."""
    i = inertia
    return [mass, com[0], com[1], com[2], i[0, 0], i[0, 1], i[0, 2], i[1, 1], i[1, 2], i[2, 2]]


NO_PAYLOAD = [0.0] * 10


def random_payloads(rng, spec, rows):
    out = []
    m_max, i_max = spec["max_mass"], spec["max_inertia"]
    for k in range(rows):
        kind = k % 10
        if kind == 0:
            out.append(list(NO_PAYLOAD))
            continue
        mass = m_max if kind in (1, 3) else rng.uniform(0.0, m_max)
        com = random_com(rng, on_edge=kind in (2, 3))
        inertia = i_max * np.eye(3) if kind == 3 else random_inertia(rng, mass)
        out.append(payload_values(mass, com, inertia))
    return out


def pick_and_place_parts(rng, spec):
    """Part A: the maximum mass, centre of mass on the edge; parts B and C random within the ranges."""
    m_max = spec["max_mass"]
    a = payload_values(m_max, random_com(rng, True), random_inertia(rng, m_max))
    parts = [a]
    for _ in range(2):
        mass = rng.uniform(0.2 * m_max, m_max)
        parts.append(payload_values(mass, random_com(rng, False), random_inertia(rng, mass)))
    return parts


def tensor(p):
    """The symmetric inertia tensor of a payload row."""
    return np.array([[p[4], p[5], p[6]], [p[5], p[7], p[8]], [p[6], p[8], p[9]]])


def check_payload(where, p, spec):
    m, c, i = p[0], np.array(p[1:4]), tensor(p)
    if not all(math.isfinite(v) for v in p):
        fail(f"{where}: payload not finite: {p}")
    if not 0.0 <= m <= spec["max_mass"]:
        fail(f"{where}: payload mass {m} beyond [0, {spec['max_mass']}] kg")
    if np.linalg.norm(c) > COM_RADIUS + COM_SLACK:
        fail(f"{where}: centre of mass {c} beyond {COM_RADIUS} m")
    if np.max(np.abs(i)) > spec["max_inertia"]:
        fail(f"{where}: inertia {i} beyond {spec['max_inertia']} kg m^2 per element")
    if m == 0.0:
        if any(v != 0.0 for v in p):
            fail(f"{where}: a massless payload with a centre of mass or inertia: {p}")
        return
    eig = np.sort(np.linalg.eigvalsh(i))
    if eig[0] <= 0.0 or eig[0] + eig[1] < eig[2] * (1 - 1e-12):
        fail(f"{where}: inertia {i} not positive definite or beyond the triangle inequality (eigenvalues {eig})")


# ----------------------------------------------------------------------------------------------
# The payload frame's pose in the last moving joint's frame, from the URDF text (own, not Pinocchio's).

def frame_pose(path, link):
    """Compose the fixed joints from `link` up to the child link of the nearest moving joint."""
    joints = {}
    for joint in ET.parse(path).getroot().findall("joint"):
        origin = joint.find("origin")
        joints[joint.find("child").get("link")] = dict(
            type=joint.get("type"), parent=joint.find("parent").get("link"),
            xyz=np.array(arms.floats(origin.get("xyz") if origin is not None else None, [0, 0, 0])),
            rpy=arms.floats(origin.get("rpy") if origin is not None else None, [0, 0, 0]))
    rot, pos = np.eye(3), np.zeros(3)
    while joints[link]["type"] == "fixed":
        j = joints[link]
        r0 = arms.rpy_matrix(*j["rpy"])
        rot, pos = r0 @ rot, r0 @ pos + j["xyz"]
        link = j["parent"]
    return rot, pos


def own_with_payload(chain, pose, p):
    """The own chain with the payload merged into the last body (mass, first moment, inertia about the
    joint frame's origin)."""
    rot, pos = pose
    out = copy.deepcopy(chain)
    m = p[0]
    if m == 0.0:
        return out
    c = rot @ np.array(p[1:4]) + pos
    last = out[-1]
    last["mass"] = last["mass"] + m
    last["h"] = last["h"] + m * c
    last["inertia"] = last["inertia"] + rot @ tensor(p) @ rot.T + m * (np.dot(c, c) * np.eye(3) - np.outer(c, c))
    return out


# ----------------------------------------------------------------------------------------------

def evaluate(name, model, chain, gravity, n, samples, payloads=None, pose=None, frame_id=None):
    """pin.rnea on every row, checked against the own Newton-Euler and crba + nle; rows and statistics."""
    data = model.createData()
    last = model.njoints - 1
    bare = model.inertias[last].copy()
    worst_own, worst_crba, max_tau, lines = 0.0, 0.0, [0.0] * n, []
    for r, s in enumerate(samples):
        s = [float(v) + 0.0 for v in s]
        q, qd, qdd = s[0:n], s[n:2 * n], s[2 * n:3 * n]
        own_chain = chain
        extra = []
        if payloads is not None:
            p = [float(v) + 0.0 for v in payloads[r]]
            model.inertias[last] = bare + model.frames[frame_id].placement.act(
                pin.Inertia(p[0], np.array(p[1:4]), tensor(p)))
            own_chain = own_with_payload(chain, pose, p)
            extra = p
        qp, v, a = arms.to_pinocchio_q(model, q), np.array(qd), np.array(qdd)
        tau = [float(x) for x in pin.rnea(model, data, qp, v, a)]
        own = arms.own_rnea(own_chain, gravity, q, qd, qdd)
        mm = pin.crba(model, data, qp)
        mm = np.triu(mm) + np.triu(mm, 1).T
        second = mm @ a + pin.nonLinearEffects(model, data, qp, v)
        d_own = max(abs(tau[i] - own[i]) for i in range(n))
        d_crba = max(abs(tau[i] - float(second[i])) for i in range(n))
        if not (d_own < TOLERANCE and d_crba < TOLERANCE):
            fail(f"{name} row {r}: pin.rnea {tau} vs own Newton-Euler {own} (max diff {d_own:.3e}) "
                 f"vs crba+nle {list(second)} (max diff {d_crba:.3e}); sample {s} payload {extra}")
        worst_own, worst_crba = max(worst_own, d_own), max(worst_crba, d_crba)
        max_tau = [max(max_tau[i], abs(tau[i])) for i in range(n)]
        lines.append(",".join(arms.num(x) for x in s + extra + tau))
    model.inertias[last] = bare
    return lines, worst_own, worst_crba, max_tau


def check_samples(name, robot, n, samples):
    for r, s in enumerate(samples):
        q, qd, qdd = s[0:n], s[n:2 * n], s[2 * n:3 * n]
        if len(s) != 3 * n or any(not math.isfinite(v) for v in s) or any(abs(v) > arms.ANGLE_LIMIT for v in q):
            fail(f"{name} row {r}: bad sample {s}")
        if any(abs(qd[i]) > robot["vmax"][i] or abs(qdd[i]) > robot["amax"][i] for i in range(n)):
            fail(f"{name} row {r}: beyond the declared ranges: {qd} {qdd}")


def write(out_dir, name, header, n, payload, lines, worst_own, worst_crba, max_tau, rows):
    cols = ([f"q{i}" for i in range(1, n + 1)] + [f"qd{i}" for i in range(1, n + 1)]
            + [f"qdd{i}" for i in range(1, n + 1)] + (PAYLOAD_COLUMNS if payload else [])
            + [f"tau{i}" for i in range(1, n + 1)])
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, f"{name}.csv"), "w") as f:
        f.write("\n".join(header + [",".join(cols)] + lines) + "\n")
    print(f"| {os.path.relpath(os.path.join(out_dir, name), os.path.join(HERE, 'arms'))}.csv | {rows} "
          f"| {' / '.join(f'{x:.2f}' for x in max_tau)} | {worst_own:.1e} | {worst_crba:.1e} |")


def common_header(name, description, robot, model, n, seed, checks, reference_extra):
    names = [model.names[i] for i in range(1, model.njoints)]
    gravity_text = ",".join(arms.short(g) for g in model.gravity.linear)
    return [
        f"# {name}: {description}",
        f"# regenerate: {COMMAND}",
        f"# reference: Pinocchio {pin.__version__} pin.rnea on {robot['source']} ({arms.EXAMPLE_ROBOT_DATA}, "
        f"sha256 {robot['sha256']}){reference_extra}; checked on every row: {checks}",
        f"# seed: {seed}",
        f"# robot: name={robot['name']} source={robot['source']} tip={robot['tip']}",
        f"# joints: {','.join(names)} (numbered 1..{n} from the root; gravity {gravity_text} m/s^2 in the base frame)",
        f"# ranges: vmax={','.join(arms.short(x) for x in robot['vmax'])} "
        f"amax={','.join(arms.short(x) for x in robot['amax'])}",
    ]


def checks_text(worst_own, worst_crba):
    return (f"max |rnea - own Newton-Euler| = {worst_own:.1e} N*m, "
            f"max |rnea - (crba qdd + nle)| = {worst_crba:.1e} N*m")


def payload_files(robot, model, chain):
    n, spec = model.nv, PAYLOADS[robot["name"]]
    frame_id = model.getFrameId(spec["frame"])
    if frame_id >= len(model.frames) or model.frames[frame_id].parentJoint != model.njoints - 1:
        fail(f"{robot['name']}: payload frame {spec['frame']} is not fixed to the last moving joint")
    pose = frame_pose(os.path.join(ROOT, robot["source"]), spec["frame"])
    placement = model.frames[frame_id].placement
    if np.max(np.abs(placement.rotation - pose[0])) > 1e-12 or np.max(np.abs(placement.translation - pose[1])) > 1e-12:
        fail(f"{robot['name']}: payload frame pose {pose} (URDF text) vs Pinocchio {placement}")
    kinds = [
        ("random", "uniform random samples (q in [-pi, pi), qd, qdd within the declared ranges) with a random "
                   "payload per row: every 10th row none, the maximum mass, the centre of mass on the sphere's "
                   "edge, both with the largest inertia; otherwise uniform within the declared ranges",
         f"{SEED_PAYLOAD_RANDOM} (numpy.random.default_rng)"),
        ("pick_and_place", "six quintic rest-to-rest moves of 100 samples carrying none, part A, none, part B, "
                           "none, part C: the payload changes at rows 100, 200, 300, 400, 500 (at rest)",
         f"{SEED_PICK_AND_PLACE} (numpy.random.default_rng)"),
    ]
    for kind, description, seed in kinds:
        if kind == "random":
            rng = np.random.default_rng(SEED_PAYLOAD_RANDOM)
            samples = arms.random_samples(rng, robot["vmax"], robot["amax"])
            payloads = random_payloads(rng, spec, len(samples))
        else:
            rng = np.random.default_rng(SEED_PICK_AND_PLACE)
            samples = arms.rest_to_rest(rng, robot["vmax"], robot["amax"])
            a, b, c = pick_and_place_parts(rng, spec)
            carried = [NO_PAYLOAD, a, NO_PAYLOAD, b, NO_PAYLOAD, c]
            payloads = [list(carried[k // 100]) for k in range(len(samples))]
            changes = sum(1 for k in range(1, len(payloads)) if payloads[k] != payloads[k - 1])
            if changes < 3:
                fail(f"{robot['name']}_{kind}: the payload changes {changes} times")
        name = f"{robot['name']}_{kind}"
        check_samples(name, robot, n, samples)
        for r, p in enumerate(payloads):
            check_payload(f"{name} row {r}", p, spec)
        masses = [p[0] for p in payloads]
        if 0.0 not in masses or spec["max_mass"] not in masses:
            fail(f"{name}: rows at zero payload and at the maximum mass are required")
        if not any(abs(np.linalg.norm(p[1:4]) - COM_RADIUS) < COM_SLACK for p in payloads):
            fail(f"{name}: a row with the centre of mass on the sphere's edge is required")
        lines, worst_own, worst_crba, max_tau = evaluate(name, model, chain, [0.0, 0.0, -9.81], n, samples,
                                                         payloads, pose, frame_id)
        header = common_header(
            name, description, robot, model, n, seed, checks_text(worst_own, worst_crba),
            f" with the payload added to the last joint's body at the payload frame's placement "
            f"(model.inertias[last] += placement * pin.Inertia(m, c, I))") + [
            f"# payload: frame={spec['frame']} max-mass={arms.short(spec['max_mass'])} "
            f"com-radius={arms.short(COM_RADIUS)} max-inertia={arms.short(spec['max_inertia'])}",
            f"# declared: {robot['note']}; payload: {spec['note']}, centre of mass within com-radius of the "
            f"frame's origin, inertia about the centre of mass at most max-mass x (0.1 m)^2 per element",
            "# units: q rad (any real value); qd rad/s; qdd rad/s^2; payload_mass kg; payload_cx,cy,cz m (centre of "
            "mass in the payload frame); payload_ixx..izz kg m^2 (about the centre of mass, payload frame's axes); "
            "tau N*m (joint torque = reducer load)",
        ]
        write(PAYLOAD_DIR, name, header, n, True, lines, worst_own, worst_crba, max_tau, len(samples))


def mounting_files(robot, model, chain):
    n = model.nv
    for mounting in MOUNTINGS:
        rpy = mounting["rpy"]
        gravity = pin.rpy.rpyToMatrix(*rpy).T @ WORLD_GRAVITY
        own_gravity = arms.rpy_matrix(*rpy).T @ WORLD_GRAVITY
        if np.max(np.abs(gravity - own_gravity)) > 1e-14:
            fail(f"{mounting['name']}: Pinocchio's rpy gravity {gravity} vs own {own_gravity}")
        mounted = pin.Model(model)
        mounted.gravity = pin.Motion(gravity, np.zeros(3))
        if list(mounted.gravity.linear) != list(gravity):
            fail(f"{mounting['name']}: model.gravity {mounted.gravity.linear}, set {gravity}")
        for kind, description, seed in arms.KINDS:
            if kind not in ("random", "rest_to_rest"):
                continue
            samples = arms.make_rows(kind, robot["vmax"], robot["amax"])
            name = f"{robot['name']}_{mounting['name']}_{kind}"
            check_samples(name, robot, n, samples)
            lines, worst_own, worst_crba, max_tau = evaluate(name, mounted, chain, own_gravity, n, samples)
            rpy_text = ",".join(arms.short(x) for x in rpy)
            header = common_header(
                name, f"{mounting['what']}; {description}", robot, mounted, n, seed,
                checks_text(worst_own, worst_crba),
                f" with model.gravity = R(base-rpy)^T (0, 0, -9.81) (R from pin.rpy.rpyToMatrix)") + [
                f"# mounting: name={mounting['name']} base-rpy={rpy_text}",
                f"# declared: {robot['note']}; base-rpy: the base's orientation in the world (URDF roll, pitch, "
                f"yaw in rad), world gravity (0, 0, -9.81) m/s^2",
                "# units: q rad (any real value); qd rad/s; qdd rad/s^2; tau N*m (joint torque = reducer load)",
            ]
            write(MOUNTING_DIR, name, header, n, False, lines, worst_own, worst_crba, max_tau, len(samples))


def main():
    print(f"Pinocchio {pin.__version__}, numpy {np.__version__}, {arms.EXAMPLE_ROBOT_DATA} (URDFs in golden/robots/)")
    print()
    print("| file | rows | max abs(tau_i) N*m, joints 1..n | max abs(rnea - own Newton-Euler) N*m "
          "| max abs(rnea - (crba qdd + nle)) N*m |")
    print("| --- | --- | --- | --- | --- |")
    robots = {}
    for robot in arms.ROBOTS:
        if robot["name"] not in PAYLOADS:
            continue
        robot = dict(robot)
        model, chain, _ = arms.build_pinocchio(robot)
        robot["vmax"] = [j["velocity"] for j in chain]
        if list(model.velocityLimit) != robot["vmax"]:
            fail(f"{robot['name']}: Pinocchio velocity limits {list(model.velocityLimit)} vs URDF {robot['vmax']}")
        robots[robot["name"]] = (robot, model, chain)
    for name in ("ur5", "panda"):
        payload_files(*robots[name])
    mounting_files(*robots["ur5"])


if __name__ == "__main__":
    main()
