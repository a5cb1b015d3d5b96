#!/usr/bin/env bash
# End-to-end checks of `tigris ref`: every bad input gets a clear message naming the file or
# flag and exit code 2; dumps and schedule replays round-trip. Usage: cli_test.sh TIGRIS_BINARY
set -u
tigris=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passes=0

# expect CODE PATTERN -- ARGS...: runs tigris ARGS, checks the exit code and that stderr or
# stdout contains PATTERN (fixed string).
expect() {
  local code=$1 pattern=$2
  shift 3
  local out rc
  out=$("$tigris" "$@" 2>&1)
  rc=$?
  if [ "$rc" -ne "$code" ] || ! grep -qF -- "$pattern" <<<"$out"; then
    echo "FAIL: tigris $* -> exit $rc (want $code), output:"
    sed 's/^/    /' <<<"$out" | head -20
    echo "    (wanted to see: $pattern)"
    failures=$((failures + 1))
  else
    passes=$((passes + 1))
  fi
}

# A small valid KITTI .bin (3 points) and bad files.
printf '\x00\x00\x80\x3f\x00\x00\x00\x40\x00\x00\x40\x40\x00\x00\x00\x00' >"$tmp/one.bin"
cat "$tmp/one.bin" "$tmp/one.bin" "$tmp/one.bin" >"$tmp/three.bin"
head -c 20 "$tmp/three.bin" >"$tmp/ragged.bin"
: >"$tmp/empty.bin"
printf '\x00\x00\xc0\x7f\x00\x00\x00\x40\x00\x00\x40\x40\x00\x00\x00\x00' | cat "$tmp/one.bin" - >"$tmp/nan.bin"
printf 'this is not a point cloud\n' >"$tmp/garbage.pcd"
printf 'ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n' >"$tmp/truncated.ply"
printf 'x y z\n' >"$tmp/cloud.xyz"

expect 0 "--cloud" -- ref --help
expect 2 "$tmp/missing.bin" -- ref --cloud "$tmp/missing.bin" --queries "$tmp/three.bin"
expect 2 "$tmp/ragged.bin" -- ref --cloud "$tmp/ragged.bin" --queries "$tmp/three.bin"
expect 2 "multiple of 16" -- ref --cloud "$tmp/ragged.bin" --queries "$tmp/three.bin"
expect 2 "$tmp/empty.bin" -- ref --cloud "$tmp/empty.bin" --queries "$tmp/three.bin"
expect 2 "$tmp/nan.bin" -- ref --cloud "$tmp/three.bin" --queries "$tmp/nan.bin" --height 0
expect 2 "$tmp/garbage.pcd" -- ref --cloud "$tmp/garbage.pcd" --queries "$tmp/three.bin"
expect 2 "$tmp/truncated.ply" -- ref --cloud "$tmp/truncated.ply" --queries "$tmp/three.bin"
expect 2 "$tmp/cloud.xyz" -- ref --cloud "$tmp/cloud.xyz" --queries "$tmp/three.bin"
expect 2 "exceeds the full height 2" -- ref --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --height 3
expect 2 "--height" -- ref --height ten
expect 2 "k must be >= 1" -- ref --mode knn --k 0
expect 2 "radius must be" -- ref --mode radius --radius 0
expect 2 "--radius: must be from 0" -- ref --mode radius --radius -1
expect 2 "--k applies to --mode knn" -- ref --k 5
expect 2 "--radius and --max-nn apply" -- ref --radius 0.5
expect 2 "need --approx-thd" -- ref --leader-capacity 4
expect 2 "--approx-thd must be" -- ref --approx-thd fast
expect 2 "--mode" -- ref --mode nearest
expect 2 "$tmp/none.csv" -- ref --schedule "$tmp/none.csv"
expect 2 "/proc/tigris: cannot create the folder" -- ref --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --height 1 --out /proc/tigris

