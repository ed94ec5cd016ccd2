#!/usr/bin/env bash
# Runs every fuzz target of tests/fuzz with the given libFuzzer options (e.g.
# -max_total_time=600 or -runs=10000000), each from its committed seed corpus
# with new inputs in a scratch directory, and prints one line per target:
# executions, time, coverage (edges and features), and the corpus size.
# usage: tests/fuzz/run_fuzzers.sh BUILD_DIR [libFuzzer options...]
#   FUZZ_TARGETS="fuzz_frame_decoder fuzz_service_raw" to run only some.
#   With -fork=N (libFuzzer's fork mode: N worker processes, one corpus) the
#   executions and the time are those of the whole run, all workers together.
set -u
build=${1:?usage: run_fuzzers.sh BUILD_DIR [options]}
shift
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
targets=${FUZZ_TARGETS:-"fuzz_frame_decoder fuzz_service_raw fuzz_service_framed fuzz_scene_json fuzz_commonroad fuzz_qp_text"}
status=0
for t in $targets; do
  # The longest input worth trying: two largest frames on the line; a few
  # frames to the service; a largest Scene with room around it for the rest.
  case $t in
    fuzz_frame_decoder) max_len=2200 ;;
    fuzz_service_raw) max_len=4096 ;;
    *) max_len=16384 ;;
  esac
  case $t in
    fuzz_scene_json) seeds=("$here/corpus/scene_json" "$root/tests/scene/data") ;;
    fuzz_qp_text) seeds=("$root/tests/qp/data") ;;
    *) seeds=("$here/corpus/${t#fuzz_}") ;;
  esac
  scratch="$build/scratch/$t"
  mkdir -p "$scratch"
  log="$build/$t.log"
  "$build/$t" -max_len=$max_len -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 "$@" "$scratch" "${seeds[@]}" > "$log" 2>&1
  rc=$?
  if grep -q '^INFO: -fork=' "$log"; then
    # Fork mode: the parent's own lines (its final stats count none of the
    # workers' executions, and are 0 when it is interrupted).
    execs=$(sed -n 's/^INFO: fuzzed for \([0-9]*\) iterations.*/\1/p' "$log" | tail -1)
    [ -n "$execs" ] || execs=$(grep -E '^#[0-9]+: cov:' "$log" | tail -1 | sed -n 's/^#\([0-9]*\):.*/\1/p')
    secs=$(sed -n 's/^INFO: exiting: .* time: \([0-9]*\)s.*/\1/p' "$log" | tail -1)
    [ -n "$secs" ] || secs=$(grep -E '^#[0-9]+: cov:' "$log" | tail -1 | sed -n 's/.* time: \([0-9]*\)s.*/\1/p')
  else
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    secs=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)
  fi
  cov=$(grep -E '^#[0-9]+' "$log" | tail -1 | sed -n 's/.*cov: \([0-9]*\) ft: \([0-9]*\) corp: \([0-9]*\).*/edges \1, features \2, corpus \3/p')
  printf '%-22s rc %d  executions %s  seconds %s  %s  (log %s)\n' "$t" "$rc" "${execs:-?}" "${secs:-?}" "${cov:-?}" "$log"
  [ $rc -eq 0 ] || status=1
done
exit $status
