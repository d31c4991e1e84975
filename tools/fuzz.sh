#!/usr/bin/env bash
# Runs riffle's libFuzzer targets (tests/fuzz/fuzz_*.cpp; docs/RELIABILITY.md) over their seed corpora.
#   tools/fuzz.sh BUILD_DIR SECONDS [NAME ...]      # NAME: checkpoint, scene, ... (default: every target built)
# BUILD_DIR is a clang build configured with -DRIFFLE_FUZZ=ON (and usually -DRIFFLE_SANITIZE=ON), e.g.
#   BUILD_DIR=build-fuzz CC=clang CXX=clang++ CMAKE_ARGS="-DRIFFLE_FUZZ=ON -DRIFFLE_SANITIZE=ON \
#     -DCMAKE_BUILD_TYPE=RelWithDebInfo" tools/setup.sh
# Each target runs for SECONDS with the committed seeds (tests/fuzz/corpus/NAME) copied into a work corpus
# (BUILD_DIR/fuzz/NAME/corpus, kept between runs so a long campaign can continue), its dictionary
# (tests/fuzz/NAME.dict) if there is one, and the limits: 10 s per input (a hang), 2 GiB resident, 1 GiB per
# allocation. A crash, hang, leak or over-limit allocation leaves its input in BUILD_DIR/fuzz/NAME/artifacts and makes
# this script exit 1. The last line of each target's statistics says how many inputs it ran. The targets run side by
# side, up to FUZZ_JOBS at a time (default: the cores, nproc), each for the full SECONDS; reports come in the order
# named.
# alloc_dealloc_mismatch is off: clang 14 with GCC 12's libstdc++ reports std::stable_sort's temporary buffer
# (operator new(nothrow), then free) as a mismatch, a false positive of that pairing.
set -uo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then
  sed -n '2,11p' "$0" >&2
  exit 2
fi
build_dir=$1
seconds=$2
shift 2
names=("$@")
if [ ${#names[@]} -eq 0 ]; then
  for binary in "$build_dir"/riffle_fuzz_*; do
    [ -x "$binary" ] && names+=("${binary##*/riffle_fuzz_}")
  done
fi
if [ ${#names[@]} -eq 0 ]; then
  echo "fuzz: no riffle_fuzz_* target in $build_dir (configure with -DRIFFLE_FUZZ=ON)" >&2
  exit 2
fi
# One target's run, its report into $work/report.txt and its exit code into $work/code.
fuzz_one() {
  local name=$1 binary=$build_dir/riffle_fuzz_$1 work=$build_dir/fuzz/$1
  mkdir -p "$work/corpus" "$work/artifacts"
  [ -d "tests/fuzz/corpus/$name" ] && cp -n tests/fuzz/corpus/"$name"/* "$work/corpus/" 2>/dev/null
  local options=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 -print_final_stats=1
                 -artifact_prefix="$work/artifacts/" -close_fd_mask=1)
  [ -f "tests/fuzz/$name.dict" ] && options+=(-dict="tests/fuzz/$name.dict")
  {
    echo "fuzz: $name for $seconds s ($(ls "$work/corpus" | wc -l) corpus inputs)"
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:alloc_dealloc_mismatch=0} "$binary" "${options[@]}" "$work/corpus" \
      > "$work/log.txt" 2>&1
    local code=$?
    grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "$work/log.txt" | sed "s/^/fuzz: $name: /"
    if [ $code -ne 0 ]; then
      echo "fuzz: $name FAILED (exit $code); the end of its log ($work/log.txt):"
      tail -n 40 "$work/log.txt"
      ls "$work/artifacts"
    fi
    echo "$code" > "$work/code"
  } > "$work/report.txt"
}
jobs_at_once=${FUZZ_JOBS:-$(nproc)}
running=0
for name in "${names[@]}"; do
  if [ "$running" -ge "$jobs_at_once" ]; then
    wait -n
    running=$((running - 1))
  fi
  rm -f "$build_dir/fuzz/$name/code"
  fuzz_one "$name" &
  running=$((running + 1))
done
wait
status=0
for name in "${names[@]}"; do
  cat "$build_dir/fuzz/$name/report.txt"
  code=$(cat "$build_dir/fuzz/$name/code" 2>/dev/null || echo missing)
  [ "$code" = 0 ] || status=1
done
exit $status
