#!/usr/bin/env python3
"""Golden inverse-dynamics traces for every joint of three arms, from an independent reference.

For each robot and each trace kind this writes golden/arms/<robot>_<kind>.csv: joint angles q,
velocities qd, accelerations qdd and the torque tau of EVERY joint, tau = M(q) qdd + C(q, qd) qd + G(q),
computed by Pinocchio's recursive Newton-Euler algorithm (pin.rnea).

Robots (joints numbered from the root, moving joints only; q = 0 is the URDF's zero configuration):
  planar3  built in, exactly make_golden.build_arm (imported from make_golden.py): three revolute z
           joints, links along x of 0.4 / 0.35 / 0.3 m, a point mass m3 = 10 kg at the end of link 3,
           links 1 and 2 massless, gravity (+9.81, 0, 0) m/s^2 (t1 = 0 points link 1 down).
  ur5      golden/robots/ur5_robot.urdf (example-robot-data 6.0.0), chain from the root to tool0,
           gravity (0, 0, -9.81). Every moving joint is on that chain, so nothing is locked.
  panda    golden/robots/panda.urdf (example-robot-data 6.0.0), arm joints 1-7 up to panda_hand; the
           two finger joints (prismatic, not on the chain) are locked at 0 with pin.buildReducedModel,
           so the fingers' masses ride rigidly on the hand (as on the real robot with the gripper
           closed). Gravity (0, 0, -9.81).

Declared ranges (every sample stays within them; the hardware's fixed-point formats are sized from them):
  planar3  vmax 3, 3, 3 rad/s (the paper's arm, as make_golden.py); amax 10, 10, 10 rad/s^2.
  ur5      vmax = the URDF <limit velocity>: 3.15, 3.15, 3.15, 3.2, 3.2, 3.2 rad/s.
           amax 15 rad/s^2 for every joint: a declared value of ours (Universal Robots publishes no
           per-joint acceleration limit for the UR5 CB-series arm in this description).
  panda    vmax = the URDF <limit velocity>: 2.175 (joints 1-4), 2.61 (joints 5-7) rad/s.
           amax 15, 7.5, 10, 12.5, 15, 20, 20 rad/s^2: Franka Emika's datasheet joint acceleration
           limits for the Panda.
  Angles are any real number (the hardware wraps them modulo 2 pi); every trace keeps |q| <= 4 pi.
  The Panda's joints have position limits (URDF lower/upper), but the dynamics do not care: the
  traces deliberately go beyond them (full turns, random angles in [-pi, pi)).

Trace kinds (velocities and accelerations of the trajectories are the analytic derivatives of the
angles, checked by central differences against a rigorous truncation bound):
  multiturn     1000 rows, 10 s at 10 ms: per joint a constant speed (40 % of vmax, alternating sign)
                plus two sinusoids (peak speeds 30 % and 20 % of vmax, each peak acceleration at most
                45 % of amax): every angle covers the full circle; peaks at most 90 % of the ranges.
  rest_to_rest  600 rows: six quintic (minimum-jerk) moves between random poses in [-pi, pi)^n,
                100 samples per move, each move from rest to rest, timed so the fastest joint uses
                90 % of its speed or acceleration range (and at least 0.5 s).
  random        1000 rows: uniform samples, q in [-pi, pi), qd in [-vmax, vmax], qdd in [-amax, amax].
  edge_cases    every joint alone and all joints together at 0, +-pi/2, +-pi, 3pi/2, 2pi and +-1e-9
                beside each; extreme velocities and accelerations of both signs at two fixed poses
                (all 2^(2n) sign combinations when 2n <= 6, otherwise 8 fixed patterns - all the same
                sign, qd and qdd of opposite signs, alternating signs along the chain - plus 64 seeded
                random combinations per pose); each joint alone at +-vmax or +-amax with the others at
                rest, at two poses; rest (gravity only) at 0, at the two poses and at 8 seeded poses.

Seeds (numpy.random.default_rng, a new generator per robot and file): rest_to_rest 7, random 11,
edge_cases 13; multiturn uses no random numbers. Output is bit-for-bit reproducible with the pinned
versions (golden/requirements-arms.txt).

Independent checks (on every row; the script stops on any failure):
  1. an own Newton-Euler (numpy, moments about each body frame's origin, classical accelerations) on a
     model read from the URDF text with xml.etree (own parser: rpy, axes, inertial origins, fixed
     and locked joints merged into the moving body they ride on) - independent of Pinocchio's
     parser and algorithms; for planar3 built from the arm's parameters;
  2. Pinocchio's second formulation M(q) qdd + nle(q, qd) (pin.crba + pin.nonLinearEffects);
  3. planar3: the closed form tau3 of docs/equations.md (make_golden.tau3_exact).
  Tolerance 1e-9 N*m (absolute) for each; the torques are at most a few hundred N*m, so doubles
  agree to about 1e-13 N*m and 1e-9 leaves room only for rounding, not for a modelling difference.
  Also checked: every sample within the declared ranges, |q| <= 4 pi, the URDF files' SHA-256, the
  Pinocchio chain's joint names and velocity limits against the own URDF parser.

Format: '#' comment lines (what, regeneration command, reference and versions, seed, and the
machine-readable lines '# robot: name=... source=... tip=...' and '# ranges: vmax=... amax=...'),
one header row q1..qn,qd1..qdn,qdd1..qddn,tau1..taun, then one row per sample; every number is the
Python repr of the double (round-trips exactly), never -0.0.

Regenerate (from the repository root):
    python3 -m venv .venv-golden && .venv-golden/bin/pip install -r golden/requirements-arms.txt
    .venv-golden/bin/python golden/make_golden_arms.py
"""
import hashlib
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import make_golden  # noqa: E402  (planar3: build_arm, ROBOT and the closed form tau3_exact)

