#!/bin/sh
# make fuzz-long: a fuzzing campaign. Every libFuzzer target in build/fuzz
# runs in turn for $1 seconds (FUZZ_SECONDS) on $2 cores (JOBS, libFuzzer's
# fork mode), on a corpus kept between campaigns in fuzz/work/<target>/ (git
# ignores it), seeded from fuzz/corpus/<target>/. After each target:
#   - the kept corpus is minimised (-merge=1 into a fresh folder);
#   - inputs that add coverage to the committed seeds are merged into
#     fuzz/corpus/<target>/ (-merge=1 adds only those): commit them;
#   - one line: executions, coverage (edges and features of the whole kept
#     corpus, as libFuzzer counts them) and the crashes, timeouts and
#     out-of-memory inputs found, which are kept in fuzz/work/crashes/.
#     Timeouts and slow units are run again alone: on a loaded machine (the
#     campaign runs beside other work, or niced) an input can wait past the
#     timeout without being slow. Those that finish alone within it move to
#     fuzz/work/crashes/unreproduced/ and are counted apart, with the
#     longest time alone.
# The campaign goes on past a crash and fails at the end if any target
# found one: turn each into a regression test.
# Usage: fuzz/long.sh SECONDS [JOBS] [TARGET...]
secs=${1:-1800}
jobs=${2:-2}
shift 2 2>/dev/null || shift $#
work=fuzz/work
mkdir -p "$work/crashes"
opts="-max_len=65536 -timeout=10 -rss_limit_mb=2048"

# the last "#N: cov: C ft: F" line of a fork-mode log: N C F
progress() { grep -o '^#[0-9]*: cov: [0-9]* ft: [0-9]*' "$1" | tail -1 | tr -d '#:' | awk '{print $1, $3, $5}'; }

one() {
    f=$1
    name=$(basename "$f")
    corpus=$work/$name seeds=fuzz/corpus/$name log=$work/$name.log
    mkdir -p "$corpus" "$seeds" "$work/$name.min"
    ls "$work/crashes" | grep "^$name-" > "$work/$name.before"
    before=$(wc -l < "$work/$name.before")
    # fork mode: $jobs processes share the corpus; -ignore_*: keep going and
    # keep every finding
    "$f" -fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -max_total_time="$secs" $opts \
        -artifact_prefix="$work/crashes/$name-" "$corpus" "$seeds" > "$log" 2>&1
    set -- $(progress "$log")
    runs=${1:-0}
    # minimise the kept corpus, then add to the seeds what grows their coverage
    rm -rf "$work/$name.min" && mkdir -p "$work/$name.min"
    "$f" -merge=1 $opts "$work/$name.min" "$corpus" "$seeds" > "$work/$name.merge.log" 2>&1 &&
        rm -rf "$corpus" && mv "$work/$name.min" "$corpus"
    nseed=$(ls "$seeds" | wc -l)
    "$f" -merge=1 $opts "$seeds" "$corpus" > "$work/$name.seeds.log" 2>&1
    added=$(($(ls "$seeds" | wc -l) - nseed))
    # coverage of the whole kept corpus, as one run over it reports it
    "$f" -runs=0 $opts "$corpus" > "$work/$name.cov.log" 2>&1
    cov=$(grep -o 'INITED cov: [0-9]* ft: [0-9]*' "$work/$name.cov.log" | tail -1 | awk '{print $3, $5}')
    mkdir -p "$work/crashes/unreproduced"
    unrep=0 slowest=0
    for t in $(ls "$work/crashes" | grep "^$name-\(timeout\|slow-unit\)-" | grep -vxF -f "$work/$name.before"); do
        t0=$(date +%s.%N)
        if "$f" -timeout=10 -rss_limit_mb=2048 "$work/crashes/$t" > /dev/null 2>&1; then
            slowest=$(awk -v a="$t0" -v b="$(date +%s.%N)" -v m="$slowest" 'BEGIN { d = b - a; print (d > m ? d : m) }')
            mv "$work/crashes/$t" "$work/crashes/unreproduced/"
            unrep=$((unrep + 1))
        fi
    done
    found=$(($(ls "$work/crashes" | grep -c "^$name-") - before))
    set -- $cov
    printf '%-18s %8ss %12s runs  cov %6s  ft %6s  corpus %5s  seeds +%-4s  found %s' "$name" "$secs" "$runs" \
        "${1:-?}" "${2:-?}" "$(ls "$corpus" | wc -l)" "$added" "$found"
    [ $unrep -gt 0 ] && printf '  (%s timeouts under load that finish alone in %.2f s at most)' $unrep "$slowest"
    printf '\n'
    [ "$found" -eq 0 ]
}

targets=$*
if [ -z "$targets" ]; then
    for f in build/fuzz/fuzz_*; do
        case "$f" in *.log) continue ;; esac
        [ -x "$f" ] && targets="$targets $f"
    done
fi
echo "fuzz-long: $secs s per target on $jobs cores, corpus kept in $work/ ($(date -u +%Y-%m-%dT%H:%MZ))"
status=0
for f in $targets; do
    case "$f" in */*) ;; *) f=build/fuzz/$f ;; esac
    one "$f" || status=1
done
if [ $status -ne 0 ]; then
    echo "fuzz-long: findings in $work/crashes/ (reproduce: build/fuzz/TARGET FILE); make each a regression test"
fi
exit $status
