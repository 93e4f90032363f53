#!/usr/bin/env bash
# What each of the marker tracker's rules does on real faces: `rostro eval photos` on a set of
# photo scenes (by default the 30 held-out ones, which no rule was tuned on) with the rules on
# (the defaults) and then one rule off at a time, two runs at once. Writes the Markdown table
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

# One run: "defaults" or an option assignment; the text table to $work/<index>.
run_one() {
  local index=$1 option=$2
  if [ "$option" = defaults ]; then
    "$rostro" eval photos --file "$scenes" >"$work/$index" 2>/dev/null
  else
    "$rostro" eval photos --file "$scenes" --tracker-option "$option" >"$work/$index" 2>/dev/null
  fi
  echo "rule-effects-photos: $option done" >&2
}
export -f run_one
export rostro scenes work

options=(defaults "${rules[@]}")
for i in "${!options[@]}"; do echo "$i ${options[$i]}"; done |
  xargs -P 2 -L 1 bash -c 'run_one "$0" "$1"'

# The text table's rows: scene median p95 "swaps (events)" astray lost/visible hidden reacquire.
python3 - "$work" "${options[@]}" <<'EOF'
import re, sys
work, options = sys.argv[1], sys.argv[2:]
row = re.compile(r'^(\S+)\s+([\d.]+)\s+([\d.]+)\s+(\d+) \((\d+)\)\s+(\d+)\s+(\d+)/(\d+)\s+(\d+)\s+(\S+)')
def load(i):
    rows = {}
    for line in open(f"{work}/{i}"):
        m = row.match(line)
        if m:
            g = m.groups()
            rows[g[0]] = dict(p95=float(g[2]), swaps=int(g[3]), events=int(g[4]), astray=int(g[5]),
                              lost=int(g[6]), hidden=int(g[8]), reacquire=g[9])
    if not rows:
        sys.exit(f"rule-effects-photos: no table from the run with {options[i]}")
    return rows
def worst_reacquire(rows):
    values = [r['reacquire'] for r in rows.values() if r['reacquire'] != '-']
    if 'never' in values: return 'never'
    return max(values, key=int) if values else '-'
base = load(0)
print("| rule off | swapped (events) | astray | lost | hidden but reported | p95 within 0.3 px | "
      "worst reacquire | p95 moved by 0.02 px or more |")
print("|---|---:|---:|---:|---:|---:|---:|---|")
for i, option in enumerate(options):
    rows = base if i == 0 else load(i)
    total = lambda k: sum(r[k] for r in rows.values())
    moved = [f"{name} {base[name]['p95']:.2f} -> {r['p95']:.2f}" for name, r in rows.items()
             if name in base and abs(r['p95'] - base[name]['p95']) >= 0.02 - 1e-9]
    label = "none (the defaults)" if i == 0 else f"`{option}`"
    print(f"| {label} | {total('swaps')} ({total('events')}) | {total('astray')} | "
          f"{total('lost'):,} | {total('hidden')} | {sum(r['p95'] <= 0.3 for r in rows.values())} "
          f"of {len(rows)} | {worst_reacquire(rows)} | {', '.join(moved) if i else ''} |")
EOF
