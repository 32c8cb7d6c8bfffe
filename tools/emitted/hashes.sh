#!/usr/bin/env bash
# SHA-256 of the SystemVerilog that `run emit` writes for the designs the project promises to keep:
# every preset, planar3, the UR5 and the Panda at one sample per clock and at the shared block-RAM
# schedules of docs/benchmarks.md, and the UR5 with its monitor. A refactoring that must not change
# the hardware compares this table before and after:
#   tools/emitted/hashes.sh > before.txt   (on the old commit)
#   tools/emitted/hashes.sh | diff before.txt -
# One sbt session emits them all (about 10 minutes on 2 cores: the one-sample-per-clock arms are large).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
# The target directory is part of each header's regeneration command, so it is fixed for comparable hashes.
out="${EMITTED_DIR:-target/emitted}"
ur5="--robot golden/robots/ur5_robot.urdf --tip tool0 --max-acceleration 15"
panda="--robot golden/robots/panda.urdf --tip panda_hand --max-acceleration [15,7.5,10,12.5,15,20,20]"
designs=(
  "preset-default|--preset default"
  "preset-paper|--preset paper"
  "preset-compact|--preset compact"
  "preset-shared|--preset shared"
  "preset-smallest|--preset smallest"
  "preset-accurate|--preset accurate"
  "preset-fastest|--preset fastest"
  "preset-arm|--preset arm"
  "sincos|--top sincos"
  "planar3|--robot planar3"
  "planar3-ii3|--robot planar3 --clocks-per-sample 3 --schedule.cordic-units 1"
  "planar3-mem40|--robot planar3 --clocks-per-sample 40 --schedule.storage memory"
  "ur5|$ur5"
  "ur5-auto66|$ur5 --max-multipliers 66 --clocks-per-sample auto"
  "ur5-mem64|$ur5 --target-error 1e-3 --clocks-per-sample 64 --schedule.storage memory"
  "ur5-mem88|$ur5 --target-error 1e-3 --clocks-per-sample 88 --schedule.storage memory"
  "ur5-monitor|$ur5 --target-error 1e-3 --clocks-per-sample 88 --schedule.storage memory --monitor.enabled true"
  "panda|$panda"
  "panda-mem114|$panda --target-error 1e-3 --clocks-per-sample 114 --schedule.storage memory --schedule.adder-units 5"
)
cmds=()
for d in "${designs[@]}"; do
  name="${d%%|*}"; args="${d#*|}"
  cmds+=("run emit $args --target-dir $out/$name")
done
./sbt --error "${cmds[@]}" >&2
for d in "${designs[@]}"; do
  name="${d%%|*}"
  for f in "$out/$name"/*.sv; do
    echo "$(sha256sum "$f" | cut -d' ' -f1)  $name/$(basename "$f")"
  done
done
