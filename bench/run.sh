#!/bin/sh
# Runs every benchmark binary in BUILD/bench (default build/bench), after
# bench/sysdump has dumped the sparse systems bench_sparse solves, then
# prints the summary table made of the ROW / GROWTH / PEER lines the
# programs print (bench.h describes them; they are hidden from each
# program's own output). With a second argument, also writes the table, the
# machine and every program's full output to that Markdown file:
#   sh bench/run.sh build bench/results.md    (make bench-report)
# BENCH_NO_PEERS="eigen osmesa assimp pnmtopng" (or "all") runs without
# those peers, as on a machine that lacks them.
build=${1:-build}
report=$2
BENCH_DATA=$build/bench-data
BENCH_BUILD=$build
export BENCH_DATA BENCH_BUILD
mkdir -p "$BENCH_DATA/systems" || exit 1
log=$BENCH_DATA/run.log
: > "$log"
cpu=$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //')
cores=$(getconf _NPROCESSORS_ONLN 2>/dev/null)
load0=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)
start=$(date +%s)
echo "patchwork benchmarks on $(uname -m), $cpu ($cores cores), load average $load0"
status=0

# run NAME COMMAND...: its output to the terminal (without the table lines)
# and to the log, its exit status recorded.
run() {
    name=$1
    shift
    echo "== $name" | tee -a "$log"
    { "$@"; echo "STATUS	$name	$?"; } 2>&1 | tee -a "$log" |
        grep -v -e '^ROW	' -e '^GROWTH	' -e '^PEER	' -e '^STATUS	'
}

# the dumped systems are inputs: made again when there are none or sysdump
# (which carries the headers) is newer than them
if [ -x "$build/bench/sysdump" ]; then
    if [ -s "$BENCH_DATA/systems/index.txt" ] && [ "$BENCH_DATA/systems/index.txt" -nt "$build/bench/sysdump" ]; then
        echo "== sysdump: the systems in $BENCH_DATA/systems are newer than sysdump, kept"
    else
        run sysdump "$build/bench/sysdump" "$BENCH_DATA/systems"
    fi
fi
for b in "$build"/bench/bench_*; do
    [ -x "$b" ] || continue
    run "$(basename "$b")" "$b"
done
if grep -q '^STATUS	.*	[1-9][0-9]*$' "$log"; then
    status=1
    echo "FAILED: $(grep '^STATUS	.*	[1-9][0-9]*$' "$log" | cut -f2 | tr '\n' ' ')"
fi
minutes=$(( ($(date +%s) - start + 30) / 60 ))
load1=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)

# The summary: Markdown tables (also readable in a terminal).
table() {
    echo "Peers: $(awk -F'\t' '$1 == "PEER" && !seen[$2]++ { printf "%s%s: %s", n++ ? "; " : "", $2, $3 }' "$log")."
    echo
    echo "Ratio: patchwork's time over the peer's, CPU time, median of the per-round ratios"
    echo "(< 1: patchwork faster; **bold**: patchwork slower, with the cause in the note;"
    echo "0.95-1.05: a tie)."
    echo "Figures: wall-clock medians with CPU-time medians in brackets; every contender"
    echo "runs once per round, in rotating order, after a warm-up round unless noted."
    echo
    echo "| task | patchwork | peer | peer figure | ratio | paper (their hardware) | rounds, spread | note |"
    echo "|---|---|---|---|---|---|---|---|"
    awk -F'\t' '$1 == "ROW" {
        r = $6
        if (r ~ /^[0-9.]+$/ && r + 0 > 1.05) r = "**" r " slower**"
        else if (r ~ /^[0-9.]+$/ && r + 0 >= 0.95) r = r " (tie)"
        printf "| %s | %s | %s | %s | %s | %s | %s | %s |\n", $2, $3, $5, $4, r, $7, $8, $9
    }' "$log"
    echo
    echo "Growth: exponent b of time ~ size^b (least squares in log-log; 1 = linear)."
    echo
    echo "| method | exponent | over | note |"
    echo "|---|---|---|---|"
    awk -F'\t' '$1 == "GROWTH" { printf "| %s | %s | %s | %s |\n", $2, $3, $4, $5 }' "$log"
}

machine() {
    echo "Taken on $(date -u +%Y-%m-%d) by \`make bench-report\` on $(uname -sm), $cpu, $cores cores,"
    echo "$(awk '/MemTotal/ { printf "%.0f GB", $2 / 1048576 }' /proc/meminfo) RAM; load average $load0 at the start and $load1 at the end"
    echo "(other sessions shared the machine); $minutes min in all. Compilers: $(${CC:-cc} --version | head -1);"
    echo "$(${CXX:-c++} --version | head -1)."
}

echo
echo "== summary"
table
if [ -n "$report" ]; then
    {
        echo "# patchwork against peers"
        echo
        machine
        echo
        table
        echo
        echo "<details><summary>Full output of every benchmark</summary>"
        echo
        echo '```'
        grep -v -e '^ROW	' -e '^GROWTH	' -e '^PEER	' -e '^STATUS	' "$log"
        echo '```'
        echo
        echo "</details>"
    } > "$report.tmp" && mv "$report.tmp" "$report" && echo "wrote $report"
fi
exit $status
