#!/usr/bin/env python3
"""Compile a SystemRDL file with systemrdl-compiler and export PeakRDL's C header of it.

    python3 tools/regmap/peakrdl_header.py MAP.rdl OUT.h

The generator writes <name>_regs.rdl beside the Verilog (`run emit` of a design with the monitor);
RegMapSpec feeds it through this script and checks PeakRDL's header agrees with the generator's own
<name>_regs.h on every register offset and field. Runs itself inside tools/regmap/.venv (pinned
requirements.txt), created on first use. Exit 3: the package index is unreachable (the test skips, saying
so); 2: the SystemRDL does not compile; 1: any other failure.
"""
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
VENV = os.path.join(HERE, ".venv")
REQUIREMENTS = os.path.join(HERE, "requirements.txt")


def index_reachable(pip):
    """Whether pip reaches its configured package index (asked by package name, no host written here)."""
    probe = subprocess.run([pip, "index", "versions", "systemrdl-compiler"], capture_output=True)
    return probe.returncode == 0


def ensure_venv():
    """Re-run this script inside the pinned venv, creating it on first use."""
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        print(f"peakrdl_header: installing {REQUIREMENTS} into {VENV} (first use)", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
        pip = os.path.join(VENV, "bin", "pip")
        installed = subprocess.run([pip, "install", "-q", "-r", REQUIREMENTS])
        if installed.returncode != 0:
            reachable = index_reachable(pip)
            # A half-built venv would pass for a complete one next time.
            subprocess.run(["rm", "-rf", VENV], check=False)
            if not reachable:
                print("peakrdl_header: the package index is unreachable: cannot install PeakRDL", file=sys.stderr)
                sys.exit(3)
            sys.exit(1)
    os.execv(py, [py] + sys.argv)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(1)
    ensure_venv()
    from systemrdl import RDLCompileError, RDLCompiler
    from peakrdl_cheader.exporter import CHeaderExporter

    rdlc = RDLCompiler()
    try:
        rdlc.compile_file(sys.argv[1])
        root = rdlc.elaborate()
    except RDLCompileError:
        sys.exit(2)
    CHeaderExporter().export(root, sys.argv[2])


if __name__ == "__main__":
    main()
