#!/usr/bin/env bash
# The fuzz tests' runner (tests/fuzz/CMakeLists.txt, docs/FUZZING.md).
#   run_fuzz.sh corpus BINARY CORPUS_DIR
#       every committed input once: the regression test (libFuzzer binary or replay driver)
#   run_fuzz.sh fuzz BINARY CORPUS_DIR SECONDS SCRATCH_DIR
#       libFuzzer for SECONDS on a copy of the corpus in SCRATCH_DIR, where new inputs and any
#       crash land (never in the repository); prints the executions and what was found.
# libFuzzer's own limits make a hang or a memory blow-up a failure too: -timeout (seconds per
# input) and -rss_limit_mb (which also caps a single allocation).
set -euo pipefail
mode=$1 bin=$2 corpus=$3
case "$mode" in
  corpus)
    # File names, not the directory: libFuzzer then runs each file exactly once, whole.
    find "$corpus" -type f -print0 | sort -z | xargs -0 "$bin"
    echo "corpus: $(find "$corpus" -type f | wc -l) inputs, no failure"
    ;;
  fuzz)
    seconds=$4 scratch=$5
    rm -rf "$scratch"
    mkdir -p "$scratch/corpus" "$scratch/artifacts"
    cp "$corpus"/* "$scratch/corpus/"
    before=$(find "$scratch/corpus" -type f | wc -l)
    rc=0
    "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$scratch/artifacts/" "$scratch/corpus" >"$scratch/log" 2>&1 || rc=$?
    if [ "$rc" -ne 0 ]; then
      tail -n 60 "$scratch/log"
      echo "FAILED: the input that failed is in $scratch/artifacts/"
      exit 1
    fi
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$scratch/log")
    after=$(find "$scratch/corpus" -type f | wc -l)
    grep -E '^(#[0-9]+ +DONE|Done)' "$scratch/log" || true
    echo "$(basename "$bin"): $runs executions in ${seconds} s, no failure; corpus $before -> $after inputs"
    ;;
  *)
    echo "usage: run_fuzz.sh corpus BINARY DIR | fuzz BINARY DIR SECONDS SCRATCH" >&2
    exit 2
    ;;
esac
