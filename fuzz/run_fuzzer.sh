#!/usr/bin/env bash
# Runs one fuzz target for a bounded time on a scratch copy of its seed corpus (new corpus entries
# never land in the repository). Usage: run_fuzzer.sh <binary> <seed corpus folder> <seconds> <scratch>
# A finding (crash, sanitizer report, leak, timeout) fails with the reproducer saved in <scratch>.
set -euo pipefail
binary=$1 seeds=$2 seconds=$3 scratch=$4
name=$(basename "$binary")
rm -rf "$scratch/$name"
mkdir -p "$scratch/$name/corpus" "$scratch/$name/findings"
cp -r "$seeds"/. "$scratch/$name/corpus/"
# Sanitizer reports go to files as well: while a codec runs, hydrolux points file descriptor 2 into
# a capture buffer, so a report printed there would be lost with the crash.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}log_path=$scratch/$name/sanitizer"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:+$UBSAN_OPTIONS:}log_path=$scratch/$name/sanitizer"
status=0
"$binary" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$scratch/$name/findings/" "$scratch/$name/corpus" || status=$?
if [ "$status" -ne 0 ]; then
  for report in "$scratch/$name"/sanitizer.*; do
    [ -e "$report" ] && { echo "== $report"; cat "$report"; }
  done
  echo "reproduce: $binary $scratch/$name/findings/* (after the corpus, if it needs state: $binary -runs=1 $scratch/$name/corpus/* $scratch/$name/findings/*)"
fi
exit "$status"
