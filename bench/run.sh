#!/bin/sh
# Runs every benchmark binary in $1/bench (default build/bench).
build=${1:-build}
echo "patchwork benchmarks on $(uname -m), $(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //')"
status=0
for b in "$build"/bench/bench_*; do
    [ -x "$b" ] || continue
    echo "== $(basename "$b")"
    "$b" || status=1
done
exit $status
