#!/usr/bin/env bash
# Builds the `fuzz` preset (clang, libFuzzer, ASan + UBSan + float-cast-overflow) and runs every
# fuzz target for a fixed number of executions from its seed corpus (fuzz/corpus/NAME) and its
# regression inputs (fuzz/regressions/NAME). Fails on any crash, sanitizer report, leak, timeout
# or out-of-memory; the failing input is left in build-fuzz/findings/ (add it to
# fuzz/regressions/NAME once fixed: ctest replays that folder in every build).
#
#   scripts/fuzz.sh            the CI budget (see RUNS below; about 8 minutes on 2 cores)
#   scripts/fuzz.sh 10         ten times as many executions per target (0.01: a quick check)
#   FUZZ_TARGETS="text hdf5" scripts/fuzz.sh
set -euo pipefail
cd "$(dirname "$0")/.."
scale="${1:-1}"

# Executions per target at scale 1, from rates measured on the 2-core machine under other builds'
# load (docs/fuzzing.md): about 8-9 minutes of fuzzing plus 3-4 minutes of build, 1,009,000
# executions in all before the wcon target (20,000 more, about 50 s); zarr, backends, history,
# side_files and targets: 70,000 more, about 70 s two at a time. hdf5 is slow by design:
# each input is first read in a forked child (the containment of libhdf5's crashes), about 27
# executions/s under ASan.
declare -A RUNS=(
  [config]=300000
  [text]=90000
  [hdf5]=4000
  [zlib_chunk]=600000
  [manifest]=15000
  [wcon]=20000
  [zarr]=4000
  [backends]=15000
  [history]=6000
  [side_files]=30000
  [targets]=15000
)
# The slowest first (hdf5: a fork per input), so that the two slots end together.
targets="${FUZZ_TARGETS:-hdf5 config text zlib_chunk manifest wcon zarr backends history side_files targets}"

cmake --preset fuzz >/dev/null
# Only the targets that run are built (FUZZ_TARGETS="text" builds one).
build_targets=()
for t in $targets; do build_targets+=(fuzz_"$t"); done
cmake --build --preset fuzz -j2 --target "${build_targets[@]}"

# libhdf5's own leaks on corrupt files are suppressed (each line of the file says why).
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
# A failed huge malloc returns NULL, as glibc's does in production (libhdf5 1.10.8 asks for 128 GB
# for a corrupt metadata cache entry and reports the failure as an error). owval's own code would
# still fail the run: operator new throws std::bad_alloc, which no target catches.
export ASAN_OPTIONS="allocator_may_return_null=1:detect_leaks=1"
findings=build-fuzz/findings
mkdir -p "$findings"
rm -f "$findings"/*.outcome
# One target per core (libFuzzer's own -jobs would split one target's executions instead): two
# at a time on CI's 2 cores, which halves the wall time of the same executions.
fuzz_one() {
  local t=$1 runs scratch dict regressions log start result seconds done_line cov execs
  runs=$(awk -v n="${RUNS[$t]}" -v s="$scale" 'BEGIN { r = int(n * s); print (r < 1 ? 1 : r) }')
  # libFuzzer adds the inputs it finds to the first corpus folder: work on a scratch copy.
  scratch=$(mktemp -d)
  cp fuzz/corpus/"$t"/* "$scratch"/
  dict=()
  [ -f fuzz/dict/"$t".dict ] && dict=(-dict=fuzz/dict/"$t".dict)
  regressions=()  # a target without findings has no folder
  [ -d fuzz/regressions/"$t" ] && regressions=(fuzz/regressions/"$t")
  log="$findings/$t.log"
  start=$(date +%s)
  if build-fuzz/fuzz/fuzz_"$t" -runs="$runs" -seed=1 -timeout=10 -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 "${dict[@]}" -artifact_prefix="$findings/$t-" \
      "$scratch" "${regressions[@]}" >"$log" 2>&1; then
    result=ok
  else
    result=FAILED
  fi
  rm -rf "$scratch"
  seconds=$(( $(date +%s) - start ))
  done_line=$(grep -E '^#[0-9]+\s+DONE' "$log" | tail -1 || true)
  cov=$(sed -n 's/.*cov: \([0-9]*\).*/\1/p' <<<"$done_line")
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  # First line: what the summing below reads; then what is printed.
  {
    echo "${execs:-0} $result"
    echo "fuzz $t: $result, ${execs:-?} executions in ${seconds}s, coverage ${cov:-?} edges"
    if [ "$result" = FAILED ]; then
      grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$log" | head -20 || true
    fi
  } >"$findings/$t.outcome"
}
parallel=${FUZZ_JOBS:-2}
for t in $targets; do
  while [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do
    wait -n || true
  done
  fuzz_one "$t" &
done
wait
# The outcomes in the order given, read from the files each target wrote (a target whose
# outcome is missing died before writing it: that fails the run too).
total=0
status=0
for t in $targets; do
  if [ -f "$findings/$t.outcome" ]; then
    tail -n +2 "$findings/$t.outcome"
    read -r execs result <"$findings/$t.outcome"
    total=$(( total + execs ))
    [ "$result" = ok ] || status=1
  else
    echo "fuzz $t: FAILED, no outcome recorded (see $findings/$t.log)"
    status=1
  fi
  rm -f "$findings/$t.outcome"
done
echo "fuzz: $total executions in all"
exit $status
