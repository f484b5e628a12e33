#!/bin/sh
# The test runner behind `make test`: runs every unit-test binary and every
# shell test, prints their PASS/FAIL/SKIP/INFO lines, and closes with
# "N passed, N failed, N skipped". Exit status 1 if anything failed.
# Usage: tests/run.sh BUILD_DIR
build=${1:-build}
log=$(mktemp)
trap 'rm -f "$log"' EXIT INT TERM

for t in "$build"/tests/test_*; do
    [ -x "$t" ] || continue
    name=$(basename "$t")
    "$t" > "$log.out" 2>&1
    status=$?
    cat "$log.out"
    cat "$log.out" >> "$log"
    # a binary that dies without reporting a failure is a failure itself
    if [ $status -ne 0 ] && ! grep -q '^FAIL' "$log.out"; then
        echo "FAIL $name: exited with status $status" | tee -a "$log"
    fi
done
rm -f "$log.out"

for s in tests/sh/*.sh; do
    [ -f "$s" ] || continue
    BUILD="$build" sh "$s" 2>&1 | tee -a "$log"
done

pass=$(grep -c '^PASS' "$log")
fail=$(grep -c '^FAIL' "$log")
skip=$(grep -c '^SKIP' "$log")
echo "$pass passed, $fail failed, $skip skipped"
[ "$fail" -eq 0 ]