OUT_DIR = os.path.join(HERE, "arms")
PI = math.pi
ANGLE_LIMIT = 4 * PI
TOLERANCE = 1e-9  # N*m, every independent check
SEED_REST_TO_REST, SEED_RANDOM, SEED_EDGE = 7, 11, 13
EXAMPLE_ROBOT_DATA = "example-robot-data 6.0.0"
COMMAND = (".venv-golden/bin/python golden/make_golden_arms.py   (from the repository root; setup: "
           "python3 -m venv .venv-golden && .venv-golden/bin/pip install -r golden/requirements-arms.txt)")

# name, source (relative to the repository root, or builtin), tip link, SHA-256 of the URDF,
# declared acceleration ranges (rad/s^2) and why.
ROBOTS = [
    dict(name="planar3", source="builtin", tip="-", sha256=None, vmax=[3.0, 3.0, 3.0], amax=[10.0, 10.0, 10.0],
         note="the paper's planar arm (make_golden.build_arm); vmax 3 rad/s and amax 10 rad/s^2 as make_golden.py"),
    dict(name="ur5", source="golden/robots/ur5_robot.urdf", tip="tool0",
         sha256="cede880fc2a987ef9dd23bbcda3e0ad1e7b1df8b58d638d100cfbff8ebc806cb", vmax=None, amax=[15.0] * 6,
         note="vmax = URDF <limit velocity>; amax 15 rad/s^2 for every joint is a declared value of ours "
              "(no per-joint acceleration limit in the description)"),
    dict(name="panda", source="golden/robots/panda.urdf", tip="panda_hand",
         sha256="63792d2679f22c4e41cda2c4d9d903644e628970ad0656b9eec8485113941555",
         vmax=None, amax=[15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0],
         note="vmax = URDF <limit velocity>; amax = Franka Emika's datasheet joint acceleration limits; finger "
              "joints locked at 0 (their masses ride on the hand); angles go beyond the joints' position limits "
              "on purpose (the dynamics do not care)"),
]


def fail(message):
    sys.exit(f"make_golden_arms.py: FAILED: {message}")


def num(v):
    """A double as written in the files: Python repr, no -0.0."""
    return repr(float(v) + 0.0)


def short(v):
    """A declared range value: repr without a trailing '.0' (3.15, 10, 2.175)."""
    s = num(v)
    return s[:-2] if s.endswith(".0") else s


# ----------------------------------------------------------------------------------------------
# Own model: a serial chain of moving joints, each carrying one rigid body (the merged links).