# Small real runs: dumps, then a replay of the recorded schedule must give the same results.
expect 0 "3 neighbours" -- ref --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --height full --out "$tmp/o1"
base=(ref --mode knn --k 4 --height 7 --approx-thd default --out "$tmp/o2")
expect 0 "approximate" -- "${base[@]}" --dump-results "$tmp/r1.csv" --dump-schedule "$tmp/s1.csv"
expect 0 "approximate" -- "${base[@]}" --dump-results "$tmp/r2.csv" --schedule "$tmp/s1.csv"
if ! cmp -s "$tmp/r1.csv" "$tmp/r2.csv"; then
  echo "FAIL: replaying the recorded schedule changed the results"; failures=$((failures + 1))
else passes=$((passes + 1)); fi
if [ "$(head -1 "$tmp/r1.csv")" != "query,rank,index,dist2" ] || [ "$(head -1 "$tmp/s1.csv")" != "seq,query,leaf,event" ]; then
  echo "FAIL: dump headers"; failures=$((failures + 1))
else passes=$((passes + 1)); fi
grep -q '"leaf_points"' "$tmp/o2/stats.json" && passes=$((passes + 1)) || { echo "FAIL: stats.json lacks visits"; failures=$((failures + 1)); }
# A schedule edited to send a query to another leaf is rejected with the row named.
awk -F, 'NR==3 {$3 = ($3 == 0 ? 1 : 0)} {print}' OFS=, "$tmp/s1.csv" >"$tmp/s2.csv"
expect 2 "schedule row 1" -- "${base[@]}" --schedule "$tmp/s2.csv"

