#!/usr/bin/env bash
# A long fuzzing campaign on many cores: independent libFuzzer workers per target, each with its own copy of the
# committed seeds and its own random seed, for SECONDS (docs/RELIABILITY.md, "Today's figures").
#   tools/fuzz_campaign.sh BUILD_DIR SECONDS CHECKPOINT_WORKERS SCENE_WORKERS [OUT_DIR]
# BUILD_DIR holds riffle_fuzz_checkpoint and riffle_fuzz_scene (the fuzz build of tools/fuzz.sh). RUNNER, if set,
# prefixes every command: a machine without Debian 12's libraries runs the binaries with Debian's loader and a
# folder of the libraries `ldd` names, RUNNER="lib/ld-linux-x86-64.so.2 --library-path lib". Prints each worker's
# exit status and the executions per target; exits 1 if a worker failed (its input is in OUT_DIR/NAME/wK/artifacts).
set -uo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 4 ]; then
  sed -n '2,8p' "$0" >&2
  exit 2
fi
build_dir=$(cd "$1" && pwd)
seconds=$2
out=$(mkdir -p "${5:-$build_dir/campaign}" && cd "${5:-$build_dir/campaign}" && pwd)
# shellcheck disable=SC2206
runner=(${RUNNER:-})
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:alloc_dealloc_mismatch=0} UBSAN_OPTIONS=print_stacktrace=1
worker() {  # NAME K
  local dir=$out/$1/w$2 extra=()
  mkdir -p "$dir/corpus" "$dir/artifacts"
  cp tests/fuzz/corpus/"$1"/* "$dir/corpus/"
  [ -f "tests/fuzz/$1.dict" ] && extra=(-dict="tests/fuzz/$1.dict")
  "${runner[@]}" "$build_dir/riffle_fuzz_$1" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -malloc_limit_mb=1024 -print_final_stats=1 -close_fd_mask=1 -seed=$((1000 + $2)) \
    -artifact_prefix="$dir/artifacts/" "${extra[@]}" "$dir/corpus" > "$dir/log.txt" 2>&1
  echo "$1 w$2 exit $?" >> "$out/exits.txt"
}
: > "$out/exits.txt"
for k in $(seq 1 "$3"); do worker checkpoint "$k" & done
for k in $(seq 1 "$4"); do worker scene "$k" & done
wait
cat "$out/exits.txt"
for name in checkpoint scene; do
  cat "$out/$name"/w*/log.txt 2>/dev/null | awk -v name="$name" '
    /^stat::number_of_executed_units/ { runs += $2 } /^stat::peak_rss_mb/ { if ($2 > rss) rss = $2 }
    END { printf "%s: %d executions, peak RSS %d MB\n", name, runs, rss }'
done
! grep -qv "exit 0$" "$out/exits.txt"