def rpy_matrix(r, p, y):
    """URDF fixed-axis roll-pitch-yaw: R = Rz(y) Ry(p) Rx(r)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def axis_rotation(a, q):
    """Rodrigues: rotation by q about the unit axis a."""
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(q) * k + (1 - math.cos(q)) * (k @ k)


def floats(text, default):
    return [float(x) for x in text.split()] if text is not None else list(default)


def parse_urdf(path, tip):
    """The chain root -> tip from the URDF text: moving joints in order, each with the merged body it moves.

    Links on no chain joint's subtree but the root's ride on the base and are dropped; fixed joints and
    moving joints off the chain (locked at 0, where their motion is the identity) merge their child into
    the body of the nearest chain joint above them.
    """
    root_el = ET.parse(path).getroot()
    links = {}
    for link in root_el.findall("link"):
        inertial = link.find("inertial")
        if inertial is None:
            links[link.get("name")] = None
            continue
        origin = inertial.find("origin")
        xyz = floats(origin.get("xyz") if origin is not None else None, [0, 0, 0])
        rpy = floats(origin.get("rpy") if origin is not None else None, [0, 0, 0])
        i = inertial.find("inertia").attrib
        tensor = np.array([[float(i["ixx"]), float(i["ixy"]), float(i["ixz"])],
                           [float(i["ixy"]), float(i["iyy"]), float(i["iyz"])],
                           [float(i["ixz"]), float(i["iyz"]), float(i["izz"])]])
        rot = rpy_matrix(*rpy)
        links[link.get("name")] = (float(inertial.find("mass").get("value")), np.array(xyz), rot @ tensor @ rot.T)
    joints = {}
    for joint in root_el.findall("joint"):
        origin = joint.find("origin")
        limit = joint.find("limit")
        axis = joint.find("axis")
        a = np.array(floats(axis.get("xyz") if axis is not None else None, [1, 0, 0]))
        joints[joint.find("child").get("link")] = dict(
            name=joint.get("name"), type=joint.get("type"), parent=joint.find("parent").get("link"),
            xyz=np.array(floats(origin.get("xyz") if origin is not None else None, [0, 0, 0])),
            rpy=floats(origin.get("rpy") if origin is not None else None, [0, 0, 0]),
            axis=a / np.linalg.norm(a), velocity=float(limit.get("velocity")) if limit is not None else None)
    for j in joints.values():
        if j["type"] not in ("revolute", "continuous", "prismatic", "fixed"):
            fail(f"{path}: joint {j['name']} of type {j['type']} is not supported")
    # the chain: from the tip up to the root
    chain, link = [], tip
    while link in joints:
        if joints[link]["type"] != "fixed":
            chain.append(link)
        link = joints[link]["parent"]
    chain.reverse()  # child links of the moving chain joints, from the root
    index = {child: k for k, child in enumerate(chain)}
    bodies = [[0.0, np.zeros(3), np.zeros((3, 3))] for _ in chain]  # mass, first moment, inertia about origin
    for name, inertia in links.items():
        if inertia is None or inertia[0] == 0.0:
            continue
        mass, com, i_com = inertia
        rot, pos, link = np.eye(3), np.zeros(3), name  # pose of this link in the frame of `link`
        while link not in index and link in joints:
            j = joints[link]
            r0 = rpy_matrix(*j["rpy"])
            rot, pos = r0 @ rot, r0 @ pos + j["xyz"]
            link = j["parent"]
        if link not in index:
            continue  # rides on the base
        c = rot @ com + pos
        body = bodies[index[link]]
        body[0] += mass
        body[1] = body[1] + mass * c
        body[2] = body[2] + rot @ i_com @ rot.T + mass * (np.dot(c, c) * np.eye(3) - np.outer(c, c))
    chain_joints = []
    for k, child in enumerate(chain):
        j = joints[child]
        chain_joints.append(dict(name=j["name"], prismatic=j["type"] == "prismatic", r0=rpy_matrix(*j["rpy"]),
                                 p0=j["xyz"], axis=j["axis"], mass=bodies[k][0], h=bodies[k][1],
                                 inertia=bodies[k][2], velocity=j["velocity"], continuous=j["type"] == "continuous"))
    return chain_joints


def planar3_chain(r):
    """The planar arm in the own model's terms, from its parameters (not from Pinocchio)."""
    chain = []
    for k, offset in enumerate((0.0, r["l1"], r["l2"])):
        last = k == 2
        chain.append(dict(name=f"j{k + 1}", prismatic=False, r0=np.eye(3), p0=np.array([offset, 0.0, 0.0]),
                          axis=np.array([0.0, 0.0, 1.0]), mass=r["m3"] if last else 0.0,
                          h=np.array([r["m3"] * r["l3"] if last else 0.0, 0.0, 0.0]), inertia=np.diag(
                              [0.0, r["m3"] * r["l3"] ** 2, r["m3"] * r["l3"] ** 2]) if last else np.zeros((3, 3)),
                          velocity=None, continuous=False))
    return chain


