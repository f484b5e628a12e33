#!/bin/sh
# The C programs quoted in README.md compile against the headers as they
# are (warnings are errors), so the documentation cannot drift from the API.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
awk -v dir="$tmp" '
    /^```c$/ { n++; f = dir "/block" n ".c"; print "#include <stdio.h>" > f; inside = 1; next }
    /^```/   { inside = 0; next }
    inside   { print >> f }
' README.md
count=0
for f in "$tmp"/block*.c; do
    [ -f "$f" ] || continue
    count=$((count + 1))
    what=$(grep -m1 -o '[a-z]*\.h"' "$f" | tr -d '"')
    if ${CC:-cc} -std=c99 -Wall -Wextra -Werror -I. -o "$tmp/a.out" "$f" -lm 2> "$tmp/err.txt"; then
        echo "PASS readme: the $what quick start compiles"
    else
        echo "FAIL readme: the $what quick start does not compile: $(head -3 "$tmp/err.txt" | tr '\n' ' ')"
    fi
done
[ "$count" -gt 0 ] || echo "FAIL readme: no C program found in README.md"
