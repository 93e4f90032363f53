#!/usr/bin/env bash
# Runs every benchmark of a Release build and writes their figures, with the machine they
# ran on, to docs/benchmarks-latest.md. docs/benchmarks.md holds the curated figures and
# what they mean against each target; this file is the raw record behind them.
#   bash bench/run.sh [build-dir] [name-filter]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
filter=${2:-}
out=docs/benchmarks-latest.md
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT

cmake --build "$build" -j"$(nproc)" >/dev/null
{
  echo "# Latest benchmark run"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GiB"
  echo "- system: $(. /etc/os-release && echo "$PRETTY_NAME"), $(c++ --version | head -1)"
  echo "- commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo
  for exe in $(find "$build/bench" -type f -name 'bench_*' -perm -u+x | sort); do
    name=$(basename "$exe")
    [[ -n "$filter" && "$name" != *"$filter"* ]] && continue
    echo "## $name"
    echo
    echo '```'
    "$exe" --benchmark_color=false 2>&1 | grep -v '^\*\*\*WARNING\*\*\* Library was built as DEBUG'
    echo '```'
    echo
  done
} > "$tmp"
mv "$tmp" "$out"
echo "wrote $out"
