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
exec "$binary" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$scratch/$name/findings/" "$scratch/$name/corpus"
