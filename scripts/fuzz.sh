#!/usr/bin/env bash
# Builds the libFuzzer targets (clang++, ASan + UBSan, -j1, into build-fuzz/) and runs each for
# SECONDS (default 60), one after another at nice 10, then prints target / seconds / executions
# / crashes / wrong reads. Exits 1 when any target crashed or read wrongly.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]      targets: kitti_bin pcd ply config schedule_csv results_csv
#                                             register_config workload_trace
#
# Each target starts from its seeds in fuzz/corpus/<target>/ and keeps what it finds in
# build-fuzz/corpus/<target>/ (reused by the next run); crashing inputs go to
# build-fuzz/artifacts/<target>/ and the log to build-fuzz/logs/<target>.log. After a crash the
# target restarts for the time left (at most 5 times). A wrong read (the reader accepted the input
# but returned something else than it holds) is a crash whose log says "WRONG READ".
# Add each crashing input to fuzz/corpus/<target>/ once fixed: fuzz_corpus_regression replays it.
set -uo pipefail
cd "$(dirname "$0")/.."
root=$PWD
seconds=${1:-60}
shift || true
all_targets=(kitti_bin pcd ply config schedule_csv results_csv register_config workload_trace)
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=("${all_targets[@]}")
build=${TIGRIS_FUZZ_BUILD_DIR:-build-fuzz}

if ! [[ $seconds =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "usage: scripts/fuzz.sh [SECONDS] [TARGET...]  (targets: ${all_targets[*]})" >&2
  exit 2
fi
for t in "${targets[@]}"; do
  case " ${all_targets[*]} " in *" $t "*) ;; *) echo "unknown target '$t' (${all_targets[*]})" >&2; exit 2 ;; esac
done

cmake -S . -B "$build" -DTIGRIS_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null || exit 1
for t in "${targets[@]}"; do
  nice -n 10 cmake --build "$build" -j1 --target "fuzz_$t" >/dev/null || { echo "build of fuzz_$t failed" >&2; exit 1; }
done

declare -A execs crashes wrong
status=0
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t" "$build/artifacts/$t" "$build/logs"
  log="$build/logs/$t.log"
  : >"$log"
  dict=()
  [ -f "fuzz/$t.dict" ] && dict=(-dict="$root/fuzz/$t.dict")
  execs[$t]=0 crashes[$t]=0 wrong[$t]=0
  end=$(($(date +%s) + seconds))
  for attempt in 1 2 3 4 5 6; do
    left=$((end - $(date +%s)))
    [ "$left" -lt 1 ] && break
    run_log="$build/logs/$t.run$attempt.log"
    nice -n 10 "$build/fuzz/fuzz_$t" -max_total_time="$left" -print_final_stats=1 -max_len=8192 \
      -timeout=10 -rss_limit_mb=2048 "${dict[@]}" -artifact_prefix="$build/artifacts/$t/" \
      "$build/corpus/$t" "fuzz/corpus/$t" >"$run_log" 2>&1
    rc=$?
    cat "$run_log" >>"$log"
    n=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$run_log" | awk '{s += $2} END {print s + 0}')
    if [ "$n" -eq 0 ]; then  # no final stats after a crash: the last status line
      n=$(grep -o '^#[0-9]*' "$run_log" | tail -1 | tr -d '#')
    fi
    execs[$t]=$((execs[$t] + ${n:-0}))
    if [ $rc -ne 0 ]; then
      if grep -q 'WRONG READ' "$run_log"; then
        wrong[$t]=$((wrong[$t] + 1))
      else
        crashes[$t]=$((crashes[$t] + 1))
      fi
      status=1
      [ "$attempt" -eq 6 ] && break
      continue
    fi
    break
  done
done

printf '\n%-14s %8s %12s %8s %12s\n' target seconds executions crashes "wrong reads"
for t in "${targets[@]}"; do
  printf '%-14s %8s %12s %8s %12s\n' "$t" "$seconds" "${execs[$t]}" "${crashes[$t]}" "${wrong[$t]}"
done
[ $status -ne 0 ] && echo "crashing inputs: $build/artifacts/<target>/, logs: $build/logs/"
exit $status
