#!/usr/bin/env python3
"""Fault and resume test of tools/sweep/evaluate.py on a real two-worker Dask cluster on loopback.

    python3 tools/sweep/test_cluster.py MANIFEST WORKDIR [--deadline SECONDS]

MANIFEST: a small sweep from `./sbt "run sweep --arms --emit-only --robots planar3 --schedules ii64,ii256"`
(ArmSweepDaskSpec writes one). Starts `dask scheduler` and two `dask worker`s (each in a session of its
own), then:

1. evaluates the manifest plus one broken point (Verilog Yosys refuses) on the cluster, and kills the first
   worker seen running a good point's job (its whole session, and the job's tools, as if its machine died):
   every good point must still finish (Dask moves the lost job to the other worker), the broken one is
   recorded as failed with its log;
2. evaluates again: nothing is recomputed (every good point cached; the failed one is tried again);
3. removes one result and leaves a half-written temporary in the cache, as an interrupted sweep does:
   the next run computes that one job only;
4. evaluates with `--timeout 2` into a fresh cache: every job failed with its log, the run ends normally;
5. on a second cluster whose one worker cannot run the flow (REDUCERLOAD_ESTIMATE names no clone, so the job
   raises on the worker), evaluates with `--retries 2`: Dask runs every job three times (the worker's log
   counts them), then each is recorded as failed with the worker's error.

Every run with a failed job must exit 1 after writing its results.

Writes WORKDIR/results.json (run 1's good points) for the caller to merge, prints one line per check, exits 1
on a failed check. Stops everything it started by itself within --deadline (default 1200 s).
"""
import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from evaluate import VENV, ensure_venv, sha256_file  # noqa: E402

started = []


def start(cmd, log, env=None):
    # Temporary files in the test's own directory: a worker killed mid-job (check 1) cannot remove its job's.
    tmp = os.path.join(os.path.dirname(os.path.abspath(log)), "tmp")
    os.makedirs(tmp, exist_ok=True)
    env = dict(env if env is not None else os.environ, TMPDIR=tmp)
    p = subprocess.Popen(cmd, stdout=open(log, "w"), stderr=subprocess.STDOUT, start_new_session=True, env=env)
    started.append(p)
    return p


def stop(p):
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    p.wait()


def estimate_sessions(sid):
    """Sessions of the estimate.py processes of good points a worker (session `sid`) started: mid-job if any. The job runs
    estimate.py in a session of its own (so a timeout can stop its tools), hence by ancestry, not by session."""
    procs = {}
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            stat = open(f"/proc/{pid}/stat").read()
            ppid = int(stat.rsplit(")", 1)[1].split()[1])
            procs[int(pid)] = (ppid, os.getsid(int(pid)), open(f"/proc/{pid}/cmdline", "rb").read())
        except (OSError, ProcessLookupError, ValueError, IndexError):
            pass

    def in_worker(pid):
        while pid in procs and pid > 1:
            if procs[pid][1] == sid:
                return True
            pid = procs[pid][0]
        return False
    return {s for pid, (_, s, cmd) in procs.items() if b"estimate.py" in cmd and b"Broken" not in cmd and in_worker(pid)}


