#!/bin/sh
# Every example program runs and writes the images it promises.
suite=examples cmd=
. "$(dirname "$0")/lib.sh"
build=${BUILD:-build}
for ex in "$build"/examples/*; do
    [ -x "$ex" ] || continue
    name=$(basename "$ex")
    if (cd "$tmp" && "$OLDPWD/$ex" > out.txt 2>&1); then
        missing=""
        for f in $(grep -o '[a-z_]*\.\(ppm\|png\|pastes\|obj\|mtl\)' "$tmp/out.txt"); do
            [ -s "$tmp/$f" ] || missing="$missing $f"
        done
        if [ -z "$missing" ]; then pass "$name"; else fail "$name" "missing$missing"; fi
    else
        fail "$name" "$(tail -1 "$tmp/out.txt")"
    fi
done
