#!/bin/sh
# Every example program runs and writes the images it promises.
build=${BUILD:-build}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
for ex in "$build"/examples/*; do
    [ -x "$ex" ] || continue
    name=$(basename "$ex")
    if (cd "$tmp" && "$OLDPWD/$ex" > out.txt 2>&1); then
        missing=""
        for f in $(grep -o '[a-z_]*\.\(ppm\|png\|pastes\|obj\|mtl\)' "$tmp/out.txt"); do
            [ -s "$tmp/$f" ] || missing="$missing $f"
        done
        if [ -z "$missing" ]; then echo "PASS examples/$name"; else echo "FAIL examples/$name: missing$missing"; fi
    else
        echo "FAIL examples/$name: $(tail -1 "$tmp/out.txt")"
    fi
done
