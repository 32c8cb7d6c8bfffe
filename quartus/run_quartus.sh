#!/usr/bin/env bash
# Compile an emitted design with Quartus for EP4CE30F29C6 and run timing analysis.
# usage: quartus/run_quartus.sh [--sv FILE] [--top MODULE]
# default: ../generated/reducer_load.sv (emit it first with ./sbt "run emit")
# Needs Quartus (quartus_sh on the PATH); nothing else in the project does.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
sv="$here/../generated/reducer_load.sv"
top=""
while [ $# -gt 0 ]; do
  case "$1" in
    --sv) sv="$2"; shift 2 ;;
    --top) top="$2"; shift 2 ;;
    -h|--help) sed -n '2,5p' "$0"; exit 0 ;;
    *) echo "run_quartus.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
command -v quartus_sh >/dev/null 2>&1 || { echo "run_quartus.sh: quartus_sh is not on the PATH (install Quartus Prime Lite with Cyclone IV support)" >&2; exit 2; }
[ -f "$sv" ] || { echo "run_quartus.sh: $sv does not exist; emit it first: ./sbt \"run emit\"" >&2; exit 2; }
sv="$(cd "$(dirname "$sv")" && pwd)/$(basename "$sv")"
[ -n "$top" ] || top="$(basename "$sv" .sv)"
cd "$here"
quartus_sh -t compile.tcl "$top" "$sv"
quartus_sta reducer_load -c reducer_load --do_report_timing
echo "fit summary:    $here/output_files/reducer_load.fit.summary"
echo "timing summary: $here/output_files/reducer_load.sta.summary"