# tigris run: bad configurations are errors naming the key or buffer; two runs are identical.
expect 2 "be.pes_per_su" -- run --set be.pes_per_su=0
expect 2 "unknown key" -- run --set fe.recursion_unit=3
expect 2 "'node_cache.policy' must be one of \`" -- run --set node_cache.policy=foo
expect 2 "Point Buffer" -- run --set sram.points.bytes=100000
expect 2 "sram.query_stack.bytes" -- run --set sram.query_stack.bytes=64
expect 2 "radius must be" -- run --mode radius --radius 0
expect 2 "leader capacity must be" -- run --approx-thd 1 --leader-capacity -1
# Values that used to wrap, overflow or be taken in another base.
expect 2 "must be a whole number" -- run --seed -1
expect 2 "must be a whole number" -- ref --seed 1e23
expect 2 "must be a decimal number" -- run --set clock_mhz=0x10
expect 2 "must be a decimal number" -- run --set energy.distance_pj=inf
expect 2 "'clock_mhz' = 1e-10 is out of range" -- run --set clock_mhz=1e-10
expect 2 "'dram.bytes_per_cycle' = 1e-15 is out of range" -- run --set dram.bytes_per_cycle=1e-15
expect 2 "'energy.distance_pj' = 1e+308 is out of range" -- run --set energy.distance_pj=1e308
# The default top height is clamped for small clouds (with a note); an explicit one is not.
expect 0 "the default top height 10 is clamped to 2" -- ref --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --out "$tmp/clamp"
expect 0 "MATCH" -- run --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --out "$tmp/clamp_run"
# A folder holds one command's output: run does not write into ref's.
expect 2 "holds the output of tigris ref" -- run --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --out "$tmp/clamp"
expect 2 "$tmp/three.bin: top height 10" -- run --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --height 10
# Output paths: empty, a full disk, dots in folder names.
expect 2 "--out was given an empty value" -- run --out ""
expect 2 "/dev/full: writing the waveforms failed" -- run --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --height 1 --out "$tmp/full" --vcd /dev/full
expect 0 "gtkwave $tmp/o/dir.v2/waves.gtkw" -- run --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --height 1 --out "$tmp/dots" --vcd "$tmp/o/dir.v2/waves"
[ -f "$tmp/o/dir.v2/waves.gtkw" ] && passes=$((passes + 1)) || { echo "FAIL: the save file is not beside the waves"; failures=$((failures + 1)); }
expect 2 "need --approx-thd" -- run --leader-width 3
expect 2 "every_leaf" -- run --approx-thd default --leader-width 3
expect 0 "followers" -- run --approx-thd default --set leader.scope=every_leaf --leader-width 2 --height 8 --out "$tmp/rw"
expect 2 "applies to leader scope first_leaf" -- run --approx-thd default --set leader.scope=every_leaf --leader-in-flight wait
expect 0 "followers" -- run --approx-thd default --leader-scope every_leaf --mode knn --k 4 --leader-width 2 --height 8 --out "$tmp/ra" --dump-schedule "$tmp/ra.csv"
expect 0 "approximate" -- ref --approx-thd default --leader-scope every_leaf --mode knn --k 4 --leader-width 2 --height 8 --out "$tmp/rb" --schedule "$tmp/ra.csv"
# first_leaf, finished_only: the schedule carries the leaders' finishes, and its replay agrees.
fo=(--approx-thd default --leader-in-flight finished_only --height 8 --dump-results)
expect 0 "MATCH" -- run "${fo[@]}" "$tmp/fo_run.csv" --out "$tmp/fo" --dump-schedule "$tmp/fo.csv"
grep -q ',finish$' "$tmp/fo.csv" && passes=$((passes + 1)) || { echo "FAIL: no finish rows in $tmp/fo.csv"; failures=$((failures + 1)); }
expect 0 "approximate" -- ref "${fo[@]}" "$tmp/fo_ref.csv" --out "$tmp/fo2" --schedule "$tmp/fo.csv"
cmp -s "$tmp/fo_run.csv" "$tmp/fo_ref.csv" && passes=$((passes + 1)) || { echo "FAIL: finished_only replay dumps differ"; failures=$((failures + 1)); }
expect 2 "$tmp/none.json" -- run --config "$tmp/none.json"
small=(run --cloud "$tmp/three.bin" --queries "$tmp/three.bin" --height 1)
expect 0 "MATCH" -- "${small[@]}" --out "$tmp/r0"
expect 0 "Node Cache fifo" -- "${small[@]}" --set node_cache.policy=fifo --out "$tmp/r0fifo"
expect 0 "MATCH" -- run --mode knn --k 3 --height 12 --out "$tmp/run1" --dump-results "$tmp/run1.csv"
expect 0 "MATCH" -- run --mode knn --k 3 --height 12 --out "$tmp/run2"
c1=$(grep -m1 '"cycles"' "$tmp/run1/stats.json"); c2=$(grep -m1 '"cycles"' "$tmp/run2/stats.json")
if [ -z "$c1" ] || [ "$c1" != "$c2" ] || ! cmp -s <(grep -v '"simulation"\|"golden"\|"command_line"' "$tmp/run1/stats.json") <(grep -v '"simulation"\|"golden"\|"command_line"' "$tmp/run2/stats.json"); then
  echo "FAIL: two identical runs differ ($c1 vs $c2)"; failures=$((failures + 1))
else passes=$((passes + 1)); fi
# The accelerator's results dump equals the golden model's.
expect 0 "knn" -- ref --mode knn --k 3 --height 12 --out "$tmp/ref3" --dump-results "$tmp/ref3.csv"
cmp -s "$tmp/run1.csv" "$tmp/ref3.csv" && passes=$((passes + 1)) || { echo "FAIL: run and ref dumps differ"; failures=$((failures + 1)); }

