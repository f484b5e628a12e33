#!/bin/sh
# The C programs quoted in README.md and the guides in docs/ compile
# against the headers as they are (warnings are errors), so the
# documentation cannot drift from the API.
suite=readme cmd=
. "$(dirname "$0")/lib.sh"
awk -v dir="$tmp" '
    /^```c$/ { n++; f = dir "/block" n ".c"; print "#include <stdio.h>" > f; inside = 1; next }
    /^```/   { inside = 0; next }
    inside   { print >> f }
' README.md docs/*.md
count=0
for f in "$tmp"/block*.c; do
    [ -f "$f" ] || continue
    count=$((count + 1))
    what=$(grep -m1 -o '[a-z]*\.h"' "$f" | tr -d '"')
    if ${CC:-cc} -std=c99 -Wall -Wextra -Werror -I. -o "$tmp/a.out" "$f" -lm 2> "$tmp/err.txt"; then
        pass "$what quick start compiles ($(basename "$f"))"
    else
        fail "$what quick start ($(basename "$f"))" "does not compile: $(head -3 "$tmp/err.txt" | tr '\n' ' ')"
    fi
done
[ "$count" -ge 4 ] || fail count "$count C programs in README.md and docs/, one per header expected"
