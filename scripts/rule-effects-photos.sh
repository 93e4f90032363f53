#!/usr/bin/env bash
# What each of the marker tracker's rules does on real faces: `rostro eval photos` on a set of
# photo scenes (by default the 30 held-out ones, kept for checking the rules; the hold on a dot
# found again was made there) with the rules on (the defaults) and then one rule off at a time,
# two runs at once. Writes the Markdown table
# of docs/accuracy.md ("The tracker's rules on scenes they were not tuned on") to stdout:
# totals over the set and the scenes whose 95th percentile moved by 0.02 px or more.
#   bash scripts/rule-effects-photos.sh [build-dir] [scene-file]   # about 40 minutes on two cores
set -euo pipefail
cd "$(dirname "$0")/.."
rostro=$(realpath "${1:-build}")/rostro
scenes=${2:-data/eval/photo_scenes_heldout.json}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The option that turns each rule off (docs/rules.md says what each is for).
rules=(
  brows.edge_fit_mid_brows=false
  edge_fit_elsewhere=false
  surround_test_upper_face_only=false
  eyes.inner_corners_raise_share=false
  eyes.inner_corners_symmetric_centre=false
  eyes.inner_corner_max_elongation_large=3
  eyes.max_dot_growth_found=2
  eyes.eye_size_memory_frames=0
  eyes.max_lid_elongation=100
  lower_lip.together=false
  lower_lip.with_the_jaw=false
  identification.lower_lip_apart=false
  identification.dots_beside_points=false
  min_recent_size=0
  swap_back_pairs=false
  hold_found_after_lost=0
)

# One run: "defaults" or an option assignment; its rows (eval photos --report) to
# $work/<index>.json. A run that fails stops the script with its last line of output.
run_one() {
  local index=$1 option=$2 args=()
  [ "$option" = defaults ] || args=(--tracker-option "$option")
  if ! "$rostro" eval photos --file "$scenes" "${args[@]}" --report "$work/$index.json" \
    >"$work/$index.log" 2>&1; then
    echo "rule-effects-photos: the run with $option failed: $(tail -n 1 "$work/$index.log")" >&2
    return 255  # xargs stops at once
  fi
  echo "rule-effects-photos: $option done" >&2
}
export -f run_one
export rostro scenes work

options=(defaults "${rules[@]}")
for i in "${!options[@]}"; do echo "$i ${options[$i]}"; done |
  xargs -P 2 -L 1 bash -c 'run_one "$0" "$1"'

# The rows of each run (eval/report.hpp, photo_report_json).
python3 - "$work" "${options[@]}" <<'EOF'
import json, sys
work, options = sys.argv[1], sys.argv[2:]
def load(i):
    with open(f"{work}/{i}.json") as f:
        return {r['name']: r for r in json.load(f)['rows']}
def worst_reacquire(rows):
    occluded = [r for r in rows.values() if r['occlusions'] > 0]
    if not occluded: return '-'
    if any(r['worst_reacquire'] is None for r in occluded): return 'never'
    return str(max(r['worst_reacquire'] for r in occluded))
def p95(r):  # nothing scored counts as missing the aim
    return r['p95_px'] if r['p95_px'] is not None else float('inf')
base = load(0)
print("| rule off | swapped (events) | astray | lost | hidden but reported | p95 within 0.3 px | "
      "worst reacquire | p95 moved by 0.02 px or more |")
print("|---|---:|---:|---:|---:|---:|---:|---|")
for i, option in enumerate(options):
    rows = base if i == 0 else load(i)
    total = lambda k: sum(r[k] for r in rows.values())
    moved = [f"{name} {p95(base[name]):.2f} -> {p95(r):.2f}" for name, r in rows.items()
             if name in base and abs(p95(r) - p95(base[name])) >= 0.02 - 1e-9]
    label = "none (the defaults)" if i == 0 else f"`{option}`"
    print(f"| {label} | {total('swapped')} ({total('swap_events')}) | {total('astray')} | "
          f"{total('lost'):,} | {total('hidden_reported')} | "
          f"{sum(p95(r) <= 0.3 for r in rows.values())} of {len(rows)} | "
          f"{worst_reacquire(rows)} | {', '.join(moved) if i else ''} |")
EOF
