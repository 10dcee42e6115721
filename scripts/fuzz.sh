#!/usr/bin/env bash
# Builds every libFuzzer target (tests/fuzz) with clang, ASan + UBSan, in
# build-fuzz/, then runs each for SECONDS (default 60) on a copy of its seed
# corpus. A crash leaves its input in build-fuzz/fuzz/artifacts/<target>/ and
# fails the script; turn every one into a regression test (docs/fuzzing.md).
# Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
seconds=${1:-60}
case "$seconds" in ''|*[!0-9]*) echo "usage: scripts/fuzz.sh [SECONDS]" >&2; exit 2;; esac

bash scripts/setup.sh
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# The loaders read files: the targets write each input to $TMPDIR, in memory where there is one.
[ -d /dev/shm ] && [ -w /dev/shm ] && export TMPDIR=/dev/shm

CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_FUZZ=ON \
  -DFOVEART_BUILD_BENCH=OFF "-DFOVEART_SANITIZE=address;undefined;fuzzer-no-link" >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target fuzzers

out=build-fuzz/fuzz
failed=()
printf '%-28s %12s %10s\n' target executions result
for corpus in tests/fuzz/corpus/*/; do
  target=$(basename "$corpus")
  work=$out/corpus/$target
  mkdir -p "$work" "$out/artifacts/$target"
  cp -n "$corpus"/* "$work"/ 2>/dev/null || true
  log=$out/$target.log
  # -rss_limit_mb: a loader that allocates what a header claims is a finding, not an OOM of the box.
  if "$out/$target" -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536 -timeout=10 \
      -artifact_prefix="$out/artifacts/$target/" "$work" >"$log" 2>&1; then
    result=ok
  else
    result=CRASH
    failed+=("$target")
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
  # After a crash there is no final stat line: take libFuzzer's last progress line (it starts "#N"),
  # not a frame number of the stack trace ("    #20 0x...").
  [ -n "$execs" ] || execs=$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
  printf '%-28s %12s %10s\n' "$target" "${execs:-?}" "$result"
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: crashes in ${failed[*]}; inputs in $out/artifacts/, logs in $out/*.log" >&2
  exit 1
fi
