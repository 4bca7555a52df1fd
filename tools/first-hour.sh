#!/usr/bin/env bash
# The first hour, measured: a fresh clone of this repository's HEAD, then the README's two
# commands (the main job, then the test command), each timed by wall clock, and the ratio
# of the second to the first. Prints one line a measurement and the machine it ran on, for
# README's set-up section. Rerun it on an idle machine; a loaded one (another build beside
# it) gives larger and noisier numbers, so the load average is printed too.
#
#   tools/first-hour.sh [RUNS]     RUNS fresh clones in turn (default 1); times of each
#
# It builds in a temporary folder (several GB with the target directory) and removes it.
set -euo pipefail
runs=${1:-1}
repo=$(git -C "$(dirname "$0")/.." rev-parse --show-toplevel)
commit=$(git -C "$repo" rev-parse --short HEAD)
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
echo "machine: $(nproc) cores, ${cpu:-unknown CPU}, $(free -g | awk '/Mem:/{print $2}') GiB; commit $commit"
for run in $(seq "$runs"); do
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  git clone -q "$repo" "$work/coil"
  cd "$work/coil"
  load0=$(cut -d' ' -f1 /proc/loadavg)
  t0=$(date +%s.%N)
  cargo run --release -p coil-tune -- paper --out out/paper > "$work/main.log" 2>&1 ||
    { tail -30 "$work/main.log"; echo "the main job failed"; exit 1; }
  t1=$(date +%s.%N)
  cargo test --release --workspace --locked > "$work/test.log" 2>&1 ||
    { grep -E 'FAILED|panicked' "$work/test.log" | head -30; echo "the test command failed"; exit 1; }
  t2=$(date +%s.%N)
  load1=$(cut -d' ' -f1 /proc/loadavg)
  main=$(awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}')
  tests=$(awk -v a="$t1" -v b="$t2" 'BEGIN {print b - a}')
  passed=$(grep -Eo '[0-9]+ passed' "$work/test.log" | awk '{s+=$1} END {print s}')
  binaries=$(grep -c '^     Running ' "$work/test.log" || true)
  printf 'run %d: main job %.0f s, test command %.0f s (%s tests passed in %s test binaries), ratio %.2f, load average %s -> %s\n' \
    "$run" "$main" "$tests" "$passed" "$binaries" "$(awk -v a="$main" -v b="$tests" 'BEGIN {print b / a}')" "$load0" "$load1"
  cd "$repo"
  rm -rf "$work"
  trap - EXIT
done
