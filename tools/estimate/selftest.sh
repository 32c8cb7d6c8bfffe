#!/usr/bin/env bash
# Check the estimator on designs whose resources are known: a 16-bit adder (16 LEs, its result
# register packs into them) and one 18x18 multiply whose 36 input and 36 output register bits are
# the embedded multiplier's own registers (no LEs); and two kept copies of a register.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="$(mktemp)"
python3 "$here/estimate.py" --top est_probe --no-fmax --json "$out" "$here/testdata/est_probe.sv"
python3 - "$out" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
want = dict(les_arith=16, registers=88, registers_in_blocks=72, mult18x18=1, les=16, memory_bits=0)
bad = {k: (r[k], v) for k, v in want.items() if r[k] != v}
if bad:
    sys.exit(f"estimate selftest: got/expected {bad}")
print("estimate selftest: adder and multiply ok")
PY
# Kept copies (`keep, preserve` on a reg) stay registers of their own: 3 x 4 bits. --registers names them:
# the copies (c0, c1) loaded from the register r, r from the input port.
python3 "$here/estimate.py" --top est_keep --no-fmax --registers --json "$out" "$here/testdata/est_keep.sv" >/dev/null
python3 - "$out" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
want = dict(registers=12, les=12)
bad = {k: (r[k], v) for k, v in want.items() if r[k] != v}
if bad:
    sys.exit(f"estimate selftest (kept copies): got/expected {bad}")
own = [(x["name"], x["loaded_from"], x["bits"]) for x in r["registers_own_le"]]
if own != [("c#", "a register", 8), ("r", "a port or constant", 4)]:
    sys.exit(f"estimate selftest (--registers): got {own}")
print("estimate selftest: kept copies ok")
PY
# A memory read as Chisel reads it (address register, word), then a register in the logic: the M9K holds the
# address and output registers, the register after them takes an LE per bit (8), the adder 9.
python3 "$here/estimate.py" --top est_ram_word --no-fmax --registers --json "$out" "$here/testdata/est_ram_word.sv" >/dev/null
python3 - "$out" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
want = dict(registers_in_blocks=5, registers_unpacked=8, les=17, m9k_blocks=1)
bad = {k: (r[k], v) for k, v in want.items() if r[k] != v}
own = [(x["name"], x["bits"]) for x in r["registers_own_le"]]
if bad or own != [("fabric", 8)]:
    sys.exit(f"estimate selftest (memory word): got/expected {bad}, registers with an LE {own}")
print("estimate selftest: memory word registers ok")
PY
# A block-RAM delay whose word an adder reads: Yosys takes the word's register into the RAM and leaves
# the read address register in the fabric; the flow moves that register into the DP16KD and gives it
# its output register, as an M9K has (needs the ECP5 tools: installed into the venv on first use).
python3 - "$here" <<'PY'
import json, os, shutil, sys, tempfile
sys.path.insert(0, sys.argv[1])
import estimate
work = tempfile.mkdtemp(prefix="estimate-selftest-")
design = os.path.join(sys.argv[1], "testdata", "est_delay.sv")
shutil.copy(design, work)
changed = estimate.ecp5_synthesis([design], "est_delay", work)
cells = json.load(open(os.path.join(work, "ecp5.json")))["modules"]["est_delay"]["cells"].values()
rams = [c for c in cells if c["type"] == "DP16KD"]
modes = sorted(c["parameters"].get("REGMODE_B", "NOREG") for c in rams)
ffs = sum(c["type"] == "TRELLIS_FF" for c in cells)
shutil.rmtree(work)
# 5 pointer + 9 result flip-flops stay; the 5 read-address ones moved into the RAM
if (changed, modes, ffs) != (1, ["OUTREG"], 14):
    sys.exit(f"estimate selftest (delay): got {changed} RAMs changed, modes {modes}, {ffs} flip-flops; expected 1, ['OUTREG'], 14")
print("estimate selftest: block-RAM delay ok")
PY
# A small memory (16 x 8) is a DP16KD on the ECP5, never LUT RAM: the Cyclone IV E has only M9Ks.
python3 - "$here" <<'PY'
import json, os, shutil, sys, tempfile
sys.path.insert(0, sys.argv[1])
import estimate
work = tempfile.mkdtemp(prefix="estimate-selftest-")
design = os.path.join(sys.argv[1], "testdata", "est_small_ram.sv")
shutil.copy(design, work)
estimate.ecp5_synthesis([design], "est_small_ram", work)
cells = json.load(open(os.path.join(work, "ecp5.json")))["modules"]["est_small_ram"]["cells"].values()
kinds = sorted({c["type"] for c in cells if c["type"] in ("DP16KD", "TRELLIS_DPR16X4")})
shutil.rmtree(work)
if kinds != ["DP16KD"]:
    sys.exit(f"estimate selftest (small memory): got {kinds}; expected ['DP16KD']")
print("estimate selftest: small memory in block RAM ok")
PY
# Several seeds: one synthesis, a place and route per seed, the slowest seed's clock as the figure; a run
# stopped by --minutes (here before it places anything) is reported as not routed, with no clock.
python3 "$here/estimate.py" --top est_probe --seed 1,2 --jobs 2 --json "$out" "$here/testdata/est_probe.sv" >/dev/null
python3 - "$out" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
runs = r["runs"]
ok = (r["seed"] == [1, 2] and [x["seed"] for x in runs] == [1, 2] and r["routed"] and all(x["routed"] for x in runs)
      and r["fmax_ecp5_mhz"] == min(x["fmax_mhz"] for x in runs))
if not ok:
    sys.exit(f"estimate selftest (seeds): got {r}")
print("estimate selftest: several seeds ok")
PY
python3 "$here/estimate.py" --top est_probe --minutes 0.001 --json "$out" "$here/testdata/est_probe.sv" >/dev/null
python3 - "$out" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
if r["routed"] or r["fmax_ecp5_mhz"] is not None:
    sys.exit(f"estimate selftest (stopped run): got routed {r['routed']}, fmax {r['fmax_ecp5_mhz']}")
print("estimate selftest: a stopped run ok")
PY
