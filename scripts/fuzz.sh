#!/usr/bin/env bash
# Usage: scripts/fuzz.sh SECONDS
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz/ and fuzzes each reader for
# SECONDS: the input reader and the checkpoint reader side by side, one core each. Each starts
# from its seeds (the examples' inputs, real checkpoints) and its saved reproducers
# (fuzz/regressions/), and grows a scratch corpus under build-fuzz/fuzz/corpus/. Any crash, leak,
# sanitizer report or slow input fails the script; the input that caused it is saved under
# build-fuzz/fuzz/artifacts/. Prints the executions and coverage of each target.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:?usage: scripts/fuzz.sh SECONDS}
scripts/install-deps.sh
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DTSUCHI_FUZZ=ON -DTSUCHI_BUILD_TESTS=OFF
cmake --build build-fuzz -j"$(nproc)" --target input_reader_fuzz checkpoint_reader_fuzz fuzz_seeds

dir=build-fuzz/fuzz
export OMP_NUM_THREADS=1
# target, kind of seeds, -max_len (the largest seed is ~3 kB of TOML or ~5 kB of checkpoint).
run() {
  local target=$1 kind=$2 max_len=$3
  local corpus=$dir/corpus/$target log=$dir/logs/$target.log
  mkdir -p "$corpus" "$dir/artifacts" "$dir/logs"
  local inputs=("$corpus" "$dir/seeds/$kind")
  if [ -d "fuzz/regressions/$kind" ]; then inputs+=("fuzz/regressions/$kind"); fi
  "$dir/$target" -max_total_time="$seconds" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 \
    -dict="fuzz/$kind.dict" -print_final_stats=1 -artifact_prefix="$dir/artifacts/$target-" \
    "${inputs[@]}" >"$log" 2>&1
}
run input_reader_fuzz input 16384 & input_pid=$!
run checkpoint_reader_fuzz checkpoint 16384 & checkpoint_pid=$!
status=0
wait $input_pid || status=1
wait $checkpoint_pid || status=1

for target in input_reader_fuzz checkpoint_reader_fuzz; do
  log=$dir/logs/$target.log
  if grep -qE "ERROR: (libFuzzer|AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer)|runtime error:|==ERROR" "$log"; then
    status=1
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  last=$(grep -E "^#[0-9]+" "$log" | tail -n 1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([^ ]*\).*/\1/p' <<<"$last")
  echo "$target: ${execs:-?} executions in ${seconds} s, ${rate:-?} exec/s, cov ${cov:-?}, ft ${ft:-?}, corpus ${corp:-?} (log: $log)"
done
if ((status != 0)); then
  echo "fuzzing found a problem: see the logs above and the inputs in $dir/artifacts/" >&2
  for target in input_reader_fuzz checkpoint_reader_fuzz; do
    grep -E -A30 "ERROR:|runtime error:" "$dir/logs/$target.log" | head -n 60 >&2 || true
  done
  exit 1
fi
