#!/bin/sh
# Runs every libFuzzer target in build/fuzz for $1 seconds each (default
# 60), $2 at a time (default 1), seeded from fuzz/corpus/<target>/. Prints
# one line per target with its execution count. A crash leaves its input in
# build/fuzz/crashes/ and makes the run fail: turn it into a regression test.
secs=${1:-60}
jobs=${2:-1}
mkdir -p build/fuzz/crashes
one() {
    f=$1
    name=$(basename "$f")
    corpus=build/fuzz/corpus/$name
    mkdir -p "$corpus"
    seeds=""
    [ -d "fuzz/corpus/$name" ] && seeds="fuzz/corpus/$name"
    if "$f" -max_total_time="$secs" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
        -artifact_prefix=build/fuzz/crashes/"$name"- "$corpus" $seeds > build/fuzz/"$name".log 2>&1; then
        runs=$(grep -o 'Done [0-9]* runs' build/fuzz/"$name".log | tail -1)
        echo "fuzz $name: ok ($runs in ${secs}s)"
    else
        echo "fuzz $name: FAILED, see build/fuzz/$name.log and build/fuzz/crashes/"
        tail -30 build/fuzz/"$name".log
        return 1
    fi
}
targets=""
for f in build/fuzz/fuzz_*; do
    case "$f" in *.log) continue ;; esac
    [ -x "$f" ] && targets="$targets $f"
done
status=0
pids=""
w=0
while [ $w -lt "$jobs" ]; do
    (
        k=0 st=0
        for f in $targets; do
            if [ $((k % jobs)) -eq $w ]; then one "$f" || st=1; fi
            k=$((k + 1))
        done
        exit $st
    ) > build/fuzz/worker$w.out &
    pids="$pids $!"
    w=$((w + 1))
done
for p in $pids; do wait "$p" || status=1; done
cat build/fuzz/worker*.out
rm -f build/fuzz/worker*.out
exit $status