# The accelerator's schedule replays through the golden model to the same results. --max-nn
# leaves the walk (and the schedule) as it is but keeps the results dump at 21 MB, not 630 MB.
expect 0 "MATCH" -- run --mode radius --radius 0.5 --max-nn 8 --height 9 --out "$tmp/hs" --dump-schedule "$tmp/hs.csv" --dump-results "$tmp/hs_run.csv"
expect 0 "radius" -- ref --mode radius --radius 0.5 --max-nn 8 --height 9 --out "$tmp/hs2" --schedule "$tmp/hs.csv" --dump-results "$tmp/hs_ref.csv"
cmp -s "$tmp/hs_run.csv" "$tmp/hs_ref.csv" && passes=$((passes + 1)) || { echo "FAIL: schedule replay dumps differ"; failures=$((failures + 1)); }

# Waveforms: a VCD with the unit signals and a GTKWave save file beside it.
expect 0 "waves" -- "${small[@]}" --out "$tmp/w" --vcd "$tmp/w/run.vcd"
if grep -q '^\$enddefinitions' "$tmp/w/run.vcd" && grep -q 'busy' "$tmp/w/run.vcd" && grep -q 'tigris.fe.fqq_occupancy' "$tmp/w/run.gtkw"; then
  passes=$((passes + 1))
else echo "FAIL: --vcd output"; failures=$((failures + 1)); fi

# tigris register: the default run (synthetic pair, dp4, exact search) and its clear errors.
expect 0 "wrote $tmp/reg/registration.json" -- register --out "$tmp/reg"
if grep -q '"transform"' "$tmp/reg/registration.json" && grep -q '"kdtree_share"' "$tmp/reg/registration.json" &&
   grep -q '"rotation_deg"' "$tmp/reg/registration.json"; then passes=$((passes + 1))
else echo "FAIL: register's registration.json"; failures=$((failures + 1)); fi
expect 2 "unknown key 'icp.max_iteration' (did you mean 'icp.max_iterations'?)" -- register --set icp.max_iteration=3 --out "$tmp/reg2"
expect 2 "'normals.radius' = -1.0 is out of range" -- register --set normals.radius=-1 --out "$tmp/reg2"
expect 2 "$tmp/missing.json: cannot read configuration file: no such file" -- register --config "$tmp/missing.json" --out "$tmp/reg2"
expect 2 "$tmp/missing.bin" -- register --source "$tmp/missing.bin" --target "$tmp/three.bin" --out "$tmp/reg2"
expect 2 "--source and --target go together" -- register --source "$tmp/three.bin" --out "$tmp/reg2"

# Error injection: bad values are rejected before any work, naming the flag or key.
expect 2 "--inject-kth must be an integer K in 1..100000" -- register --inject-kth 0 --out "$tmp/reg2"
expect 2 "--inject-kth must be an integer K in 1..100000" -- register --inject-kth 2.5 --out "$tmp/reg2"
expect 2 "--inject-kth must be an integer K in 1..100000" -- register --inject-kth abc --out "$tmp/reg2"
expect 2 "--inject-shell must be R1,R2 in metres" -- register --inject-shell 0.1 --out "$tmp/reg2"
expect 2 "--inject-shell must be R1,R2 in metres" -- register --inject-shell 0.1,x --out "$tmp/reg2"
expect 2 "--inject-shell 0.4,0.2: needs 0 <= R1 < R2" -- register --inject-shell 0.4,0.2 --out "$tmp/reg2"
expect 2 "--inject-shell 0.35,0.5: needs R1 < r < R2 around the normal radius r = 0.3" -- register --inject-shell 0.35,0.5 --out "$tmp/reg2"
expect 2 "--inject-shell 0.1,0.3: needs R1 < r < R2" -- register --inject-shell 0.1,0.3 --out "$tmp/reg2"
expect 2 "--inject-shell 0.1,0.4: needs R1 < r < R2 around the normal radius r = 0.75" -- register --preset dp7 --inject-shell 0.1,0.4 --out "$tmp/reg2"
expect 2 "--inject-kth needs --search exact, flann or accel" -- register --inject-kth 4 --search approx --out "$tmp/reg2"
expect 2 "'inject.normals_shell_inner' < 'normals.radius'" -- register --set inject.normals_shell_outer=0.2 --out "$tmp/reg2"
expect 0 "inject.rpce_kth" -- register --list-config
# An injected run says so and echoes the injection in registration.json.
expect 0 "RPCE returns the K-th nearest (K = 4), normals search the shell 0.1..0.4 m (r 0.3)" -- register --inject-kth 4 --inject-shell 0.1,0.4 --out "$tmp/inj"
if grep -q '"rpce_kth": 4' "$tmp/inj/registration.json" && grep -q '"normals_shell_outer": 0.4' "$tmp/inj/registration.json" &&
   grep -q '"error": "kth_nearest"' "$tmp/inj/registration.json"; then passes=$((passes + 1))
