#!/usr/bin/env bash
# sbt launcher for machines with only a JDK (and Maven).
# Uses an installed `sbt` when present; otherwise fetches the pinned sbt-launch artifact
# through Maven's own repository settings, verifies its SHA-256, caches it and runs it.
# Arguments are passed through as sbt commands, e.g. ./sbt test, ./sbt "run --help".
set -euo pipefail

# `./sbt run --help` would run `run` with no arguments (emitting into generated/) before sbt refuses
# `--help`: the application's arguments belong inside the quotes with `run`. Checked first, with bash
# builtins only, so nothing else has run.
previous=""
for arg in "$@"; do
  case "$previous" in
    run | runMain)
      if [ "${arg#-}" != "$arg" ]; then
        echo "sbt: '$arg' after '$previous' is an sbt option, not the application's: quote them together, e.g. ./sbt \"$previous $arg\"" >&2
        exit 2
      fi ;;
  esac
  previous="$arg"
done

# Relative paths on the command line are the caller's: the application resolves them against this
# directory (reducerload.app.Cli.userPath), since sbt runs in the repository.
export REDUCERLOAD_CWD="$PWD"

SBT_LAUNCH_VERSION="1.11.7"
SBT_LAUNCH_SHA256="f92a2095ac75008764fe3b2b793ffe624c4fbef5bfd9b0022e4bc2daf668c651"

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# A directory with its own build.sbt is an sbt project of its own (examples/: `cd examples && ../sbt test`):
# sbt runs there; anywhere else it runs in the repository.
[ -f "$PWD/build.sbt" ] || cd "$here"

# Run without a terminal (CI, no stdin) and with a readable log.
sbt_opts=(-Dsbt.supershell=false -Dsbt.server.forcestart=false -Dsbt.ci="${CI:-false}")
[ -t 1 ] || sbt_opts+=(-Dsbt.log.noformat=true -Dsbt.color=false)
java_opts=(-Xss8m -Xmx4g -XX:+UseParallelGC)

if [ -z "${SBT_FORCE_LAUNCHER:-}" ] && command -v sbt >/dev/null 2>&1 && [ "$(command -v sbt)" != "$here/sbt" ]; then
  exec sbt "${sbt_opts[@]}" "$@"
fi

cache_dir="${XDG_CACHE_HOME:-$HOME/.cache}/reducer-load-sbt"
jar="$cache_dir/sbt-launch-$SBT_LAUNCH_VERSION.jar"

sha_of() { sha256sum "$1" | cut -d' ' -f1; }

if [ ! -f "$jar" ] || [ "$(sha_of "$jar")" != "$SBT_LAUNCH_SHA256" ]; then
  command -v mvn >/dev/null 2>&1 || { echo "sbt: neither sbt nor mvn is installed; install one of them (JDK 11+ is needed too)" >&2; exit 2; }
  mkdir -p "$cache_dir"
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  echo "sbt: fetching org.scala-sbt:sbt-launch:$SBT_LAUNCH_VERSION through Maven" >&2
  mvn -q -B dependency:copy "-Dartifact=org.scala-sbt:sbt-launch:$SBT_LAUNCH_VERSION:jar" \
    "-DoutputDirectory=$tmp" -Dmdep.stripVersion=false </dev/null >&2
  got="$(sha_of "$tmp/sbt-launch-$SBT_LAUNCH_VERSION.jar")"
  if [ "$got" != "$SBT_LAUNCH_SHA256" ]; then
    echo "sbt: SHA-256 mismatch for sbt-launch-$SBT_LAUNCH_VERSION.jar: expected $SBT_LAUNCH_SHA256, got $got" >&2
    exit 2
  fi
  mv "$tmp/sbt-launch-$SBT_LAUNCH_VERSION.jar" "$jar"
fi

if [ "$#" -eq 0 ]; then
  echo "usage: ./sbt <sbt commands>, e.g. ./sbt run, ./sbt test, ./sbt \"run --help\"" >&2
  exit 2
fi
exec java "${java_opts[@]}" "${sbt_opts[@]}" -jar "$jar" "$@" </dev/null
