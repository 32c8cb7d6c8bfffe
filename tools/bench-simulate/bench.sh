#!/usr/bin/env bash
# Benchmark of `run simulate` (issue 14), not a test. For each design it writes a seeded random
# trajectory within the declared ranges (`run trajectory`), warms the harness cache with a short run,
# then times `./sbt "run simulate ..."` end to end (sbt start-up, elaboration, cached harness, CSV
# input and output) once per engine, and prints a table. The model's and the RTL's files must be
# identical (checked with cmp). The machine's load is printed: on a shared machine, figures are noisy.
#
# usage: tools/bench-simulate/bench.sh [joint3] [ur5] [ur5-shared] [ur5-memory]   (default: all four)
# env:   SAMPLES (joint3, default 1000000), UR5_SAMPLES (default 200000), SEED (default 1),
#        WORK (scratch directory, default ${TMPDIR:-/tmp}/reducer-load-bench)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$root"
samples="${SAMPLES:-1000000}"
ur5_samples="${UR5_SAMPLES:-200000}"
seed="${SEED:-1}"
work="${WORK:-${TMPDIR:-/tmp}/reducer-load-bench}"
mkdir -p "$work"
designs=("$@")
[ ${#designs[@]} -gt 0 ] || designs=(joint3 ur5 ur5-shared ur5-memory)

ur5=(--robot golden/robots/ur5_robot.urdf --tip tool0 --max-acceleration 15)
rows=()

# design label, engine, sample count, design settings...
bench() {
  local label="$1" engine="$2" n="$3"; shift 3
  local input="$work/$label-$n-$seed.csv" out="$work/$label-$engine.csv" log="$work/$label-$engine.log"
  if [ ! -s "$input" ]; then
    ./sbt --error "run trajectory --samples $n --seed $seed --output $input $*" >/dev/null
  fi
  if [ "$engine" = rtl ]; then # warm the harness cache (a build is not part of the measurement)
    head -1001 "$input" > "$work/$label-warm.csv"
    ./sbt --error "run simulate --input $work/$label-warm.csv --output $work/$label-warm-out.csv $*" >/dev/null
  fi
  local load; load="$(cut -d' ' -f1 /proc/loadavg)"
  local t0 t1; t0="$(date +%s.%N)"
  /usr/bin/env time -f "%U %S" -o "$log.cpu" ./sbt "run simulate --input $input --output $out --engine $engine $*" > "$log" 2>&1 \
    || { echo "bench: simulate failed, see $log" >&2; exit 1; }
  t1="$(date +%s.%N)"
  local wall; wall="$(echo "$t1 - $t0" | bc -l)"
  local read; read="$(sed -n 's/^input: .* in \([0-9.]*\) s$/\1/p' "$log")"
  local rate; rate="$(sed -n 's/^simulation rate: \([0-9]*\) samples\/s.*/\1/p' "$log")"
  local cpurate; cpurate="$(sed -n 's/.*JVM side \([0-9]*\) samples per CPU second.*/\1/p' "$log")"
  local clocks; clocks="$(sed -n 's/.*; \([0-9]*\) clock cycles\/s per harness process.*/\1/p' "$log")"
  local clockscpu; clockscpu="$(sed -n 's/.*clock cycles\/s per harness process (\([0-9]*\) per CPU second).*/\1/p' "$log")"
  local enginerate; enginerate="$(sed -n 's/.*engine [0-9.]* us (\([0-9]*\) samples\/s per job.*/\1/p' "$log")"
  local cpu; cpu="$(awk '{printf "%.0f", $1 + $2}' "$log.cpu")"
  rows+=("$(printf '| %s | %s | %d | %.1f | %.0f | %s | %s | %s | %s | %s | %s | %s | %s |' "$label" "$engine" "$n" "$wall" \
    "$(echo "$n / $wall" | bc -l)" "$read" "$rate" "$cpurate" "${enginerate:--}" "${clocks:--}" "${clockscpu:--}" "$cpu" "$load")")
}

same() { # two result files of one design
  if cmp -s "$1" "$2"; then echo "identical"; else echo "DIFFERENT"; fi
}

for d in "${designs[@]}"; do
  case "$d" in
    joint3)
      bench joint3 rtl "$samples"
      bench joint3 model "$samples"
      echo "joint3: rtl and model files $(same "$work/joint3-rtl.csv" "$work/joint3-model.csv")" ;;
    ur5) bench ur5-ii1 rtl "$ur5_samples" "${ur5[@]}" ;;
    ur5-shared) bench ur5-66blocks rtl "$ur5_samples" "${ur5[@]}" --max-multipliers 66 --clocks-per-sample auto ;;
    ur5-memory) bench ur5-memory-ii64 rtl "$ur5_samples" "${ur5[@]}" --target-error 1e-3 --clocks-per-sample 64 --schedule.storage memory ;;
    *) echo "bench: unknown design '$d' (joint3, ur5, ur5-shared, ur5-memory)" >&2; exit 2 ;;
  esac
done

echo
echo "$(nproc) processors; load average now $(cut -d' ' -f1-3 /proc/loadavg); seed $seed; logs in $work"
echo "$(java -version 2>&1 | head -1); $(verilator --version 2>/dev/null || echo 'no verilator'); commit $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
echo "| design | engine | samples | wall clock s (end to end) | samples/s end to end | CSV read s | replay samples/s (wall) | replay samples per JVM CPU s | engine samples/s per job (model, or harness process with its files) | harness clocks/s per process (wall) | harness clocks per CPU s | CPU s (user+sys, sbt, JVM and harness processes) | load at start |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
printf '%s\n' "${rows[@]}"
