#!/bin/sh
# CLI tests: usage, outputs, determinism, and clear one-line errors (exit
# status 1, no output file left behind) on bad input of every kind.
suite=cli cmd=
. "$(dirname "$0")/lib.sh"

"$bin" --version | grep -q '^patchwork [0-9]' && pass version || fail version "no version line"
"$bin" --help | grep -q 'tiled' && pass help || fail help "no command list"
"$bin" tiled --help | grep -q -- '--out-obj' && pass tiled_help || fail tiled_help "no options"

out="--out-image $tmp/out/x.png --out-obj $tmp/out/x.obj"
expect_error no_mesh "mesh is required" tiled --out-image "$tmp/out/x.png"
expect_error unknown_option "unknown option" tiled --mesh procedural:cube --frobnicate $out
expect_error bad_number "not a whole number" tiled --mesh procedural:cube --pairs 0 $out
expect_error missing_file "$tmp/nope.obj" tiled --mesh "$tmp/nope.obj" $out
# outputs are checked before any work: the folder, with the reason
expect_error no_folder "--out-image $tmp/out/nowhere/x.png: cannot write there (No such file or directory)" \
    tiled --mesh procedural:cube --out-image "$tmp/out/nowhere/x.png"
expect_error obj_extension "--out-obj $tmp/out/x.png: give an .obj file" tiled --mesh procedural:cube --out-obj "$tmp/out/x.png"
expect_error nothing_to_do "nothing to write" tiled --mesh procedural:cube
expect_error bad_extension "give an image (.png .ppm .pgm .pam)" tiled --mesh procedural:cube --out-image "$tmp/out/x.gif"
expect_error unknown_builtin "unknown built-in mesh" tiled --mesh procedural:teapot $out

printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n' > "$tmp/syntax.obj"
expect_error obj_syntax "syntax.obj.*4" tiled --mesh "$tmp/syntax.obj" $out
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n' > "$tmp/range.obj"
expect_error obj_index "range.obj" tiled --mesh "$tmp/range.obj" $out
printf 'v 0 0 nan\nv 1 0 0\nv 1 1 0\nf 1 2 3\n' > "$tmp/nan.obj"
expect_error obj_nan "non-finite" tiled --mesh "$tmp/nan.obj" $out
printf 'OFF\n2147483648 1 0\n0 0 0\n' > "$tmp/huge.off"
expect_error off_huge_header "huge.off" tiled --mesh "$tmp/huge.off" $out
printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n' > "$tmp/short.off"
expect_error off_truncated "short.off" tiled --mesh "$tmp/short.off" $out
printf 'OFF\n8 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 -1 0\n0 -1 0\n1 0 1\n0 0 1\n4 0 1 2 3\n4 1 0 5 4\n4 0 1 6 7\n' > "$tmp/fin.off"
expect_error non_manifold "non-manifold" tiled --mesh "$tmp/fin.off" $out
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\001\002' > "$tmp/trunc.ply"
expect_error ply_truncated "trunc.ply" tiled --mesh "$tmp/trunc.ply" $out
printf 'P6\n4 4\n255\nabc' > "$tmp/short.ppm"
expect_error image_truncated "short.ppm" tiled --mesh procedural:cube --exemplar "$tmp/short.ppm" $out
: > "$tmp/empty.obj"
expect_error empty_mesh "empty.obj" tiled --mesh "$tmp/empty.obj" $out

# a successful run writes all outputs, with an MTL that names the texture
rm -rf "$tmp/out" && mkdir -p "$tmp/out"
if "$bin" tiled --mesh procedural:double-torus --subdivide 1 --seed 3 --size 200x150 \
        --out-obj "$tmp/out/dt.obj" --out-image "$tmp/out/dt_render.png" > "$tmp/stdout" 2> "$tmp/stderr" &&
   [ -s "$tmp/out/dt.obj" ] && [ -s "$tmp/out/dt.png" ] && [ -s "$tmp/out/dt_render.png" ] &&
   grep -q 'map_Kd dt.png' "$tmp/out/dt.mtl" &&
   grep -q '^mtllib dt.mtl' "$tmp/out/dt.obj" && grep -q '^vt ' "$tmp/out/dt.obj" &&
   grep -q '^f [0-9]*/[0-9]* ' "$tmp/out/dt.obj" && [ -z "$(ls "$tmp/out" | grep partial)" ]; then
    pass outputs
else
    fail outputs "$(cat "$tmp/stderr") $(ls "$tmp/out" | tr '\n' ' ')"
fi

# two outputs on one file (here the OBJ's default texture and the rendering)
# are refused before anything is written
rm -rf "$tmp/out" && mkdir -p "$tmp/out"
if "$bin" tiled --mesh procedural:torus --out-obj "$tmp/out/t.obj" --out-image "$tmp/out/t.png" \
        > /dev/null 2> "$tmp/stderr"; then
    fail same-path "exit status 0"
elif grep -q 'named by two outputs' "$tmp/stderr" && [ -z "$(ls "$tmp/out")" ]; then
    pass same-path
else
    fail same-path "$(cat "$tmp/stderr") $(ls "$tmp/out" | tr '\n' ' ')"
fi

