#!/bin/sh
# The test runner behind `make test`: runs every unit-test binary and every
# shell test, JOBS at a time (default: the number of processors), prints
# their PASS/FAIL/SKIP/INFO lines test by test in a fixed order, and closes
# with "N passed, N failed, N skipped". Exit status 1 if anything failed.
# Usage: tests/run.sh BUILD_DIR [JOBS]
#
# Each worker takes the next test from a shared queue, and the longest ones
# (SLOW below, measured) are queued first, so that the workers finish
# together instead of one running the longest test last.
build=${1:-build}
jobs=${2:-$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)}
SLOW="headers.sh gltf.sh test_lapped_atlas test_pgp_gltf test_alloc_failures test_lst_io test_stuffing pgp_cli.sh test_lst \
    examples.sh test_pgp_synth assimp_corpus.sh lapped_cli.sh test_lapped test_lst_cut"

# One test: its output to $logs/NAME.log; a binary that dies without
# reporting a failure is a failure itself.
if [ "${1:-}" = --one ]; then
    build=$2 logs=$3 t=$4
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
    exit 0
fi

logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT INT TERM

list=""
for t in "$build"/tests/test_* tests/sh/*.sh; do
    [ -f "$t" ] || continue
    case "$t" in *.sh) ;; *) [ -x "$t" ] || continue ;; esac
    list="$list $t"
done

# The queue: the slow tests that exist, in SLOW's order, then the others.
queue=""
for s in $SLOW; do
    for t in $list; do [ "$(basename "$t")" = "$s" ] && queue="$queue $t"; done
done
for t in $list; do
    case " $SLOW " in *" $(basename "$t") "*) ;; *) queue="$queue $t" ;; esac
done
printf '%s\n' $queue | xargs -P "$jobs" -n 1 sh "$0" --one "$build" "$logs"

for t in $list; do cat "$logs/$(basename "$t").log"; done > "$logs/all"
cat "$logs/all"
pass=$(grep -c '^PASS' "$logs/all")
fail=$(grep -c '^FAIL' "$logs/all")
skip=$(grep -c '^SKIP' "$logs/all")
echo "$pass passed, $fail failed, $skip skipped"
[ "$fail" -eq 0 ]
