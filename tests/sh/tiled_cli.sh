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
     ! grep -q -- "--scale S" "$tmp/err" ||
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

# any mesh (issue 23): tiles of a given side on the grid of a periodic
# parameterization; the figures on stdout, no small-tile warning, OBJ and
# glTF written
"$bin" tiled --mesh procedural:torus --subdivide 2 --scale 0.3 --out-image "$tmp/pic.png" --size 200x150 \
    --out-obj "$tmp/grid.obj" --out-glb "$tmp/grid.glb" > "$tmp/out" 2> "$tmp/err"
status=$?
if [ $status -ne 0 ]; then fail grid_mode "exit status $status: $(cat "$tmp/err")"
elif [ ! -s "$tmp/pic.png" ] || [ ! -s "$tmp/grid.obj" ] || [ ! -s "$tmp/grid.glb" ] || [ ! -s "$tmp/grid.png" ]; then
    fail grid_mode "an output is missing"
elif ! grep -q "pieces in [0-9]* cells" "$tmp/out" || ! grep -q " 0 mismatched" "$tmp/out"; then
    fail grid_mode "unexpected summary: $(cat "$tmp/out")"
elif [ -s "$tmp/err" ]; then fail grid_mode "unexpected stderr: $(cat "$tmp/err")"
else pass grid_mode; fi

# its pieces share their corners (welded): fewer OBJ vertices than corners,
# and the .glb passes Khronos' validator and reads back as the OBJ
verts=$(grep -c '^v ' "$tmp/grid.obj") corners=$(awk '/^f /{n += NF - 1} END {print n}' "$tmp/grid.obj")
if [ "$verts" -gt 0 ] && [ $((2 * verts)) -lt "$corners" ]; then pass grid_welded
else fail grid_welded "$verts OBJ vertices for $corners corners"; fi
js=$(dirname "$0")/../js
if ! command -v node > /dev/null 2>&1 || [ ! -d "$js/node_modules/gltf-validator" ]; then
    echo "SKIP tiled_cli/grid_gltf: node or tests/js/node_modules missing (apt-get install nodejs npm; make js)"
else
    node "$js/validate.mjs" "$tmp/grid.glb"
    node "$js/roundtrip.mjs" "$tmp/grid.glb" "$tmp/grid.obj"
fi

# tile sides the mesh cannot carry are refused with the range; so are
# negative and non-numeric ones and an unknown field
"$bin" tiled --mesh procedural:torus --scale 1000 --out-image "$tmp/x.png" > "$tmp/out" 2> "$tmp/err"
status=$?
if [ $status -eq 0 ] || ! grep -q "tile side 1000 is outside \[" "$tmp/err"; then
    fail grid_bad_scale "status $status: $(cat "$tmp/err")"
else pass grid_bad_scale; fi
bad=0
for args in "--scale -1" "--scale nan" "--scale x" "--scale 0.3 --field sideways"; do
    # shellcheck disable=SC2086
    if "$bin" tiled --mesh procedural:torus $args --out-image "$tmp/x.png" > "$tmp/out" 2> "$tmp/err" ||
        ! grep -q -- "--" "$tmp/err"; then
        bad=1
        fail grid_bad_flags "$args accepted or no message: $(cat "$tmp/err")"
    fi
done
[ $bad -eq 0 ] && pass grid_bad_flags
