#!/usr/bin/env bash
# compare-outputs.sh: do the working tree's results match those of a git revision, byte for byte?
#
# Usage:  scripts/compare-outputs.sh REV        e.g.  scripts/compare-outputs.sh HEAD
#         scripts/compare-outputs.sh --help
#
# Builds two tsuchi binaries (Release, only the `tsuchi` target, tests off):
#   base  the commit REV resolves to: its tree is exported with `git archive` into
#         build-compare/rev-<commit>/src and built in build-compare/rev-<commit>/build. Both are
#         kept, so a second comparison against the same commit only re-runs `make` (nothing to do).
#         Nothing in .git is touched (no worktree, no branch). `rm -rf build-compare` reclaims it.
#   work  the working tree as it is now (uncommitted changes included), built in
#         build-compare/work (never in build/).
# Then runs every case below with each binary (`--threads 1`; both binaries read the same input
# files, those of the working tree, so only the code differs) into
# build-compare/out/base/CASE and build-compare/out/work/CASE, and compares every file of the two
# folders byte for byte. For each case it prints "identical", or for each differing file its first
# difference: for a text file the line number and that line of both; for a binary file (one with a
# NUL byte: .vtu frames, checkpoints) the offset of the first differing byte. A file present on one
# side only, or a different exit status of tsuchi, is a difference too.
#
# Cases (each run takes seconds; with warm builds a full comparison takes about 2.5 minutes of CPU,
# 3 minutes of wall time on a busy 2-core machine, mostly the six triaxial cases):
#   triaxial/test{1,2,3}_{fixed,free}   examples/triaxial/*.toml to 3 % axial strain:
#                                       --set recorders.0.stop_above=0.03 --set time.end=0.2
#   DIR/NAME (every other examples/*/*.toml that is a `tsuchi run` input, i.e. has no [test] table:
#                                       bar_vibration/bar, column_self_weight/column, column_3d,
#                                       simple_shear/simple_shear): the whole example, as is
#   element_tests/NAME                  every examples/*/*.toml with a [test] table, through
#                                       `tsuchi element FILE -o CASE/NAME.csv`
#   bar_vibration/bar+checkpoint        the bar with --set checkpoint.every_steps=500 (each
#                                       checkpoint replaces the last; the final checkpoint.tsuchi
#                                       is compared)
#   column_self_weight/column_3d+checkpoint   the 3D column with --set checkpoint.every_steps=200
#   bar_vibration/bar+restart           the bar to t = 0.1 s with checkpoint.every_steps=500, then
#                                       `--restart CASE/checkpoint.tsuchi --set time.end=0.2`
#
# What is NOT compared, explicitly: the console output of tsuchi (its standard output and error,
# kept in build-compare/out/{base,work}/CASE.log), because it holds wall-clock figures (steps/s,
# particle-steps/s, elapsed time, ETA). Every file tsuchi writes is compared unfiltered; the frames'
# header holds the program version (`tsuchi --version`), so if the two versions differ the script
# says so first and those files will differ.
#
# Exit status: 0 every case identical; 1 some difference; 2 usage error, unknown revision, failed
# build or any other failure of the script itself.
# Environment: COMPARE_JOBS  parallel build jobs (default 1).
set -euo pipefail
set -o errtrace
trap 'echo "compare-outputs.sh: unexpected failure at line $LINENO" >&2; exit 2' ERR

usage() {
  sed -n '4,5p' "$0" | sed 's/^# \{0,1\}//' >&2
  echo "(the header comment of $0 says more)" >&2
}
die() { echo "compare-outputs.sh: $*" >&2; exit 2; }