def check(ok, what):
    print(f"test_cluster: {'ok' if ok else 'FAILED'}: {what}", flush=True)
    if not ok:
        raise SystemExit(1)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("manifest")
    ap.add_argument("workdir")
    ap.add_argument("--deadline", type=float, default=1200.0)
    a = ap.parse_args()
    ensure_venv()
    t0 = time.time()
    os.makedirs(a.workdir, exist_ok=True)
    base = os.path.dirname(os.path.abspath(a.manifest))
    manifest = json.load(open(a.manifest))
    good = len(manifest["points"]) * len(manifest["seeds"])
    # One point whose Verilog Yosys refuses: a tool failure, recorded, the sweep goes on.
    broken = os.path.join(base, "points", "broken.sv")
    with open(broken, "w") as f:
        f.write("module Broken(input a; endmodule\n")
    manifest["points"].append({"key": "broken", "robot": "none", "point": "broken", "settings": {}, "top": "Broken",
                               "path": "points/broken.sv", "sha256": sha256_file(broken)})
    with_broken = os.path.join(base, "manifest-test.json")
    with open(with_broken, "w") as f:
        json.dump(manifest, f)

    dask = os.path.join(VENV, "bin", "dask")

    def cluster(name, n, env=None):
        """A scheduler on a free loopback port and `n` single-threaded workers; returns its address and workers."""
        s = socket.socket()
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
        s.close()
        address = f"tcp://127.0.0.1:{port}"
        start([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"], os.path.join(a.workdir, f"{name}-scheduler.log"))
        workers = [start([dask, "worker", address, "--host", "127.0.0.1", "--nthreads", "1", "--no-dashboard", "--name", f"w{i}"],
                         os.path.join(a.workdir, f"{name}-worker{i}.log"), env) for i in range(n)]
        from distributed import Client
        with Client(address, timeout=60) as c:
            c.wait_for_workers(n, timeout=120)
        print(f"test_cluster: {name}: scheduler {address}, {n} workers ({time.time() - t0:.0f} s)", flush=True)
        return address, workers

    try:
        address, workers = cluster("main", 2)

        def evaluate(n, extra=(), at=address):
            # argparse keeps the last of a repeated option: `extra` overrides the cache and the timeout.
            return start([sys.executable, os.path.join(HERE, "evaluate.py"), with_broken, "--cluster", at,
                          "--cache", os.path.join(a.workdir, "cache"), "--results", os.path.join(a.workdir, f"results{n}.json"),
                          "--timeout", "600", *extra], os.path.join(a.workdir, f"evaluate{n}.log"))

        run1 = evaluate(1)
        killed = False
        while run1.poll() is None:
            if time.time() - t0 > a.deadline:
                check(False, f"run 1 within {a.deadline:.0f} s")
            # Whichever worker first runs a good point's job: Dask decides where jobs go.
            busy = [] if killed else [(i, w, js) for i, w in enumerate(workers) for js in [estimate_sessions(w.pid)] if js]
            for i, w, jobs in busy[:1]:
                time.sleep(2)  # well inside the job (estimates here take tens of seconds)
                stop(w)
                for job in jobs:  # as if its machine died: the job's tools too
                    try:
                        os.killpg(job, signal.SIGKILL)
                    except ProcessLookupError:
                        pass
                killed = True
                print(f"test_cluster: killed worker w{i} mid-job ({time.time() - t0:.0f} s)", flush=True)
            time.sleep(0.5)
        print(open(os.path.join(a.workdir, "evaluate1.log")).read(), flush=True)
        check(run1.returncode == 1, "run 1 exits 1 (a job failed)")
        check(killed, "a worker was killed while running a job")
        r1 = json.load(open(os.path.join(a.workdir, "results1.json")))
        summary = r1["summary"]
        check(summary["ran"] == good and summary["failed"] == 1 and summary["cached"] == 0,
              f"run 1: {good} ran, 1 failed, 0 cached (got {summary})")
        bad = [j for j in r1["jobs"] if j["key"] == "broken"][0]
        check(bad["status"] == "failed" and os.path.isfile(bad["log"]) and "Broken" in open(bad["log"]).read(),
              f"the broken point is recorded as failed with its log ({bad['log']})")

        run2 = evaluate(2)
        try:
            run2.wait(timeout=max(1.0, a.deadline - (time.time() - t0)))
        except subprocess.TimeoutExpired:
            check(False, f"run 2 within {a.deadline:.0f} s")
        print(open(os.path.join(a.workdir, "evaluate2.log")).read(), flush=True)
        r2 = json.load(open(os.path.join(a.workdir, "results2.json")))
        check(r2["summary"]["ran"] == 0 and r2["summary"]["cached"] == good,
              f"run 2 recomputes nothing: {good} cached, 0 ran (got {r2['summary']})")
        same = {(j["key"], j["seed"]): j["estimate"] for j in r1["jobs"] if j["status"] == "ok"} == \
            {(j["key"], j["seed"]): j["estimate"] for j in r2["jobs"] if j["status"] == "ok"}
        check(same, "run 2's results equal run 1's")
        # As an interrupted sweep leaves it: one job's result missing, a half-written temporary beside the others.
        first = [j for j in r1["jobs"] if j["status"] == "ok"][0]
        os.unlink(os.path.join(a.workdir, "cache", first["cache_key"] + ".json"))
        with open(os.path.join(a.workdir, "cache", ".tmp-partial"), "w") as f:
            f.write('{"status": "ok", "estim')
        run3 = evaluate(3)
        run3.wait(timeout=max(1.0, a.deadline - (time.time() - t0)))
        r3 = json.load(open(os.path.join(a.workdir, "results3.json")))
        check(r3["summary"]["ran"] == 1 and r3["summary"]["cached"] == good - 1,
              f"an interrupted sweep picks up: 1 ran, {good - 1} cached (got {r3['summary']})")
        # A job past --timeout: failed with its log, the sweep goes on.
        run4 = evaluate(4, ["--timeout", "2", "--cache", os.path.join(a.workdir, "cache-timeout")])
        run4.wait(timeout=max(1.0, a.deadline - (time.time() - t0)))
        r4 = json.load(open(os.path.join(a.workdir, "results4.json")))
        timed_out = [j for j in r4["jobs"] if j["key"] != "broken"]
        check(run4.returncode == 1 and all(j["status"] == "failed" and "timed out" in j["error"] and os.path.isfile(j["log"]) for j in timed_out)
              and r4["summary"]["failed"] == good + 1, f"jobs past --timeout are failed with their logs (got {r4['summary']})")
        # A job that raises on its worker: Dask's retries, then failed with the worker's error.
        bad_env = dict(os.environ, REDUCERLOAD_ESTIMATE=os.path.join(a.workdir, "no-clone"))
        bad_address, bad_workers = cluster("retry", 1, bad_env)
        run5 = evaluate(5, ["--retries", "2", "--cache", os.path.join(a.workdir, "cache-retry")], at=bad_address)
        run5.wait(timeout=max(1.0, a.deadline - (time.time() - t0)))
        stop(bad_workers[0])  # its log complete
        attempts = open(os.path.join(a.workdir, "retry-worker0.log")).read().count("Compute Failed")
        r5 = json.load(open(os.path.join(a.workdir, "results5.json")))
        check(run5.returncode == 1 and attempts == 3 * (good + 1) and r5["summary"]["failed"] == good + 1
              and all(j["status"] == "failed" and "not found" in j["error"] for j in r5["jobs"]),
              f"a job that raises is run 1 + 2 retries times, then failed with the worker's error ({attempts} attempts, {r5['summary']})")
        r1["jobs"] = [j for j in r1["jobs"] if j["key"] != "broken"]
        with open(os.path.join(a.workdir, "results.json"), "w") as f:
            json.dump(r1, f, indent=2)
        print(f"test_cluster: all checks passed in {time.time() - t0:.0f} s", flush=True)
    finally:
        for p in started:
            stop(p)
        os.unlink(broken)
        os.unlink(with_broken)


if __name__ == "__main__":
    main()