def own_rnea(chain, gravity, q, qd, qdd):
    """Newton-Euler in body frames: forward pass (velocities, classical accelerations of each frame's
    origin; gravity as a base acceleration -g), backward pass (forces and moments about each origin)."""
    n = len(chain)
    w, wd, vd = np.zeros(3), np.zeros(3), -np.asarray(gravity, dtype=float)
    rots, forces, moments = [], [], []
    for k, j in enumerate(chain):
        a = j["axis"]
        if j["prismatic"]:
            rot, p = j["r0"], j["p0"] + j["r0"] @ a * q[k]
        else:
            rot, p = j["r0"] @ axis_rotation(a, q[k]), j["p0"]
        vd_origin = rot.T @ (vd + np.cross(wd, p) + np.cross(w, np.cross(w, p)))
        w_in = rot.T @ w
        wd_in = rot.T @ wd
        if j["prismatic"]:
            w, wd = w_in, wd_in
            vd = vd_origin + 2 * np.cross(w, a * qd[k]) + a * qdd[k]
        else:
            w = w_in + a * qd[k]
            wd = wd_in + np.cross(w_in, a * qd[k]) + a * qdd[k]
            vd = vd_origin
        m, h, i_o = j["mass"], j["h"], j["inertia"]
        forces.append(m * vd + np.cross(wd, h) + np.cross(w, np.cross(w, h)))
        moments.append(i_o @ wd + np.cross(w, i_o @ w) + np.cross(h, vd))
        rots.append((rot, p))
    tau = [0.0] * n
    f_next, n_next = np.zeros(3), np.zeros(3)
    for k in range(n - 1, -1, -1):
        if k + 1 < n:
            rot, p = rots[k + 1]
            f_child = rot @ f_next
            f_k = forces[k] + f_child
            n_k = moments[k] + rot @ n_next + np.cross(p, f_child)
        else:
            f_k, n_k = forces[k], moments[k]
        a = chain[k]["axis"]
        tau[k] = float(a @ (f_k if chain[k]["prismatic"] else n_k))
        f_next, n_next = f_k, n_k
    return tau


# ----------------------------------------------------------------------------------------------
# Pinocchio models.

