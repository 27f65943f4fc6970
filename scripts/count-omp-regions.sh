#!/usr/bin/env bash
# count-omp-regions.sh: how many OpenMP parallel regions and barriers does one step of a run enter?
#
# Usage:  scripts/count-omp-regions.sh TSUCHI INPUT [tsuchi run options...]
#         e.g.  scripts/count-omp-regions.sh build/app/tsuchi bench/cases/triaxial_2d.toml
#
# Each region costs a fork and a join, each barrier a wait for the slowest thread; on a host where
# that takes microseconds (`tsuchi-bench --sync` measures it) their number per step sets a floor
# under the time per step that no change to the particle loops moves. This script builds a small
# preload library (with the system's c++, into a temporary folder) that counts the calls tsuchi
# makes into GCC's OpenMP runtime (libgomp): GOMP_parallel (every `omp parallel`, `parallel for`
# with a static schedule included), GOMP_parallel_loop_* and GOMP_parallel_sections (the other
# combined constructs), GOMP_barrier (explicit barriers, the end of a static worksharing loop
# without nowait and of `omp single`) and GOMP_loop_end, GOMP_sections_end and
# GOMP_single_copy_end (the ends of the other worksharing constructs, each a barrier; their
# *_cancel forms too). Reductions and `omp critical` take a lock, not a barrier, and are not
# counted. tsuchi uses only `parallel`, static `parallel for`, `barrier` and `critical` today; the
# others are counted so that a new stage using them is not missed. It runs
# `TSUCHI run INPUT --threads 1 -o TMP --set time.max_steps=N` for
# N = 100 and 200 (on one thread, so a barrier is one call) and prints the difference divided by
# the difference of the steps the two runs made (their summary line): per step, the set-up's
# regions cancelling out. Output is written to a temporary folder, removed at the end. The extra
# options must not set --threads (a barrier would count once per thread).
# Needs a tsuchi built with GCC (libgomp); the counts do not depend on the thread count.
# Exit status: 0 counted; 2 usage error or a failed run or build.
set -euo pipefail