# determinism: same seed, byte-identical files
"$bin" tiled --mesh procedural:torus --seed 5 --size 120x90 --out-obj "$tmp/a.obj" --out-image "$tmp/a_r.png" > /dev/null 2>&1
"$bin" tiled --mesh procedural:torus --seed 5 --size 120x90 --out-obj "$tmp/b.obj" --out-image "$tmp/b_r.png" > /dev/null 2>&1
sed 's/b\.mtl/a.mtl/' "$tmp/b.obj" > "$tmp/b2.obj"
if [ -s "$tmp/a.png" ] && cmp -s "$tmp/a.obj" "$tmp/b2.obj" && cmp -s "$tmp/a.png" "$tmp/b.png" &&
   cmp -s "$tmp/a_r.png" "$tmp/b_r.png"; then
    pass determinism
else
    fail determinism "outputs differ between two runs with the same seed"
fi

# a hand-made tiled texture (thesis layout) validates; a scrambled one does not
"$bin" tiled --mesh procedural:cube --guard none --out-tiles "$tmp/plain.ppm" > /dev/null 2>&1
if "$bin" tiled --tiles "$tmp/plain.ppm" --validate > "$tmp/stdout" 2>&1; then pass validate_ok; else fail validate_ok "$(cat "$tmp/stdout")"; fi
"$bin" tiled --mesh procedural:cube --guard none --seed 9 --out-tiles "$tmp/other.ppm" > /dev/null 2>&1
if [ -s "$tmp/plain.ppm" ] && [ -s "$tmp/other.ppm" ]; then
    # splice: top half from one set, bottom half from another
    size=$(wc -c < "$tmp/plain.ppm")
    half=$((size / 2))
    head -c "$half" "$tmp/plain.ppm" > "$tmp/mixed.ppm"
    tail -c $((size - half)) "$tmp/other.ppm" >> "$tmp/mixed.ppm"
    expect_error validate_mismatch "do not match" tiled --tiles "$tmp/mixed.ppm" --validate
else
    fail validate_mismatch "could not write the tile sets"
fi

# the quick demo: every method's scenes, PPM and PNG of each, the same bytes twice
if "$bin" demo --quick "$tmp/demo1" > "$tmp/stdout" 2>&1 && "$bin" demo --quick "$tmp/demo2" > /dev/null 2>&1; then
    n=$(ls "$tmp/demo1" | wc -l)
    missing=""
    for m in tiled lapped pgp lst; do ls "$tmp/demo1" | grep -q "^${m}_.*\.png$" || missing="$missing $m"; done
    if [ -n "$missing" ]; then fail demo_quick "no images of:$missing"
    elif [ "$(ls "$tmp/demo1" | grep -c '\.png$')" -ne "$(ls "$tmp/demo1" | grep -c '\.ppm$')" ]; then fail demo_quick "PNG and PPM counts differ"
    elif ! diff -r "$tmp/demo1" "$tmp/demo2" > /dev/null; then fail demo_quick "two runs differ"
    else pass demo_quick; fi
    echo "INFO cli/demo_quick: $n files"
else
    fail demo_quick "$(tail -1 "$tmp/stdout")"
fi
expect_error demo_usage "usage: patchwork demo" demo --quick "$tmp/out/a" "$tmp/out/b"

# --view and --view-up, shared by every command that renders: a Z-up view
# draws another picture than the default; an axis name and its vector are
# the same; bad directions are refused naming the flag
for m in tiled lapped pgp; do
    case $m in
        tiled) args="tiled --mesh procedural:torus --exemplar procedural:pebbles" ;;
        lapped) args="lapped --mesh procedural:torus --texture procedural:dots" ;;
        pgp) args="pgp --mesh procedural:torus --tile procedural:bricks" ;;
    esac
    if "$bin" $args --size 64x48 --out-image "$tmp/$m.y.ppm" > /dev/null 2>&1 &&
        "$bin" $args --size 64x48 --view-up z --out-image "$tmp/$m.z.ppm" > /dev/null 2>&1 &&
        "$bin" $args --size 64x48 --view-up 0,0,2 --out-image "$tmp/$m.z2.ppm" > /dev/null 2>&1 &&
        ! cmp -s "$tmp/$m.y.ppm" "$tmp/$m.z.ppm" && cmp -s "$tmp/$m.z.ppm" "$tmp/$m.z2.ppm"; then pass "view_up_$m"
    else fail "view_up_$m" "--view-up z did not change the picture, or differs from 0,0,2"; fi
    expect_error "bad_view_$m" "is not a direction X,Y,Z" $args --view 0,0,0 --out-image "$tmp/out/x.png"
    expect_error "bad_view_up_$m" "--view-up: 'w' is not" $args --view-up w --out-image "$tmp/out/x.png"
    if "$bin" $args --size 64x48 --supersample 1 --out-image "$tmp/$m.s1.ppm" > /dev/null 2>&1 &&
        ! cmp -s "$tmp/$m.y.ppm" "$tmp/$m.s1.ppm"; then pass "supersample_$m"
    else fail "supersample_$m" "--supersample 1 gave the default's picture, or failed"; fi
    expect_error "bad_supersample_$m" "--supersample: '9' is not a whole number in 1..8" $args --supersample 9 \
        --out-image "$tmp/out/x.png"
done
