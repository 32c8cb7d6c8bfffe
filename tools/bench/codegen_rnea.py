"""A code-generated RNEA: the robot's constants folded into straight-line C (the strongest CPU peer).

The software peer the FPGA datapath is compared with is not only Pinocchio's generic rnea but RNEA
generated for one robot with its constants folded (the GRiD benchmarks' CPU baseline: Pinocchio with
CppADCodeGen). The pip `pin` wheel has no CasADi bindings, so this module writes the same Newton-Euler
as golden/make_golden_arms.py's own model (`own_rnea`: body frames, gravity as a base acceleration)
over CasADi SX symbols: constant products fold and products by 0 or 1 vanish as the expression is
built, CasADi generates C from it, and gcc compiles it with -O3 -march=native. Every generated
function is checked against pin.rnea on random samples before it is timed.
"""
import hashlib
import os
import subprocess
import sys

import casadi as ca
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CFLAGS = ["-O3", "-march=native", "-std=c99"]
TOLERANCE = 1e-9  # N*m, generated C against pin.rnea


def _rotation(axis, s, c):
    """Rodrigues with symbolic sin/cos: I + s K + (1 - c) K^2 for the unit axis' cross-product matrix K."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return ca.SX(np.eye(3)) + s * ca.SX(k) + (1 - c) * ca.SX(k @ k)


def rnea_expression(chain, gravity):
    """tau(q, qd, qdd) of the own chain as one CasADi SX Function (revolute and prismatic joints)."""
    n = len(chain)
    q, qd, qdd = ca.SX.sym("q", n), ca.SX.sym("qd", n), ca.SX.sym("qdd", n)
    w, wd, vd = ca.SX.zeros(3), ca.SX.zeros(3), ca.SX(-np.asarray(gravity, dtype=float))
    frames, forces, moments = [], [], []
    for k, j in enumerate(chain):
        a = ca.SX(j["axis"])
        r0 = ca.SX(j["r0"])
        if j["prismatic"]:
            rot, p = r0, ca.SX(j["p0"]) + ca.mtimes(r0, a) * q[k]
        else:
            rot, p = ca.mtimes(r0, _rotation(j["axis"], ca.sin(q[k]), ca.cos(q[k]))), ca.SX(j["p0"])
        rt = rot.T
        vd_origin = ca.mtimes(rt, vd + ca.cross(wd, p) + ca.cross(w, ca.cross(w, p)))
        w_in, wd_in = ca.mtimes(rt, w), ca.mtimes(rt, wd)
        if j["prismatic"]:
            w, wd = w_in, wd_in
            vd = vd_origin + 2 * ca.cross(w, a * qd[k]) + a * qdd[k]
        else:
            w = w_in + a * qd[k]
            wd = wd_in + ca.cross(w_in, a * qd[k]) + a * qdd[k]
            vd = vd_origin
        m, h, i_o = j["mass"], ca.SX(j["h"]), ca.SX(j["inertia"])
        forces.append(m * vd + ca.cross(wd, h) + ca.cross(w, ca.cross(w, h)))
        moments.append(ca.mtimes(i_o, wd) + ca.cross(w, ca.mtimes(i_o, w)) + ca.cross(h, vd))
        frames.append((rot, p))
    tau = [None] * n
    f_next = n_next = None
    for k in range(n - 1, -1, -1):
        if f_next is None:
            f_k, n_k = forces[k], moments[k]
        else:
            rot, p = frames[k + 1]
            f_child = ca.mtimes(rot, f_next)
            f_k = forces[k] + f_child
            n_k = moments[k] + ca.mtimes(rot, n_next) + ca.cross(p, f_child)
        tau[k] = ca.dot(ca.SX(chain[k]["axis"]), f_k if chain[k]["prismatic"] else n_k)
        f_next, n_next = f_k, n_k
    return ca.Function("rnea", [q, qd, qdd], [ca.vertcat(*tau)])


HARNESS = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "rnea.h"

/* rnea_bench CALLS REPS < samples: the first line "n count", then count lines q(n) qd(n) qdd(n).
   Prints the median and the fastest repetition in ns per call, then tau of the first sample. */
static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}
static int by_value(const void* a, const void* b) {
  double x = *(const double*)a, y = *(const double*)b;
  return (x > y) - (x < y);
}
int main(int argc, char** argv) {
  long calls = atol(argv[1]);
  int reps = atoi(argv[2]), n, count;
  if (scanf("%d %d", &n, &count) != 2) return 2;
  double* s = malloc(sizeof(double) * 3 * n * count);
  for (long i = 0; i < 3L * n * count; i++)
    if (scanf("%lf", &s[i]) != 1) return 2;
  casadi_int sz_arg, sz_res, sz_iw, sz_w;
  rnea_work(&sz_arg, &sz_res, &sz_iw, &sz_w);
  const double** arg = malloc(sizeof(double*) * (sz_arg > 3 ? sz_arg : 3));
  double** res = malloc(sizeof(double*) * (sz_res > 1 ? sz_res : 1));
  casadi_int* iw = malloc(sizeof(casadi_int) * (sz_iw + 1));
  double* w = malloc(sizeof(double) * (sz_w + 1));
  double* tau = malloc(sizeof(double) * n);
  double* per_call = malloc(sizeof(double) * reps);
  volatile double sink = 0;
  res[0] = tau;
  for (int r = 0; r < reps; r++) {
    double t0 = now();
    for (long c = 0; c < calls; c++) {
      const double* x = s + 3L * n * (c % count);
      arg[0] = x; arg[1] = x + n; arg[2] = x + 2 * n;
      rnea(arg, res, iw, w, 0);
      sink += tau[0];
    }
    per_call[r] = (now() - t0) / calls * 1e9;
  }
  double fastest = per_call[0];
  for (int r = 1; r < reps; r++) if (per_call[r] < fastest) fastest = per_call[r];
  qsort(per_call, reps, sizeof(double), by_value);
  printf("%.3f %.3f\n", per_call[reps / 2], fastest);
  arg[0] = s; arg[1] = s + n; arg[2] = s + 2 * n;
  rnea(arg, res, iw, w, 0);
  for (int j = 0; j < n; j++) printf("%.17g\n", tau[j]);
  return sink == 12345.678 ? 3 : 0;
}
"""