usage() {
  sed -n '4,5p' "$0" | sed 's/^# \{0,1\}//' >&2
  echo "(the header comment of $0 says more)" >&2
}
if [[ $# -ge 1 && ( $1 == -h || $1 == --help ) ]]; then usage; exit 0; fi
if [[ $# -lt 2 ]]; then usage; exit 2; fi
tsuchi=$1 input=$2
shift 2
[[ -x $tsuchi ]] || { echo "count-omp-regions.sh: $tsuchi is not an executable" >&2; exit 2; }
[[ -f $input ]] || { echo "count-omp-regions.sh: no input file $input" >&2; exit 2; }

for a in "$@"; do
  case $a in -j*|--threads|--threads=*) echo "count-omp-regions.sh: do not set --threads: the count is made on one thread" >&2; exit 2;; esac
done
tmp=$(mktemp -d) || { echo "count-omp-regions.sh: cannot make a temporary folder" >&2; exit 2; }
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/count.cpp" <<'EOF'
// Forwards each counted libgomp entry to the real one (the next definition after this library).
#include <dlfcn.h>
#include <atomic>
#include <cstdio>

namespace {
std::atomic<long> regions{0}, barriers{0};
template <class F>
F next(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}
struct Report {
  ~Report() { std::fprintf(stderr, "omp-count: regions %ld barriers %ld\n", regions.load(), barriers.load()); }
} report;
}  // namespace

extern "C" {
void GOMP_parallel(void (*fn)(void*), void* data, unsigned threads, unsigned flags) {
  static const auto real = next<void (*)(void (*)(void*), void*, unsigned, unsigned)>("GOMP_parallel");
  ++regions;
  real(fn, data, threads, flags);
}
#define TSUCHI_COUNT_LOOP(kind)                                                                        \
  void GOMP_parallel_loop_##kind(void (*fn)(void*), void* data, unsigned threads, long start, long end, \
                                 long incr, long chunk, unsigned flags) {                               \
    static const auto real = next<void (*)(void (*)(void*), void*, unsigned, long, long, long, long, unsigned)>( \
        "GOMP_parallel_loop_" #kind);                                                                   \
    ++regions;                                                                                          \
    real(fn, data, threads, start, end, incr, chunk, flags);                                            \
  }
TSUCHI_COUNT_LOOP(static)
TSUCHI_COUNT_LOOP(dynamic)
TSUCHI_COUNT_LOOP(guided)
TSUCHI_COUNT_LOOP(nonmonotonic_dynamic)
TSUCHI_COUNT_LOOP(nonmonotonic_guided)
#define TSUCHI_COUNT_RUNTIME_LOOP(name)                                                                 \
  void name(void (*fn)(void*), void* data, unsigned threads, long start, long end, long incr, unsigned flags) { \
    static const auto real = next<void (*)(void (*)(void*), void*, unsigned, long, long, long, unsigned)>(#name); \
    ++regions;                                                                                          \
    real(fn, data, threads, start, end, incr, flags);                                                   \
  }
TSUCHI_COUNT_RUNTIME_LOOP(GOMP_parallel_loop_runtime)
TSUCHI_COUNT_RUNTIME_LOOP(GOMP_parallel_loop_maybe_nonmonotonic_runtime)
void GOMP_parallel_sections(void (*fn)(void*), void* data, unsigned threads, unsigned count, unsigned flags) {
  static const auto real = next<void (*)(void (*)(void*), void*, unsigned, unsigned, unsigned)>("GOMP_parallel_sections");
  ++regions;
  real(fn, data, threads, count, flags);
}
#define TSUCHI_COUNT_END(name)                               \
  void name() {                                              \
    static const auto real = next<void (*)()>(#name);        \
    ++barriers;                                              \
    real();                                                  \
  }
#define TSUCHI_COUNT_END_CANCEL(name)                        \
  bool name() {                                              \
    static const auto real = next<bool (*)()>(#name);        \
    ++barriers;                                              \
    return real();                                           \
  }
TSUCHI_COUNT_END(GOMP_barrier)
TSUCHI_COUNT_END(GOMP_loop_end)
TSUCHI_COUNT_END(GOMP_sections_end)
TSUCHI_COUNT_END_CANCEL(GOMP_barrier_cancel)
TSUCHI_COUNT_END_CANCEL(GOMP_loop_end_cancel)
TSUCHI_COUNT_END_CANCEL(GOMP_sections_end_cancel)
void GOMP_single_copy_end(void* data) {
  static const auto real = next<void (*)(void*)>("GOMP_single_copy_end");
  ++barriers;
  real(data);
}
}
EOF
c++ -O2 -shared -fPIC -o "$tmp/count.so" "$tmp/count.cpp" -ldl ||
  { echo "count-omp-regions.sh: cannot build the counting library" >&2; exit 2; }

declare -A regions barriers steps
for n in 100 200; do
  log="$tmp/run$n.log"
  if ! LD_PRELOAD="$tmp/count.so" "$tsuchi" run "$input" --threads 1 -o "$tmp/out$n" \
      --set "time.max_steps=$n" "$@" > "$log" 2>&1; then
    echo "count-omp-regions.sh: the run of $n steps failed:" >&2
    cat "$log" >&2
    exit 2
  fi
  line=$(grep '^omp-count:' "$log" || true)
  read -r _ _ "regions[$n]" _ "barriers[$n]" <<< "${line:-x x 0 x 0}"
  if (( regions[$n] == 0 )); then
    echo "count-omp-regions.sh: $tsuchi made no call into libgomp that was counted (not a GCC build?)" >&2
    exit 2
  fi
  # The run's summary: "done: N steps to t = ...".
  steps[$n]=$(sed -n 's/^done: \([0-9]*\) steps.*/\1/p' "$log" | tail -1)
  [[ -n ${steps[$n]} ]] || { echo "count-omp-regions.sh: no summary line (done: N steps) in the run's output:" >&2; cat "$log" >&2; exit 2; }
done
ds=$(( steps[200] - steps[100] ))
if (( ds <= 0 )); then
  echo "count-omp-regions.sh: both runs stopped after ${steps[100]} steps (time.end?): give a longer run with --set" >&2
  exit 2
fi
awk -v r="$(( regions[200] - regions[100] ))" -v b="$(( barriers[200] - barriers[100] ))" -v s="$ds" 'BEGIN {
  printf "per step: %.2f parallel regions, %.2f barriers (over %d steps)\n", r / s, b / s, s }'
