#!/bin/sh
# tiled CLI on dense meshes (issue 18): when one tile per quad would be
# drawn under 16 px, `patchwork tiled` still writes its outputs but warns,
# naming the size and what to do; coarse meshes get no warning.
suite=tiled_cli cmd=tiled
. "$(dirname "$0")/lib.sh"

# dense: the built-in torus (288 quads) three levels finer, 18,432 quads
"$bin" tiled --mesh procedural:torus --subdivide 3 --out-image "$tmp/dense.png" --size 200x150 \
    > "$tmp/out" 2> "$tmp/err"
status=$?
px=$(sed -n 's/.*tiles are drawn about \([0-9.]*\) px wide.*/\1/p' "$tmp/err")
if [ $status -ne 0 ]; then fail dense_warns "exit status $status: $(cat "$tmp/err")"
elif [ ! -s "$tmp/dense.png" ]; then fail dense_warns "no image written"
elif [ -z "$px" ]; then fail dense_warns "no size in the warning: $(cat "$tmp/err")"
elif ! awk -v p="$px" 'BEGIN { exit !(p > 0 && p < 16) }'; then fail dense_warns "tile size $px px, expected under 16"
elif ! grep -q -- "coarser quad mesh" "$tmp/err" || ! grep -q -- "--subdivide" "$tmp/err" ||
     ! grep -q "patchwork pgp" "$tmp/err" || ! grep -q "patchwork lapped" "$tmp/err"; then
    fail dense_warns "the warning does not say what to do: $(cat "$tmp/err")"
else pass dense_warns; fi

# the same torus at its own resolution, drawn at the default 800x600:
# tiles of about 50 px, no warning
"$bin" tiled --mesh procedural:torus --out-tiles "$tmp/coarse.png" > "$tmp/out" 2> "$tmp/err"
status=$?
if [ $status -ne 0 ]; then fail coarse_quiet "exit status $status: $(cat "$tmp/err")"
elif [ -s "$tmp/err" ]; then fail coarse_quiet "unexpected stderr: $(cat "$tmp/err")"
else pass coarse_quiet; fi

# a bigger picture draws the same tiles bigger: the torus one level finer
# warns at 200x150 and not at 4000x3000
"$bin" tiled --mesh procedural:torus --subdivide 1 --out-tiles "$tmp/t.png" --size 200x150 > "$tmp/out" 2> "$tmp/err1"
"$bin" tiled --mesh procedural:torus --subdivide 1 --out-tiles "$tmp/t.png" --size 4000x3000 > "$tmp/out" 2> "$tmp/err2"
if ! grep -q "tiles are drawn" "$tmp/err1"; then fail size_matters "no warning at 200x150: $(cat "$tmp/err1")"
elif [ -s "$tmp/err2" ]; then fail size_matters "warning at 4000x3000: $(cat "$tmp/err2")"
else pass size_matters; fi
