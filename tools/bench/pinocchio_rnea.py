#!/usr/bin/env python3
"""Pinocchio's RNEA time per call on this CPU, for the three golden-trace robots.

For planar3, UR5 and Panda (the same Pinocchio models as golden/make_golden_arms.py: planar3 built in,
UR5 and Panda from golden/robots/ reduced to their chains) this times pin.rnea(model, data, q, v, a)
from Python: `--calls` calls (default 100,000) cycling through 1,000 pre-drawn random samples
(q in [-pi, pi), v and a uniform in +-1, numpy.random.default_rng(1)), repeated `--reps` times
(default 7); the median repetition is reported, in microseconds per call and calls per second, and
beside it the fastest repetition (the least disturbed by other processes on a shared machine).
Single thread: the process is pinned to one CPU and BLAS/OpenMP threads are set to 1 (pin.rnea itself
is single-threaded).

Every call goes through the Python binding (argument conversion, result allocation); the same loop
on an empty model (no joints) shows the smallest such overhead.

With --cpp it also times the same models from C++ (pinocchio_rnea.cpp beside this file, no Python in
the loop): it writes each model with Model.saveToText, compiles pinocchio_rnea.cpp header-only against
the venv's Pinocchio headers and Debian's Eigen (apt-get install libeigen3-dev; about 2-5 minutes of
g++ on 2 cores, cached in --build-dir), runs it, and checks that C++ and Python give the same torques
at a fixed sample.

Run from the repository root (the venv of golden/requirements-arms.txt):
    .venv-golden/bin/python tools/bench/pinocchio_rnea.py [--cpp]
"""
import argparse
import csv
import glob
import hashlib
import os
import platform
import statistics
import subprocess
import sys
import time

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[var] = "1"

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "golden"))
import make_golden_arms  # noqa: E402  (the robots' Pinocchio models)


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def samples(model, count=1000):
    rng = np.random.default_rng(1)
    n = model.nv
    out = []
    for _ in range(count):
        q = make_golden_arms.to_pinocchio_q(model, rng.uniform(-np.pi, np.pi, n)) if n else np.zeros(0)
        out.append((q, rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)))
    return out


