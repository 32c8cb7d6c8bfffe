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
# Kept copies (`keep, preserve` on a reg) stay registers of their own: 3 x 4 bits.
python3 "$here/estimate.py" --top est_keep --no-fmax --json "$out" "$here/testdata/est_keep.sv"
python3 - "$out" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
want = dict(registers=12, les=12)
bad = {k: (r[k], v) for k, v in want.items() if r[k] != v}
if bad:
    sys.exit(f"estimate selftest (kept copies): got/expected {bad}")
print("estimate selftest: kept copies ok")
PY
