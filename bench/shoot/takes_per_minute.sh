#!/usr/bin/env bash
# Takes per minute of a whole shoot (`rostro shoot`, workflow/) at -j 1 and -j 2 on this
# machine, and the per-take cost behind docs/shoot.md's "Scale on paper".
#   bash bench/shoot/takes_per_minute.sh [build-dir] [work-dir]
# Renders six synthetic marker takes of one actor at 640x480, 25 fps (two each of 2, 4 and
# 6 s, so a line through capture time against frames separates the per-frame cost from the
# fixed cost of a take), then runs the shoot from scratch four times: -j 1; -j 1 held to one
# core; -j 2 (two takes at once, one thread each); -j 2 with take_threads=2 (one take at a
# time; rostro capture itself pipelines tracking and fit on two threads when it can).
# Prints a Markdown table; run it when nothing else is building (it says the load average).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=$(realpath "${1:-build}")
work=$(realpath -m "${2:-/tmp/rostro-shoot-bench}")
rostro="$build/rostro"
command -v snakemake >/dev/null || { echo "snakemake not installed (apt-get install snakemake)"; exit 1; }
rm -rf "$work"
mkdir -p "$work/clips"

"$rostro" synth -o "$work/clips/neutral" --neutral-lead 1 --seconds 1 >/dev/null
{
  echo "take,actor,source,layout,camera,neutral,options"
  seed=10
  for len in 2 4 6; do
    for n in 1 2; do
      seed=$((seed + 1))
      "$rostro" synth -o "$work/clips/t${len}s$n" --neutral-lead 0.3 --seconds "$len" \
        --seed $seed --head-yaw 10 >/dev/null
      echo "t${len}s$n,bench,clips/t${len}s$n.mp4,$PWD/data/layouts/default.json,clips/neutral.intrinsics.yml,clips/neutral.mp4,"
    done
  done
} >"$work/shoot.csv"

echo "# Shoot benchmark"
echo
echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'); commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo "- machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(snakemake --version | sed 's/^/snakemake /')"
echo "- load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "- six takes of one actor (2, 4, 6 s x 2; 640x480, 25 fps, markers, preview on), one calibration"
echo
echo "| run | wall s | takes/min | frames/s | load after |"
echo "|---|---:|---:|---:|---|"
# "pin": the -j 1 shoot held to one core (taskset), the per-take cost a one-CPU slot pays.
for run in "1 1 -" "1 1 pin" "2 1 -" "2 2 -"; do
  set -- $run
  out="$work/out-j$1-t$2-$3"
  pin=()
  [[ $3 == pin ]] && pin=(taskset -c 1)
  start=$(date +%s.%N)
  "${pin[@]}" "$rostro" shoot "$work/shoot.csv" -j "$1" -o "$out" --config "take_threads=$2" \
    >"$out.log" 2>&1 || { echo "shoot failed: $out.log"; exit 1; }
  end=$(date +%s.%N)
  frames=$(python3 -c "import json,glob; print(sum(json.load(open(f))['frames'] for f in glob.glob('$out/takes/*/*.checks.json')))")
  label="-j $1, take_threads=$2"
  [[ $3 == pin ]] && label="$label, one core (taskset -c 1)"
  python3 -c "w=$end-$start; print(f'| $label | {w:.1f} | {6*60/w:.1f} | {$frames/w:.1f} | $(cut -d' ' -f1 /proc/loadavg) |')"
done
echo
# Per-take cost from the one-core run: capture seconds = fixed + per-frame x frames, least
# squares over the six takes.
python3 - "$work/out-j1-t1-pin" <<'PY'
import glob, json, sys
rows = [json.load(open(f)) for f in sorted(glob.glob(sys.argv[1] + "/takes/*/*.checks.json"))]
n = len(rows)
x = [r["frames"] for r in rows]; y = [r["capture_s"] for r in rows]
mx, my = sum(x) / n, sum(y) / n
slope = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
fixed = my - slope * mx
cpu = sum(r["cpu_s"] for r in rows) / sum(y)
rss = max(r["max_rss_mb"] for r in rows)
size = sum(r["duration_s"] for r in rows)
print(f"Per take on one core: {1000 * slope:.1f} ms per frame + {fixed:.2f} s fixed "
      f"(start-up, calibration load, preview set-up); CPU/wall {cpu:.2f}; "
      f"peak memory {rss:.0f} MB.")
PY
du -sk "$work/out-j1-t1--/takes" | awk '{printf "Outputs: %.1f MB for the six takes ", $1/1024}'
du -sk "$work/clips" | awk '{printf "(sources %.1f MB).\n", $1/1024}'