if [[ $# -eq 1 && ( $1 == -h || $1 == --help ) ]]; then usage; exit 0; fi
if [[ $# -ne 1 || -z $1 || $1 == -* ]]; then usage; exit 2; fi
rev=$1

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
commit=$(git rev-parse --verify --quiet "${rev}^{commit}") || die "'$rev' is not a commit of this repository"
jobs=${COMPARE_JOBS:-1}
[[ $jobs =~ ^[1-9][0-9]*$ ]] || die "COMPARE_JOBS must be a positive integer, not '$jobs'"

top=$root/build-compare
mkdir -p "$top"
started=$SECONDS

# build NAME SOURCE_DIR BUILD_DIR: a Release build of the tsuchi target; the log in BUILD_DIR.log.
build() {
  local name=$1 src=$2 dir=$3 log=$3.log
  echo "building $name ($dir) ..."
  : > "$log"
  if [[ ! -f $dir/CMakeCache.txt ]]; then
    cmake -S "$src" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DTSUCHI_BUILD_TESTS=OFF >> "$log" 2>&1 ||
      { tail -n 30 "$log" >&2; die "configuring $name failed (log: $log)"; }
  fi
  cmake --build "$dir" --target tsuchi -j"$jobs" >> "$log" 2>&1 ||
    { tail -n 30 "$log" >&2; die "building $name failed (log: $log)"; }
  [[ -x $dir/app/tsuchi ]] || die "building $name gave no $dir/app/tsuchi"
}

# The base: exported once per commit (a re-export would touch every file and force a rebuild).
base_dir=$top/rev-$commit
if [[ ! -f $base_dir/src/.exported ]]; then
  rm -rf "$base_dir/src" "$base_dir/src.tmp"
  mkdir -p "$base_dir/src.tmp"
  git archive --format=tar "$commit" | tar -x -C "$base_dir/src.tmp" || die "git archive of $commit failed"
  echo "$commit" > "$base_dir/src.tmp/.exported"
  mv "$base_dir/src.tmp" "$base_dir/src"
fi
build "base ($rev = ${commit:0:12})" "$base_dir/src" "$base_dir/build"
build "working tree" "$root" "$top/work"
declare -A bin=([base]=$base_dir/build/app/tsuchi [work]=$top/work/app/tsuchi)

version_base=$("${bin[base]}" --version 2>/dev/null || echo "(a build without --version)")
version_work=$("${bin[work]}" --version 2>/dev/null || echo "(a build without --version)")
echo "base: $version_base (commit $commit)"
echo "work: $version_work (working tree)"
if [[ $version_base != "$version_work" ]]; then
  echo "note: the version strings differ; files whose header holds the version (frames) will differ (nothing is filtered)"
fi

# The cases: "NAME|KIND|INPUT|ARGS" (ARGS: words without blanks). KIND: run, element, restart.
cases=()
for f in examples/*/*.toml; do
  dir=$(basename "$(dirname "$f")")
  name=$(basename "$f" .toml)
  if [[ $dir == triaxial && $name =~ ^test[123]_(fixed|free)$ ]]; then
    cases+=("$dir/$name|run|$f|--set recorders.0.stop_above=0.03 --set time.end=0.2")
  elif grep -q '^[[:space:]]*\[test\][[:space:]]*\(#.*\)\{0,1\}$' "$f"; then
    cases+=("$dir/$name|element|$f|")
  else
    cases+=("$dir/$name|run|$f|")
  fi
done
[[ -f examples/bar_vibration/bar.toml ]] || die "examples/bar_vibration/bar.toml is missing (the checkpoint cases use it)"
[[ -f examples/column_self_weight/column_3d.toml ]] || die "examples/column_self_weight/column_3d.toml is missing"
cases+=("bar_vibration/bar+checkpoint|run|examples/bar_vibration/bar.toml|--set checkpoint.every_steps=500")
cases+=("column_self_weight/column_3d+checkpoint|run|examples/column_self_weight/column_3d.toml|--set checkpoint.every_steps=200")
cases+=("bar_vibration/bar+restart|restart|examples/bar_vibration/bar.toml|")

# run_case SIDE NAME KIND INPUT ARGS: runs in build-compare/out/SIDE with relative output paths,
# so that no path that differs between the sides reaches tsuchi. Writes CASE.log and CASE.rc.
run_case() {
  local side=$1 name=$2 kind=$3 input=$root/$4 rc=0
  local -a args=()
  [[ -n $5 ]] && read -r -a args <<< "$5"
  local tsuchi=${bin[$side]}
  mkdir -p "$(dirname "$top/out/$side/$name")"
  (
    cd "$top/out/$side"
    case $kind in
      run) "$tsuchi" run "$input" -o "$name" --threads 1 "${args[@]}" ;;
      element) mkdir -p "$name" && "$tsuchi" element "$input" -o "$name/$(basename "$input" .toml).csv" "${args[@]}" ;;
      restart)
        "$tsuchi" run "$input" -o "$name" --threads 1 --set time.end=0.1 --set checkpoint.every_steps=500 &&
          "$tsuchi" run "$input" -o "$name" --threads 1 --restart "$name/checkpoint.tsuchi" \
            --set time.end=0.2 --set checkpoint.every_steps=500 ;;
    esac
  ) > "$top/out/$side/$name.log" 2>&1 || rc=$?
  echo "$rc" > "$top/out/$side/$name.rc"
}

clip() { local s=$1; (( ${#s} > 200 )) && s="${s:0:200}..."; printf '%s' "$s"; }
is_text() { [[ ! -s $1 ]] || LC_ALL=C grep -qI '' "$1"; }

# first_difference B W REL: describes where the two (differing) files part.
first_difference() {
  local b=$1 w=$2 rel=$3 out byte line sb sw
  out=$(LC_ALL=C cmp -- "$b" "$w" 2>&1 || true)
  sb=$(wc -c < "$b"); sw=$(wc -c < "$w")
  if is_text "$b" && is_text "$w"; then
    if [[ $out =~ differ:\ (byte|char)\ ([0-9]+),\ line\ ([0-9]+) ]]; then
      line=${BASH_REMATCH[3]}
      echo "  $rel: text, first difference at line $line:"
      echo "    base: $(clip "$(sed -n "${line}p" "$b")")"
      echo "    work: $(clip "$(sed -n "${line}p" "$w")")"
    else  # one is a prefix of the other
      local nb nw
      nb=$(wc -l < "$b"); nw=$(wc -l < "$w")
      if (( sb < sw )); then
        echo "  $rel: text, base ends after line $nb ($sb bytes); work goes on:"
        echo "    work: $(clip "$(sed -n "$((nb + 1))p" "$w")")"
      else
        echo "  $rel: text, work ends after line $nw ($sw bytes); base goes on:"
        echo "    base: $(clip "$(sed -n "$((nw + 1))p" "$b")")"
      fi
    fi
  else
    if [[ $out =~ differ:\ (byte|char)\ ([0-9]+) ]]; then
      byte=${BASH_REMATCH[2]}
      echo "  $rel: binary, first differing byte at offset $((byte - 1)) (sizes: base $sb, work $sw bytes)"
    else
      echo "  $rel: binary, identical up to the end of the shorter one (sizes: base $sb, work $sw bytes)"
    fi
  fi
}

# compare_case NAME: prints the verdict; returns 1 if the case differs.
compare_case() {
  local name=$1 b=$top/out/base/$1 w=$top/out/work/$1 rc_b rc_w rel differ=0
  local -a lines=()
  rc_b=$(< "$top/out/base/$name.rc"); rc_w=$(< "$top/out/work/$name.rc")
  if [[ $rc_b != "$rc_w" ]]; then
    lines+=("  exit status: base $rc_b, work $rc_w (logs: out/{base,work}/$name.log)")
  fi
  local list_b list_w
  list_b=$( [[ -d $b ]] && cd "$b" && find . -type f | sed 's|^\./||' | LC_ALL=C sort || true)
  list_w=$( [[ -d $w ]] && cd "$w" && find . -type f | sed 's|^\./||' | LC_ALL=C sort || true)
  while IFS= read -r rel; do
    [[ -n $rel ]] && lines+=("  $rel: only in base")
  done < <(LC_ALL=C comm -23 <(printf '%s\n' "$list_b") <(printf '%s\n' "$list_w"))
  while IFS= read -r rel; do
    [[ -n $rel ]] && lines+=("  $rel: only in work")
  done < <(LC_ALL=C comm -13 <(printf '%s\n' "$list_b") <(printf '%s\n' "$list_w"))
  local nfiles=0
  while IFS= read -r rel; do
    [[ -n $rel ]] || continue
    nfiles=$((nfiles + 1))
    if ! cmp -s -- "$b/$rel" "$w/$rel"; then
      differ=$((differ + 1))
      if (( differ <= 5 )); then
        local d
        d=$(first_difference "$b/$rel" "$w/$rel" "$rel")
        lines+=("$d")
      fi
    fi
  done < <(LC_ALL=C comm -12 <(printf '%s\n' "$list_b") <(printf '%s\n' "$list_w"))
  (( differ > 5 )) && lines+=("  ... $((differ - 5)) more differing files")
  if (( ${#lines[@]} == 0 )); then
    local note=""
    [[ $rc_b != 0 ]] && note=", both exit $rc_b"
    printf '%-44s identical (%d files%s)\n' "$name" "$nfiles" "$note"
    return 0
  fi
  printf '%-44s DIFFERENT (%d of %d common files differ)\n' "$name" "$differ" "$nfiles"
  printf '%s\n' "${lines[@]}"
  return 1
}

rm -rf "$top/out"
mkdir -p "$top/out/base" "$top/out/work"
echo "running ${#cases[@]} cases with each binary; outputs in build-compare/out/{base,work}/CASE"
status=0
for spec in "${cases[@]}"; do
  IFS='|' read -r name kind input args <<< "$spec"
  run_case base "$name" "$kind" "$input" "$args"
  run_case work "$name" "$kind" "$input" "$args"
  compare_case "$name" || status=1
done

elapsed=$((SECONDS - started))
if (( status == 0 )); then
  echo "all ${#cases[@]} cases identical (${elapsed} s)"
else
  echo "differences found (${elapsed} s); outputs kept in build-compare/out/{base,work}"
fi
exit "$status"
