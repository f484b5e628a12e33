#!/bin/sh
# Runs every libFuzzer target in build/fuzz for $1 seconds each, seeded from
# fuzz/corpus/<target>/ and tests/data/. A crash leaves its input in
# build/fuzz/crashes/ and makes the run fail.
secs=${1:-60}
status=0
mkdir -p build/fuzz/crashes
for f in build/fuzz/fuzz_*; do
    [ -x "$f" ] || continue
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
        status=1
    fi
done
exit $status
