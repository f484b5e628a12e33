#!/usr/bin/env bash
# Compile time of one implementation translation unit per header (cc -O2
# -c, CPU seconds user+sys, median of ROUNDS rounds, default 3), with
# nothing defined, PW_NO_RENDER, PW_NO_PNG and both; with a git revision,
# also that revision's headers with nothing defined ("before"), compiled in
# the same rounds so that both columns see the same machine load:
#   bash bench/compile.sh            (make bench-compile)
#   bash bench/compile.sh 7ffd9ab^   the headers as they were before 7ffd9ab
# Prints a Markdown table. CC and CFLAGS (default -O2) as for make.
set -u
cd "$(dirname "$0")/.." || exit 1
rev=${1:-}
rounds=${ROUNDS:-3}
cc=${CC:-cc}
cflags=${CFLAGS:--O2}
headers=$(make -s print-headers)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
configs="none PW_NO_RENDER PW_NO_PNG PW_NO_RENDER+PW_NO_PNG"
if [ -n "$rev" ]; then
    mkdir -p "$tmp/base"
    for h in $headers; do
        git show "$rev:$h.h" > "$tmp/base/$h.h" 2> /dev/null || { echo "no $h.h at $rev" >&2; exit 1; }
    done
    configs="before $configs"
fi

# tu HEADER CONFIG: writes the translation unit, prints its include flag
tu() {
    local up dir=. d
    up=$(echo "$1" | tr 'a-z' 'A-Z')
    : > "$tmp/$1-$2.c"
    if [ "$2" = before ]; then dir=$tmp/base; fi
    if [ "$2" != before ] && [ "$2" != none ]; then
        for d in ${2//+/ }; do echo "#define $d" >> "$tmp/$1-$2.c"; done
    fi
    printf '#define %s_IMPLEMENTATION\n#include "%s.h"\n' "$up" "$1" >> "$tmp/$1-$2.c"
    echo "-I$dir"
}

TIMEFORMAT='%U %S'
for r in $(seq "$rounds"); do
    for h in $headers; do
        for c in $configs; do
            inc=$(tu "$h" "$c")
            t=$( { time $cc $cflags $inc -c -o "$tmp/o.o" "$tmp/$h-$c.c" 2> "$tmp/err" > /dev/null; } 2>&1)
            if [ -s "$tmp/err" ] && ! [ -s "$tmp/o.o" ]; then cat "$tmp/err" >&2; exit 1; fi
            echo "$h $c $t" | awk '{ printf "%s %s %.3f\n", $1, $2, $3 + $4 }' >> "$tmp/times"
            rm -f "$tmp/o.o"
        done
    done
done

median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "Compile time, one implementation TU ($cc $cflags -c; $($cc --version | head -1)), CPU seconds, median of $rounds;"
echo "$(getconf _NPROCESSORS_ONLN) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end."
echo
printf '| header |'
for c in $configs; do printf ' %s |' "${c//+/ + }"; done
[ -n "$rev" ] && printf ' nothing vs before | both vs before |'
echo
printf '|---|'
for c in $configs; do printf -- '---|'; done
[ -n "$rev" ] && printf -- '---|---|'
echo
for h in $headers; do
    printf '| %s.h |' "$h"
    for c in $configs; do
        m=$(awk -v h="$h" -v c="$c" '$1 == h && $2 == c { print $3 }' "$tmp/times" | median)
        eval "m_${c//+/_}=$m"
        printf ' %.2f |' "$m"
    done
    if [ -n "$rev" ]; then
        awk -v a="$m_before" -v n="$m_none" -v b="$m_PW_NO_RENDER_PW_NO_PNG" \
            'BEGIN { printf " %+.0f%% | %+.0f%% |", 100 * (n - a) / a, 100 * (b - a) / a }'
    fi
    echo
done