else echo "FAIL: the injection in registration.json"; failures=$((failures + 1)); fi

# `tigris sweep` runs tigris/tools/sweep.py with this binary: one point, a CSV row that matches.
printf '{"base": {"cloud": "%s", "queries": "%s", "mode": "nn", "set": {"fe.recursion_units": 4}}, "grid": {"height": [0, 1]}}' \
  "$tmp/three.bin" "$tmp/three.bin" > "$tmp/spec.json"
expect 0 "" -- sweep "$tmp/spec.json" --out "$tmp/sw" --jobs 1
if [ "$(grep -c ',ok,' "$tmp/sw/sweep.csv")" = 2 ] && head -1 "$tmp/sw/sweep.csv" | grep -q '^point,height,status'; then passes=$((passes + 1))
else echo "FAIL: tigris sweep's sweep.csv"; cat "$tmp/sw/sweep.csv"; failures=$((failures + 1)); fi
expect 2 "--jobs must be at least 1" -- sweep "$tmp/spec.json" --out "$tmp/sw2" --jobs 0
expect 0 "usage: reproduce [" -- reproduce --help

# The work guard: estimated from a sample before the search, exit 2 naming the limit to raise.
python3 -c "import sys; sys.stdout.buffer.write(open('$tmp/one.bin','rb').read() * 3000)" > "$tmp/same.bin"
expect 2 "above --max-work 1e+06; raise --max-work" -- ref --cloud "$tmp/same.bin" --queries "$tmp/same.bin" --max-work 1e6 --out "$tmp/guard"
expect 2 "above --max-work 1e+06" -- run --cloud "$tmp/same.bin" --queries "$tmp/same.bin" --max-work 1e6 --out "$tmp/guard"
expect 0 "" -- ref --cloud "$tmp/same.bin" --queries "$tmp/same.bin" --max-work 0 --out "$tmp/guard"
expect 2 "above --max-results 1e+03" -- ref --cloud "$tmp/same.bin" --queries "$tmp/three.bin" --mode radius --radius 1 --max-results 1000 --out "$tmp/guard"
expect 2 "--max-work: must be from 0 to 1e+18" -- ref --cloud "$tmp/same.bin" --queries "$tmp/three.bin" --max-work -1 --out "$tmp/guard"

# docs/model.md's Point Buffer capacity: 130,815 points fit at height 10, 130,816 do not.
python3 -c "
import struct, random
random.seed(2)
d = b''.join(struct.pack('<4f', random.uniform(-50, 50), random.uniform(-50, 50), random.uniform(-3, 3), 0) for _ in range(130816))
open('$tmp/fits.bin', 'wb').write(d[:-16]); open('$tmp/over.bin', 'wb').write(d)"
expect 2 "above --max-work 1" -- run --cloud "$tmp/fits.bin" --queries "$tmp/three.bin" --max-work 1 --out "$tmp/cap"
expect 2 "(130816 points): the tree image needs 2097156 bytes, the Point Buffer holds 2097152 (sram.points.bytes)" -- run --cloud "$tmp/over.bin" --queries "$tmp/three.bin" --out "$tmp/cap"

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
