#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build for SECONDS each (default 5), starting from the seed
# corpus tests/fuzz/corpus/<target> and the regression inputs tests/data/fuzz-regressions/<target>;
# new inputs and crash artifacts go to a scratch folder.
#   bash tests/fuzz/run.sh BUILD_DIR [SECONDS]
# Prints one line per target (executions, corpus size, crashes); exits 1 when any target crashed,
# leaving the crashing input beside its name in the scratch folder (make it a regression input:
# tests/data/fuzz-regressions/<target>/).
set -uo pipefail
build=${1:?usage: run.sh BUILD_DIR [SECONDS]}
seconds=${2:-5}
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work=$(mktemp -d "${TMPDIR:-/tmp}/cutwork-fuzz-run.XXXXXX")
status=0
for target in scene stencils_json mesh_obj mesh_ply mesh_off mesh_stl; do
  exe="$build/bin/cutwork_fuzz_$target"
  mkdir -p "$work/$target"
  log="$work/$target.log"
  seeds=("$here/corpus/$target")
  regressions="$here/../data/fuzz-regressions/$target"
  [ -d "$regressions" ] && seeds+=("$regressions")
  "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$work/$target-" "$work/$target" "${seeds[@]}" >"$log" 2>&1
  rc=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$')
  units=$(ls "$work/$target" | wc -l)
  crashes=$(ls "$work" | grep -c "^$target-" || true)
  echo "fuzz $target: ${runs:-0} executions in ${seconds} s, ${units} new corpus inputs, ${crashes} crashes (exit ${rc})"
  if [ "$rc" -ne 0 ]; then
    status=1
    grep -m 3 -E 'ERROR|SUMMARY|Test unit written' "$log" || tail -n 5 "$log"
  fi
done
[ "$status" -eq 0 ] && rm -rf "$work" || echo "fuzz: findings kept in $work"
exit "$status"
