#!/usr/bin/env bash
# Writes the seeds of the checkpoint fuzzer (tests/fuzz/fuzz_checkpoint.cpp) into tests/fuzz/corpus/checkpoint: runs
# every scene of tests/fuzz/checkpoint_scenes for a few steps and keeps its final checkpoint, and, for scenes that
# write interval checkpoints, the first of them too (a state in the middle of a run). The scenes are small so that
# every fuzz input stays fast; the files are a few hundred KB at most. The found_*.ckpt beside them are inputs the
# fuzzer found (kept as regression seeds: each crashed an earlier build), and the v4_* to v14_*.ckpt are seeds as
# riffle wrote them in checkpoint formats 4 to 14 (compatibility fixtures: all must still load); this script leaves them alone.
#
# Usage, from the repository root:  tests/fuzz/make_checkpoint_corpus.sh build/riffle
set -euo pipefail
riffle=${1:?usage: $0 path/to/riffle}
out=tests/fuzz/corpus/checkpoint
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
for scene in tests/fuzz/checkpoint_scenes/*.toml; do
  name=$(basename "$scene" .toml)
  # The scene's path is stored in the checkpoint as given: relative, so that the seeds do not name this machine.
  "$riffle" run "$scene" --out "$work/$name" --threads 1 --log-level warn
  cp "$work/$name/checkpoints/final.ckpt" "$out/$name.ckpt"
  first=$(find "$work/$name/checkpoints" -name 'step_*.ckpt' | sort | head -n 1)
  if [ -n "$first" ] && ! cmp -s "$first" "$out/$name.ckpt"; then cp "$first" "$out/${name}_early.ckpt"; fi
done
ls -l "$out"