def build(name, function, build_dir):
    """Generate rnea.c/.h for one robot and compile it with the harness; cached by the source's hash."""
    os.makedirs(build_dir, exist_ok=True)
    work = os.path.join(build_dir, f"codegen-{name}")
    os.makedirs(work, exist_ok=True)
    cwd = os.getcwd()
    os.chdir(work)
    try:
        function.generate("rnea.c", {"with_header": True})
    finally:
        os.chdir(cwd)
    with open(os.path.join(work, "rnea.c"), "rb") as f:
        key = hashlib.sha256(f.read() + HARNESS.encode() + " ".join(CFLAGS).encode()).hexdigest()[:16]
    binary = os.path.join(work, f"rnea_bench-{key}")
    if not os.path.exists(binary):
        with open(os.path.join(work, "bench.c"), "w") as f:
            f.write(HARNESS)
        out = subprocess.run(["gcc"] + CFLAGS + ["-I" + work, os.path.join(work, "bench.c"),
                             os.path.join(work, "rnea.c"), "-o", binary, "-lm"], capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"gcc failed for {name}:\n{out.stderr[-5000:]}")
    return binary


def instructions(function):
    """Operations of the generated straight-line code (CasADi's count of its SX algorithm)."""
    return function.n_instructions()


def time_and_check(name, model, chain, gravity, calls, reps, build_dir, samples):
    """Median and fastest ns per call of the generated C; exits if it differs from pin.rnea."""
    import pinocchio as pin
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "golden"))
    import make_golden_arms

    function = rnea_expression(chain, gravity)
    data = model.createData()
    worst = 0.0
    for q, v, a in samples[:100]:
        got = np.array(function(q, v, a)).ravel()
        ref = pin.rnea(model, data, make_golden_arms.to_pinocchio_q(model, q), v, a)
        worst = max(worst, float(np.max(np.abs(got - ref))))
    if worst > TOLERANCE:
        sys.exit(f"{name}: the CasADi RNEA differs from pin.rnea by {worst:.3g} N*m")
    binary = build(name, function, build_dir)
    n = len(chain)
    text = f"{n} {len(samples)}\n" + "\n".join(" ".join(repr(float(x)) for x in np.concatenate(s)) for s in samples)
    out = subprocess.run([binary, str(calls), str(reps)], input=text, capture_output=True, text=True, check=True)
    lines = out.stdout.split()
    median, fastest = float(lines[0]), float(lines[1])
    tau = np.array([float(x) for x in lines[2:2 + n]])
    q, v, a = samples[0]
    ref = pin.rnea(model, data, make_golden_arms.to_pinocchio_q(model, q), v, a)
    if np.max(np.abs(tau - ref)) > TOLERANCE:
        sys.exit(f"{name}: the compiled RNEA differs from pin.rnea at the first sample")
    return median * 1e-9, fastest * 1e-9, instructions(function)