def build_pinocchio(robot):
    """The Pinocchio model of a robot (reduced to its chain) and, for URDF robots, the own chain."""
    if robot["source"] == "builtin":
        model, _ = make_golden.build_arm(make_golden.ROBOT)
        return model, planar3_chain(make_golden.ROBOT), [make_golden.ROBOT["g"], 0.0, 0.0]
    path = os.path.join(ROOT, robot["source"])
    with open(path, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    if digest != robot["sha256"]:
        fail(f"{robot['source']}: SHA-256 {digest}, expected {robot['sha256']} (the file must stay as the package ships it)")
    full = pin.buildModelFromUrdf(path)
    tip = full.getFrameId(robot["tip"])
    if tip >= len(full.frames):
        fail(f"{robot['source']}: no frame {robot['tip']}")
    on_chain = set(full.supports[full.frames[tip].parentJoint])
    locked = [i for i in range(1, full.njoints) if i not in on_chain]
    q_locked = to_pinocchio_q(full, np.zeros(full.nv))
    model = pin.buildReducedModel(full, locked, q_locked) if locked else full
    chain = parse_urdf(path, robot["tip"])
    names = [model.names[i] for i in range(1, model.njoints)]
    if names != [j["name"] for j in chain]:
        fail(f"{robot['name']}: Pinocchio chain {names} and the own parser's {[j['name'] for j in chain]} differ")
    return model, chain, [0.0, 0.0, -9.81]


def to_pinocchio_q(model, q):
    """Joint angles (one per degree of freedom) to Pinocchio's configuration vector: a continuous
    (unbounded) revolute joint takes (cos q, sin q)."""
    config = np.zeros(model.nq)
    for i in range(1, model.njoints):
        jm = model.joints[i]
        if jm.nq == 2 and jm.nv == 1:
            config[jm.idx_q], config[jm.idx_q + 1] = math.cos(q[jm.idx_v]), math.sin(q[jm.idx_v])
        elif jm.nq == 1 and jm.nv == 1:
            config[jm.idx_q] = q[jm.idx_v]
        else:
            fail(f"joint {model.names[i]} ({jm.shortname()}) has nq={jm.nq}, nv={jm.nv}")
    return config


# ----------------------------------------------------------------------------------------------
# Checks on the stimulus.

def check_derivatives(name, q, d, dd, dt, bound3, bound4):
    """Central differences against the written derivatives. The error of (f(t+h) - f(t-h)) / 2h is
    h^2/6 f'''(xi) exactly (Taylor with mean value), so it is bounded by h^2/6 max|f'''| per joint;
    bound3/bound4 are analytic bounds of |q'''| and |q''''| per joint; 1e-9 covers rounding."""
    q, d, dd = np.asarray(q), np.asarray(d), np.asarray(dd)
    d_err = np.max(np.abs((q[2:] - q[:-2]) / (2 * dt) - d[1:-1]), axis=0)
    dd_err = np.max(np.abs((d[2:] - d[:-2]) / (2 * dt) - dd[1:-1]), axis=0)
    d_tol = dt ** 2 / 6 * np.asarray(bound3) + 1e-9
    dd_tol = dt ** 2 / 6 * np.asarray(bound4) + 1e-9
    if np.any(d_err > d_tol) or np.any(dd_err > dd_tol):
        fail(f"{name}: velocities/accelerations are not the derivatives of the angles "
             f"(max |diff| {d_err} rad/s vs {d_tol}, {dd_err} rad/s^2 vs {dd_tol})")


# ----------------------------------------------------------------------------------------------
# The traces. Each returns rows q + qd + qdd (3n floats).

def multiturn(vmax, amax):
    n_rows, dt, n = 1000, 0.01, len(vmax)
    params = []
    for i in range(n):
        omega = (0.4 if i % 2 == 0 else -0.4) * vmax[i]
        w1, w2 = 1.3 + 0.29 * i, 8.0 + 1.7 * i  # rad/s, incommensurate
        a1 = min(0.3 * vmax[i] / w1, 0.45 * amax[i] / w1 ** 2)
        a2 = min(0.2 * vmax[i] / w2, 0.45 * amax[i] / w2 ** 2)
        params.append((0.3 - 0.2 * i, omega, a1, w1, 0.7 * i, a2, w2, 1.9 * i + 0.3))
    for i, (_, omega, a1, w1, _, a2, w2, _) in enumerate(params):  # analytic bounds, before sampling
        if abs(omega) + a1 * w1 + a2 * w2 > vmax[i] or a1 * w1 ** 2 + a2 * w2 ** 2 > amax[i]:
            fail("multiturn: sinusoid parameters exceed the declared ranges")
    q, d, dd = [], [], []
    for k in range(n_rows):
        t = k * dt
        qk, dk, ddk = [], [], []
        for centre, omega, a1, w1, p1, a2, w2, p2 in params:
            qk.append(centre + omega * (t - 5.0) + a1 * math.sin(w1 * t + p1) + a2 * math.sin(w2 * t + p2))
            dk.append(omega + a1 * w1 * math.cos(w1 * t + p1) + a2 * w2 * math.cos(w2 * t + p2))
            ddk.append(-a1 * w1 ** 2 * math.sin(w1 * t + p1) - a2 * w2 ** 2 * math.sin(w2 * t + p2))
        q.append(qk), d.append(dk), dd.append(ddk)
    check_derivatives("multiturn", q, d, dd, dt, [a1 * w1 ** 3 + a2 * w2 ** 3 for _, _, a1, w1, _, a2, w2, _ in params],
                      [a1 * w1 ** 4 + a2 * w2 ** 4 for _, _, a1, w1, _, a2, w2, _ in params])
    spans = np.ptp(np.asarray(q), axis=0)
    if np.any(spans < 2 * PI):
        fail(f"multiturn: an angle does not cover the full circle (spans {spans})")
    return [q[k] + d[k] + dd[k] for k in range(n_rows)]


def rest_to_rest(rng, vmax, amax):
    n = len(vmax)
    rows, pose = [], rng.uniform(-PI, PI, n)
    for move in range(6):
        target = rng.uniform(-PI, PI, n)
        delta = target - pose
        # quintic peaks: velocity 1.875 |delta|/T, acceleration 5.7735 |delta|/T^2; 90 % of the ranges
        duration = max([0.5] + [max(1.875 * abs(delta[i]) / (0.9 * vmax[i]),
                                    math.sqrt(5.7735 * abs(delta[i]) / (0.9 * amax[i]))) for i in range(n)])
        q, d, dd = [], [], []
        for k in range(100):
            tau = k / 99.0
            s = 10 * tau ** 3 - 15 * tau ** 4 + 6 * tau ** 5
            sd = (30 * tau ** 2 - 60 * tau ** 3 + 30 * tau ** 4) / duration
            sdd = (60 * tau - 180 * tau ** 2 + 120 * tau ** 3) / duration ** 2
            q.append(list(pose + s * delta)), d.append(list(sd * delta)), dd.append(list(sdd * delta))
        # |s'''| <= 60, |s''''| <= 360 on [0, 1]
        check_derivatives(f"rest_to_rest move {move}", q, d, dd, duration / 99.0,
                          60 * np.abs(delta) / duration ** 3, 360 * np.abs(delta) / duration ** 4)
        if any(v != 0.0 for v in d[0] + dd[0] + d[-1] + dd[-1]):
            fail(f"rest_to_rest move {move} does not start and end at rest")
        rows += [q[k] + d[k] + dd[k] for k in range(100)]
        pose = target
    return rows


def random_samples(rng, vmax, amax):
    n = len(vmax)
    q = rng.uniform(-PI, PI, (1000, n))
    d = rng.uniform(-np.asarray(vmax), np.asarray(vmax), (1000, n))
    dd = rng.uniform(-np.asarray(amax), np.asarray(amax), (1000, n))
    return [list(q[i]) + list(d[i]) + list(dd[i]) for i in range(1000)]


POSE_A = [0.9, -2.1, 2.6, -0.4, 1.7, -2.9, 0.3]
POSE_B = [-2.5, 1.2, -0.7, 2.2, -1.4, 0.6, -3.0]


def edge_cases(rng, vmax, amax):
    n = len(vmax)
    vmax, amax = list(vmax), list(amax)
    alt = [1.0 if i % 2 == 0 else -1.0 for i in range(n)]
    rest = [0.0] * (2 * n)
    ext_pos = vmax + amax
    ext_neg = [-x for x in ext_pos]
    ext_alt = [alt[i] * vmax[i] for i in range(n)] + [-alt[i] * amax[i] for i in range(n)]
    motions = [rest, ext_pos, ext_neg, ext_alt]
    boundaries = [0.0, PI / 2, -PI / 2, PI, -PI, 3 * PI / 2, 2 * PI]
    rows = []
    # 1. every joint alone on a boundary and 1e-9 either side (the others at 0), cycling the motions
    count = 0
    for j in range(n):
        for b in boundaries:
            for eps in (0.0, 1e-9, -1e-9):
                q = [0.0] * n
                q[j] = b + eps
                rows.append(q + motions[count % 4])
                count += 1
    # 2. all joints together on a boundary and 1e-9 either side, every motion
    for b in boundaries:
        for eps in (0.0, 1e-9, -1e-9):
            for m in motions:
                rows.append([b + eps] * n + m)
    # 3. extreme velocities and accelerations of both signs at two poses
    for pose in (POSE_A[:n], POSE_B[:n]):
        if 2 * n <= 6:
            signs = [[1.0 if c >> k & 1 else -1.0 for k in range(2 * n)] for c in range(2 ** (2 * n))]
        else:
            signs = []
            for sv, sa in ((1, 1), (-1, -1), (1, -1), (-1, 1)):  # all the same sign; qd and qdd opposite
                signs.append([float(sv)] * n + [float(sa)] * n)
            for sv, sa in ((1, 1), (-1, -1), (1, -1), (-1, 1)):  # alternating along the chain
                signs.append([sv * alt[i] for i in range(n)] + [sa * alt[i] for i in range(n)])
            signs += [list(2.0 * row - 1.0) for row in rng.integers(0, 2, (64, 2 * n))]
        for s in signs:
            rows.append(list(pose) + [s[i] * vmax[i] for i in range(n)] + [s[n + i] * amax[i] for i in range(n)])
    # 4. each joint alone at +-vmax, then alone at +-amax, the others at rest, at 0 and at pose A
    for pose in ([0.0] * n, POSE_A[:n]):
        for j in range(n):
            for sign in (1.0, -1.0):
                m = [0.0] * (2 * n)
                m[j] = sign * vmax[j]
                rows.append(list(pose) + m)
                m = [0.0] * (2 * n)
                m[n + j] = sign * amax[j]
                rows.append(list(pose) + m)
    # 5. rest (gravity only) at 0, at the two poses and at 8 seeded poses
    for pose in [[0.0] * n, POSE_A[:n], POSE_B[:n]] + [list(p) for p in rng.uniform(-PI, PI, (8, n))]:
        rows.append(list(pose) + rest)
    return rows


KINDS = [
    ("multiturn", "smooth multi-turn trajectory (10 s at 10 ms; per joint constant speed plus two sinusoids); "
                  "every angle covers the full circle", "none (deterministic, no random numbers)"),
    ("rest_to_rest", "six quintic point-to-point moves between random poses, each from rest to rest "
                     "(100 samples per move)", f"{SEED_REST_TO_REST} (numpy.random.default_rng)"),
    ("random", "uniform random samples: q in [-pi, pi), qd in [-vmax, vmax], qdd in [-amax, amax]",
     f"{SEED_RANDOM} (numpy.random.default_rng)"),
    ("edge_cases", "joints alone and together on 0, +-pi/2, +-pi, 3pi/2, 2pi and +-1e-9 beside; extreme "
                   "velocities/accelerations of both signs at two poses; single-joint extremes; rest (gravity only)",
     f"{SEED_EDGE} (numpy.random.default_rng)"),
]


def make_rows(kind, vmax, amax):
    if kind == "multiturn":
        return multiturn(vmax, amax)
    if kind == "rest_to_rest":
        return rest_to_rest(np.random.default_rng(SEED_REST_TO_REST), vmax, amax)
    if kind == "random":
        return random_samples(np.random.default_rng(SEED_RANDOM), vmax, amax)
    return edge_cases(np.random.default_rng(SEED_EDGE), vmax, amax)


# ----------------------------------------------------------------------------------------------

def write(robot, model, chain, gravity, kind, description, seed, rows):
    n, vmax, amax = model.nv, robot["vmax"], robot["amax"]
    data = model.createData()
    worst_own, worst_crba, worst_closed = 0.0, 0.0, 0.0
    max_tau = [0.0] * n
    lines = []
    for r, s in enumerate(rows):
        s = [float(v) + 0.0 for v in s]
        if len(s) != 3 * n or any(not math.isfinite(v) for v in s):
            fail(f"{robot['name']}_{kind} row {r}: bad sample {s}")
        q, qd, qdd = s[0:n], s[n:2 * n], s[2 * n:3 * n]
        if any(abs(v) > ANGLE_LIMIT for v in q):
            fail(f"{robot['name']}_{kind} row {r}: angle beyond +-4 pi: {q}")
        if any(abs(qd[i]) > vmax[i] or abs(qdd[i]) > amax[i] for i in range(n)):
            fail(f"{robot['name']}_{kind} row {r}: beyond the declared ranges: {qd} {qdd}")
        qp, v, a = to_pinocchio_q(model, q), np.array(qd), np.array(qdd)
        tau = [float(x) for x in pin.rnea(model, data, qp, v, a)]
        own = own_rnea(chain, gravity, q, qd, qdd)
        m = pin.crba(model, data, qp)
        m = np.triu(m) + np.triu(m, 1).T  # crba fills the upper triangle
        second = m @ a + pin.nonLinearEffects(model, data, qp, v)
        d_own = max(abs(tau[i] - own[i]) for i in range(n))
        d_crba = max(abs(tau[i] - float(second[i])) for i in range(n))
        if not (d_own < TOLERANCE and d_crba < TOLERANCE):
            fail(f"{robot['name']}_{kind} row {r}: pin.rnea {tau} vs own Newton-Euler {own} (max diff {d_own:.3e}) "
                 f"vs crba+nle {list(second)} (max diff {d_crba:.3e}); sample {s}")
        if robot["name"] == "planar3":
            closed = make_golden.tau3_exact(make_golden.ROBOT, s)
            if not abs(tau[2] - closed) < TOLERANCE:
                fail(f"planar3_{kind} row {r}: tau3 {tau[2]!r} vs the closed form {closed!r}")
            worst_closed = max(worst_closed, abs(tau[2] - closed))
        worst_own, worst_crba = max(worst_own, d_own), max(worst_crba, d_crba)
        max_tau = [max(max_tau[i], abs(tau[i])) for i in range(n)]
        lines.append(",".join(num(x) for x in s + tau))
    checks = f"max |rnea - own Newton-Euler| = {worst_own:.1e} N*m, max |rnea - (crba qdd + nle)| = {worst_crba:.1e} N*m"
    if robot["name"] == "planar3":
        checks += f", max |tau3 - closed form (docs/equations.md)| = {worst_closed:.1e} N*m"
    names = [model.names[i] for i in range(1, model.njoints)]
    gravity_text = ",".join(short(g) for g in model.gravity.linear)
    urdf = (f"{robot['source']} ({EXAMPLE_ROBOT_DATA}, sha256 {robot['sha256']})" if robot["sha256"]
            else "built in (make_golden.build_arm)")
    header = [
        f"# {robot['name']}_{kind}: {description}",
        f"# regenerate: {COMMAND}",
        f"# reference: Pinocchio {pin.__version__} pin.rnea on {urdf}; checked on every row: {checks}",
        f"# seed: {seed}",
        f"# robot: name={robot['name']} source={robot['source']} tip={robot['tip']}",
        f"# joints: {','.join(names)} (numbered 1..{n} from the root; gravity {gravity_text} m/s^2)",
        f"# ranges: vmax={','.join(short(x) for x in vmax)} amax={','.join(short(x) for x in amax)}",
        f"# declared: {robot['note']}",
        "# units: q rad (any real value); qd rad/s; qdd rad/s^2; tau N*m (joint torque = reducer load)",
    ]
    cols = ([f"q{i}" for i in range(1, n + 1)] + [f"qd{i}" for i in range(1, n + 1)]
            + [f"qdd{i}" for i in range(1, n + 1)] + [f"tau{i}" for i in range(1, n + 1)])
    os.makedirs(OUT_DIR, exist_ok=True)
    with open(os.path.join(OUT_DIR, f"{robot['name']}_{kind}.csv"), "w") as f:
        f.write("\n".join(header + [",".join(cols)] + lines) + "\n")
    closed = f"{worst_closed:.1e}" if robot["name"] == "planar3" else "-"
    print(f"| {robot['name']}_{kind}.csv | {len(rows)} | {' / '.join(f'{x:.2f}' for x in max_tau)} "
          f"| {worst_own:.1e} | {worst_crba:.1e} | {closed} |")


def main():
    print(f"Pinocchio {pin.__version__}, numpy {np.__version__}, {EXAMPLE_ROBOT_DATA} (URDFs in golden/robots/)")
    models = []
    for robot in ROBOTS:
        model, chain, gravity = build_pinocchio(robot)
        if list(model.gravity.linear) != gravity:
            fail(f"{robot['name']}: Pinocchio gravity {list(model.gravity.linear)}, expected {gravity}")
        if robot["vmax"] is None:
            robot["vmax"] = [j["velocity"] for j in chain]
            if list(model.velocityLimit) != robot["vmax"]:
                fail(f"{robot['name']}: Pinocchio velocity limits {list(model.velocityLimit)} vs URDF {robot['vmax']}")
        if len(robot["vmax"]) != model.nv or len(robot["amax"]) != model.nv:
            fail(f"{robot['name']}: ranges for {len(robot['vmax'])}/{len(robot['amax'])} joints, model has {model.nv}")
        models.append((robot, model, chain, gravity))
        names = [model.names[i] for i in range(1, model.njoints)]
        print(f"- {robot['name']}: {model.nv} joints {', '.join(names)}; gravity {[float(g) for g in model.gravity.linear]}; "
              f"vmax {robot['vmax']} rad/s; amax {robot['amax']} rad/s^2")
    print()
    print("| file | rows | max abs(tau_i) N*m, joints 1..n | max abs(rnea - own Newton-Euler) N*m "
          "| max abs(rnea - (crba qdd + nle)) N*m | max abs(tau3 - closed form) N*m |")
    print("| --- | --- | --- | --- | --- | --- |")
    for robot, model, chain, gravity in models:
        for kind, description, seed in KINDS:
            rows = make_rows(kind, robot["vmax"], robot["amax"])
            if len(rows) > 1200:
                fail(f"{robot['name']}_{kind}: {len(rows)} rows (keep every file under 1200)")
            write(robot, model, chain, gravity, kind, description, seed, rows)


if __name__ == "__main__":
    main()