def time_per_call(model, calls, reps):
    data = model.createData()
    batch = samples(model)
    rounds = max(1, calls // len(batch))
    rnea = pin.rnea
    per_call = []
    for _ in range(reps):
        t0 = time.perf_counter()
        for _ in range(rounds):
            for q, v, a in batch:
                rnea(model, data, q, v, a)
        per_call.append((time.perf_counter() - t0) / (rounds * len(batch)))
    return statistics.median(per_call), min(per_call)


HERE = os.path.dirname(os.path.abspath(__file__))
CXX_FLAGS = ["-O3", "-std=c++17", "-DNDEBUG", "-DBOOST_MPL_LIMIT_LIST_SIZE=30", "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30",
             "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "-DBOOST_FUSION_INVOKE_MAX_ARITY=12"]


def cpp_times(models, calls, reps, build_dir):
    """Median us/call from C++ for each (name, model); checks C++ and Python torques at a fixed sample."""
    prefix = os.path.join(os.path.dirname(os.path.dirname(pin.__file__)), "cmeel.prefix")
    if not os.path.isdir(os.path.join(prefix, "include", "pinocchio")):
        candidates = glob.glob(os.path.join(sys.prefix, "lib", "python3*", "site-packages", "cmeel.prefix"))
        prefix = candidates[0] if candidates else prefix
    source = os.path.join(HERE, "pinocchio_rnea.cpp")
    with open(source, "rb") as f:
        key = hashlib.sha256(f.read() + " ".join(CXX_FLAGS + [prefix]).encode()).hexdigest()[:16]
    os.makedirs(build_dir, exist_ok=True)
    binary = os.path.join(build_dir, f"pinocchio_rnea_cpp-{key}")
    if not os.path.exists(binary):
        print(f"compiling {source} (a few minutes) ...", file=sys.stderr)
        build = subprocess.run(["g++"] + CXX_FLAGS + ["-I" + os.path.join(prefix, "include"), "-I/usr/include/eigen3", source,
                        "-o", binary, "-L" + os.path.join(prefix, "lib"), "-Wl,-rpath," + os.path.join(prefix, "lib"),
                        "-lboost_serialization"], capture_output=True, text=True)
        if build.returncode != 0:
            sys.exit(f"g++ failed:\n{build.stderr[-20000:]}")
    args = [binary, str(calls), str(reps)]
    for name, model in models:
        path = os.path.join(build_dir, f"{name}.model.txt")
        model.saveToText(path)
        args += [name, path]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout.split("\n")
    result = {}
    for (name, model), line in zip(models, out):
        got_name, _, us, us_best, tau_sum, _ = line.split()
        q = np.array([0.1 * (j + 1) for j in range(model.nq)])
        expected = float(np.sum(pin.rnea(model, model.createData(), q, np.full(model.nv, 0.2), np.full(model.nv, -0.3))))
        if got_name != name or abs(float(tau_sum) - expected) > 1e-9:
            sys.exit(f"C++ and Python disagree for {name}: sum tau {tau_sum} vs {expected!r}")
        result[name] = (float(us) * 1e-6, float(us_best) * 1e-6)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--calls", type=int, default=100_000, help="calls per repetition (default 100000)")
    parser.add_argument("--reps", type=int, default=7, help="repetitions, the median is reported (default 7)")
    parser.add_argument("--cpp", action="store_true", help="also time from C++ (compiles pinocchio_rnea.cpp)")
    parser.add_argument("--codegen", action="store_true",
                        help="also time RNEA generated per robot with its constants folded (CasADi -> C, gcc -O3 -march=native)")
    parser.add_argument("--csv", help="also write the rows to this CSV (docs/sweep/cpu.csv: the sweep's CPU anchors)")
    parser.add_argument("--build-dir", default=os.path.join(ROOT, "target", "bench"),
                        help="where --cpp keeps the compiled benchmark and model files (default target/bench)")
    args = parser.parse_args()
    if args.csv and not os.access(os.path.dirname(os.path.abspath(args.csv)), os.W_OK):
        sys.exit(f"error: --csv {args.csv}: its directory is not writable")
    if args.csv and os.path.exists(args.csv) and not os.access(args.csv, os.W_OK):
        sys.exit(f"error: --csv {args.csv}: the file is read-only")
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    print(f"Pinocchio {pin.__version__}, numpy {np.__version__}, Python {platform.python_version()}; "
          f"CPU: {cpu_model()} ({os.cpu_count()} logical CPUs, 1 used); {args.calls} calls x {args.reps} reps, median")
    empty = pin.Model()
    overhead, overhead_best = time_per_call(empty, args.calls, args.reps)
    print()
    built = [(robot["name"],) + make_golden_arms.build_pinocchio(robot) for robot in make_golden_arms.ROBOTS]
    models = [(name, model) for name, model, _, _ in built]
    cpp = cpp_times(models, args.calls, args.reps, args.build_dir) if args.cpp else {}
    codegen = {}
    if args.codegen:
        import codegen_rnea
        rng = np.random.default_rng(1)
        for name, model, chain, gravity in built:
            n = model.nv
            raw = [(rng.uniform(-np.pi, np.pi, n), rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)) for _ in range(1000)]
            codegen[name] = codegen_rnea.time_and_check(name, model, chain, gravity, args.calls * 10, args.reps,
                                                        args.build_dir, raw)
    print("| robot | joints | Python pin.rnea: us/call | calls/s | C++ pinocchio::rnea: us/call | calls/s "
          "| generated C (constants folded): us/call | calls/s | its operations "
          "| fastest repetition, Python / C++ / generated: us/call |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    print(f"| (empty model: binding overhead) | 0 | {overhead * 1e6:.3f} | {1 / overhead:,.0f} | - | - | - | - | - "
          f"| {overhead_best * 1e6:.3f} / - / - |")
    rows = []
    for name, model in models:
        t, t_best = time_per_call(model, args.calls, args.reps)
        c, c_best = cpp.get(name, (None, None))
        g, g_best, ops = codegen.get(name, (None, None, None))
        us = lambda x: "-" if x is None else f"{x * 1e6:.3f}"
        rate = lambda x: "-" if x is None else f"{1 / x:,.0f}"
        print(f"| {name} | {model.nv} | {us(t)} | {rate(t)} | {us(c)} | {rate(c)} | {us(g)} | {rate(g)} "
              f"| {'-' if ops is None else ops} | {us(t_best)} / {us(c_best)} / {us(g_best)} |")
        for engine, (x, best), n in [("pinocchio-python", (t, t_best), ""), ("pinocchio-cpp", (c, c_best), ""),
                                     ("generated-c", (g, g_best), "" if ops is None else ops)]:
            if x is not None:
                rows.append([name, model.nv, engine, f"{x * 1e6:.3f}", f"{1 / x:.0f}", f"{best * 1e6:.3f}", n])
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"\nload average after the run: {load}")
    if args.csv:
        # the machine and the load beside every row: a CPU figure means little without them
        # no commas: the sweep reads the file as plain comma-separated cells
        machine = f"{cpu_model()} ({os.cpu_count()} CPUs: 1 used; load after {load})".replace(",", " ")
        tmp = args.csv + ".tmp"
        with open(tmp, "w", newline="") as out:
            w = csv.writer(out)
            w.writerow(["robot", "joints", "engine", "us_per_call", "calls_per_s", "us_fastest_rep", "operations",
                        "machine"])
            for r in rows:
                w.writerow(r + [machine])
        os.replace(tmp, args.csv)
        print(f"wrote {args.csv}")


if __name__ == "__main__":
    main()
