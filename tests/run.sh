#!/bin/sh
# The test runner behind `make test`: runs every unit-test binary and every
# shell test, JOBS at a time (default: the number of processors), prints
# their PASS/FAIL/SKIP/INFO lines test by test in a fixed order, and closes
# with "N passed, N failed, N skipped". Exit status 1 if anything failed.
# Usage: tests/run.sh BUILD_DIR [JOBS]
build=${1:-build}
jobs=${2:-$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)}
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT INT TERM

# One test: its output to $logs/NAME.log; a binary that dies without
# reporting a failure is a failure itself.
run_one() {
    t=$1
    name=$(basename "$t")
    case "$t" in
        *.sh) BUILD="$build" sh "$t" > "$logs/$name.log" 2>&1 ;;
        *)
            "$t" > "$logs/$name.log" 2>&1
            status=$?
            if [ $status -ne 0 ] && ! grep -q '^FAIL' "$logs/$name.log"; then
                echo "FAIL $name: exited with status $status" >> "$logs/$name.log"
            fi
            ;;
    esac
}

list=""
for t in "$build"/tests/test_* tests/sh/*.sh; do
    [ -f "$t" ] || continue
    case "$t" in *.sh) ;; *) [ -x "$t" ] || continue ;; esac
    list="$list $t"
done

# A fixed number of workers, each taking every jobs-th test of the list.
w=0
while [ $w -lt "$jobs" ]; do
    (
        k=0
        for t in $list; do
            [ $((k % jobs)) -eq $w ] && run_one "$t"
            k=$((k + 1))
        done
    ) &
    w=$((w + 1))
done
wait

for t in $list; do cat "$logs/$(basename "$t").log"; done > "$logs/all"
cat "$logs/all"
pass=$(grep -c '^PASS' "$logs/all")
fail=$(grep -c '^FAIL' "$logs/all")
skip=$(grep -c '^SKIP' "$logs/all")
echo "$pass passed, $fail failed, $skip skipped"
[ "$fail" -eq 0 ]
