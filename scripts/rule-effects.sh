#!/usr/bin/env bash
# What each tracker and solver rule does, measured: the closed loop (`rostro eval loop`) run
# with the rule on (the default) and off, on the scenario the rule was made for, printing per
# rule the FAPs it is about (ceres, RMS as a share of range) and the scenario's worst FAP.
# Writes the Markdown table of docs/rules.md to stdout.
#   bash scripts/rule-effects.sh [build-dir] [rule]   # every rule: about 5 minutes on two cores
set -euo pipefail
cd "$(dirname "$0")/.."
rostro=$(realpath "${1:-build}")/rostro
only=${2:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# rule | options that turn it off | scenario | loop file ("" = 640x480) | FAP names to show |
# the head's vertices ("" = the default head; else `rostro head --vertices N`, a head no rule was
# tuned on, where the rule's case arises)
rules=(
  "brows.edge_fit_mid_brows|--tracker-option brows.edge_fit_mid_brows=false|fear||raise_l_m_eyebrow raise_r_m_eyebrow"
  "edge_fit_elsewhere|--tracker-option edge_fit_elsewhere=false|turns|data/eval/closed_loop_1280x720.json|raise_b_midlip_o lower_t_midlip_o"
  "eyes.inner_corners_raise_share|--tracker-option eyes.inner_corners_raise_share=false|still|data/eval/closed_loop_1280x720.json|close_t_l_eyelid close_t_r_eyelid"
  "eyes.inner_corners_symmetric_centre|--tracker-option eyes.inner_corners_symmetric_centre=false|fear||head_yaw head_pitch"
  "eyes.inner_corner_max_elongation_large|--tracker-option eyes.inner_corner_max_elongation_large=3|turns|data/eval/closed_loop_1280x720.json|close_t_l_eyelid close_t_r_eyelid"
  "lower_lip.together|--tracker-option lower_lip.together=false|joy-turns||raise_b_lip_lm_o raise_b_lip_rm_o"
  "lower_lip.with_the_jaw|--tracker-option lower_lip.with_the_jaw=false|fear||open_jaw raise_b_midlip_o"
  "align_tags|--tracker-option align_tags=false|joy||head_pitch head_yaw"
  "pose_prior_weight|--solver-option pose_prior_weight=0|disgust||head_pitch head_yaw"
  "min_reading_share|--solver-option min_reading_share=0|turns|data/eval/closed_loop_1280x720.json|raise_l_o_eyebrow raise_r_o_eyebrow|20000"
)

# Runs the loop once for a scenario, file, options and head; caches by those.
run() {
  local scenario=$1 file=$2 options=$3 vertices=$4
  local key head=""
  key=$(echo "$scenario|$file|$options|$vertices" | md5sum | cut -c1-12)
  if [ -n "$vertices" ]; then
    head="$work/head$vertices/head.json"
    [ -s "$head" ] || "$rostro" head -o "$work/head$vertices" --vertices "$vertices" >/dev/null
  fi
  if [ ! -s "$work/$key" ]; then
    # shellcheck disable=SC2086
    "$rostro" eval loop --only "$scenario" ${file:+--file "$file"} ${head:+--head "$head"} \
      $options >"$work/$key" 2>/dev/null
  fi
  echo "$work/$key"
}

# The ceres column of a FAP's row: "1.6 (2.7%)" -> "2.7 %".
share() {
  local cell
  cell=$(awk -v fap="$2" '$2 == fap { print; exit }' "$1" | grep -o '([0-9.]*%)' | head -1)
  if [ -n "$cell" ]; then echo "${cell//[()%]/} %"; else echo "not written"; fi
}
worst() {
  awk '$2 == "ceres" && NF > 5 { print $4 " % mean, " $5 " % worst (" $6 ")"; exit }' "$1"
}

echo "| rule | off with | scenario | FAP | on | off | scenario, on | scenario, off |"
echo "|---|---|---|---|---|---|---|---|"
for rule in "${rules[@]}"; do
  IFS='|' read -r name options scenario file faps vertices <<<"$rule"
  [ -z "$only" ] || [ "$name" = "$only" ] || continue
  on=$(run "$scenario" "$file" "" "$vertices")
  off=$(run "$scenario" "$file" "$options" "$vertices")
  label="$scenario${file:+ (1280x720)}${vertices:+, the head at $vertices vertices}"
  first=1
  for fap in $faps; do
    if [ $first = 1 ]; then
      echo "| \`$name\` | \`${options#--* }\` | $label | $fap | $(share "$on" "$fap") | $(share "$off" "$fap") | $(worst "$on") | $(worst "$off") |"
      first=0
    else
      echo "| | | | $fap | $(share "$on" "$fap") | $(share "$off" "$fap") | | |"
    fi
  done
done
