#!/bin/sh
# `patchwork pgp` tests: every output and its format (rendering, OBJ with
# 'vt s t m' and its regular/singular groups, NRRD tile), determinism, the
# options that must change the result (field, seed, --no-fix, --show,
# constraints), tiles from NRRD files, images and --texture, and clear
# one-line errors (no crash, no output or .partial file left behind) on bad
# input of every kind.
suite=pgp_cli cmd=pgp
. "$(dirname "$0")/lib.sh"

# ---- helpers -------------------------------------------------------------

# pgp NAME ARGS...: runs `patchwork pgp ARGS` (stdout in $tmp/NAME.log);
# prints a FAIL line and returns 1 unless it exits 0 with a quiet stderr.
pgp() { run_ok "$@"; }

# reported LOG triangles|singular: from "pgp: T triangles, K singular (P%), ..."
reported() {
    sed -n 's/^pgp: \([0-9]*\) triangles, \([0-9]*\) singular (\([0-9.]*\)%).*/\1 \2 \3/p' "$1" |
        awk -v w="$2" '{ print (w == "triangles") ? $1 : (w == "singular") ? $2 : $3 }'
}

# check_obj FILE NTRIS NSING: validates the OBJ of a map; prints nothing
# when it is valid, else what is wrong.
check_obj() {
    awk -v ntris="$2" -v nsing="$3" '
    function bad(m) { if (err == "") err = "line " NR ": " m }
    function isnum(s) { return s ~ /^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$/ }
    err != "" { next }
    /^#/ { next }
    $1 == "v" { if (NF != 4 || !isnum($2) || !isnum($3) || !isnum($4)) bad("bad v line"); nv++; next }
    $1 == "vt" {
        if (NF != 4 || !isnum($2) || !isnum($3) || !isnum($4)) bad("bad vt line (s t m)")
        if ($4 < 0 || $4 > 1) bad("m = " $4 " is outside [0, 1]")
        nvt++; next
    }
    $1 == "g" {
        if (NF != 2) bad("bad group line")
        else if (group == "" && $2 != "regular") bad("first group is " $2)
        else if (group == "regular" && $2 != "singular") bad("second group is " $2)
        else if (group == "singular") bad("a third group")
        group = $2; last = -1; next
    }
    $1 == "f" {
        if (group == "") bad("a face before any group")
        if (NF != 4) { bad("a face with " NF - 1 " corners"); next }
        for (k = 2; k <= 4; k++) {
            split($k, c, "/")
            if (c[1] !~ /^[0-9]+$/ || c[2] !~ /^[0-9]+$/ || c[1] < 1 || c[1] > nv) bad("bad corner " $k)
            if (k == 2) tri = (c[2] - 1 - (c[2] - 1) % 3) / 3
            if (c[2] != 3 * tri + k - 1) bad("corner " $k " of triangle " tri " has the wrong vt")
        }
        if (tri <= last) bad("triangle " tri " after " last " in group " group)
        last = tri; nf++; if (group == "singular") ns++
        next
    }
    { bad("unexpected line: " $0) }
    END {
        if (err == "" && group != "singular") err = "groups missing (last: " group ")"
        if (err == "" && nf != ntris) err = nf " faces for " ntris " triangles"
        if (err == "" && nvt != 3 * ntris) err = nvt " vt lines for " ntris " triangles"
        if (err == "" && ns != nsing) err = ns " singular faces, " nsing " reported"
        if (err != "") print err
    }' "$1"
}

# png_size FILE: "WxH" from a PNG's IHDR, or nothing if FILE is no PNG.

# nrrd_field FILE NAME: the value of a NRRD header field.
nrrd_field() { head -c 400 "$1" | awk -v f="$2" 'NF == 0 { exit } index($0, f ": ") == 1 { print substr($0, length(f) + 3) }'; }

# differs NAME A B [same]: files A and B differ (or are the same).
differs() {
    if [ -s "$2" ] && [ -s "$3" ]; then
        if [ "$4" = same ]; then
            if cmp -s "$2" "$3"; then pass "$1"; else fail "$1" "$(basename "$2") and $(basename "$3") differ"; fi
        elif ! cmp -s "$2" "$3"; then pass "$1"; else fail "$1" "$(basename "$2") and $(basename "$3") are identical"; fi
    else
        fail "$1" "missing output files"
    fi
}

# ---- usage -------------------------------------------------------------------

if "$bin" pgp --help > "$tmp/help" 2>&1 && grep -q -- '--out-obj' "$tmp/help" && grep -q -- '--constraints' "$tmp/help" &&
   grep -q -- '--show' "$tmp/help"; then pass help; else fail help "no option list (or non-zero exit)"; fi
if "$bin" --help | grep -q '^  pgp '; then pass listed; else fail listed "pgp is not in patchwork --help"; fi

# ---- a run with every output ------------------------------------------------------

mesh="--mesh procedural:sphere --scale 0.5"
bricks="--tile procedural:bricks"
o="$tmp/all"
mkdir -p "$o"
if pgp outputs $mesh $bricks --size 96x72 --out-image "$o/x.png" --out-obj "$o/x.obj" --out-tile "$o/x.nrrd"; then
    ntris=$(reported "$tmp/outputs.log" triangles)
    nsing=$(reported "$tmp/outputs.log" singular)
    if [ "${ntris:-0}" -eq 2880 ] && [ -n "$nsing" ] && grep -q '^pgp: 2880 triangles, [0-9]* singular ([0-9.]*%) around [0-9]* vortices, tile 256x256 with 4 layers$' "$tmp/outputs.log"
    then pass summary; else fail summary "$(cat "$tmp/outputs.log")"; fi
    if [ "$(png_size "$o/x.png")" = 96x72 ]; then pass image; else fail image "no 96x72 PNG"; fi
    problem=$(check_obj "$o/x.obj" "${ntris:-0}" "${nsing:-x}")
    if [ -z "$problem" ] && [ "$(grep -c '^v ' "$o/x.obj")" -eq 1442 ]; then pass obj; else fail obj "${problem:-not 1442 vertices}"; fi
    if [ "$(head -1 "$o/x.nrrd")" = NRRD0004 ] && [ "$(nrrd_field "$o/x.nrrd" dimension)" = 4 ] &&
       [ "$(nrrd_field "$o/x.nrrd" sizes)" = "3 256 256 4" ] && [ "$(nrrd_field "$o/x.nrrd" type)" = uint8 ] &&
       [ "$(nrrd_field "$o/x.nrrd" encoding)" = raw ] && [ "$(wc -c < "$o/x.nrrd")" -gt 786432 ]
    then pass tile; else fail tile "header: $(head -c 200 "$o/x.nrrd" | head -6 | tr '\n' '|')"; fi
    if [ -z "$(ls "$o" | grep partial)" ]; then pass no_partial; else fail no_partial "$(ls "$o")"; fi
fi

# ---- determinism and options that matter -------------------------------------------------

run() { name=$1; shift; pgp "$name" $mesh --size 64x48 --out-image "$tmp/$name.png" --out-obj "$tmp/$name.obj" "$@"; }
run_tile() { name=$1; shift; pgp "$name" --mesh procedural:grid --out-tile "$tmp/$name.nrrd" "$@"; }

run base $bricks && run again $bricks && differs same_run "$tmp/base.png" "$tmp/again.png" same &&
    differs same_run_obj "$tmp/base.obj" "$tmp/again.obj" same
run up_default $bricks --field up && differs field_up_is_default "$tmp/base.obj" "$tmp/up_default.obj" same
run up_x $bricks --field up:1,0,0 && differs field_up_matters "$tmp/base.obj" "$tmp/up_x.obj"
run up_eq $bricks --field=up:1,0,0 && differs field_equals_form "$tmp/up_x.obj" "$tmp/up_eq.obj" same
run curv $bricks --field curvature && differs field_curvature_matters "$tmp/base.obj" "$tmp/curv.obj"
run scale $bricks --scale 0.3 && differs scale_matters "$tmp/base.obj" "$tmp/scale.obj"
run nofix $bricks --no-fix && differs no_fix_matters "$tmp/base.png" "$tmp/nofix.png"
run material $bricks --show material && differs show_material "$tmp/base.png" "$tmp/material.png"
run singular $bricks --show singular && differs show_singular "$tmp/base.png" "$tmp/singular.png"
run paperfix $bricks --fix paper && differs fix_paper_matters "$tmp/base.png" "$tmp/paperfix.png"
run allfix $bricks --fix all && differs fix_all_matters "$tmp/paperfix.png" "$tmp/allfix.png"
run ghosts $bricks --fix paper --show ghosts && differs show_ghosts "$tmp/paperfix.png" "$tmp/ghosts.png"
run zoomed $bricks --zoom 6 --center vortex:0 && differs zoom_matters "$tmp/base.png" "$tmp/zoomed.png"
# issue 17's report: vortices, the share drawn specially (the vortex triangles with the clean fix,
# section 3's singular ones with --fix paper), stretch and shear, and a warning for short periods
if grep -q '^pgp: drawn specially (fix clean): [0-9]* triangles ([0-9.]*%); surface stretched by more than 30%: [0-9.]*%, sheared by more than 20 degrees: [0-9.]*%$' "$tmp/base.log" &&
   [ "$(sed -n 's/^pgp: drawn specially (fix paper): \([0-9]*\) triangles.*/\1/p' "$tmp/paperfix.log")" = "$(reported "$tmp/base.log" singular)" ] &&
   grep -q '^pgp: warning: tile side 0.5 is under 8 mean edge lengths' "$tmp/base.log"
then pass report; else fail report "$(cat "$tmp/base.log" "$tmp/paperfix.log" | tr '\n' '|')"; fi
run_tile seed0 $bricks && run_tile seed5 $bricks --seed 5 && differs seed_matters "$tmp/seed0.nrrd" "$tmp/seed5.nrrd"

# constraints: materials change the m of the OBJ, comments and radius lines are fine
printf '# weathered at the bottom\nradius 0.8\nmaterial 2 1\nmaterial 3 0.5\nradius 0\nscale 0 0.4\norient 0 1 0 0\n' > "$tmp/cons.txt"
if run cons $bricks --constraints "$tmp/cons.txt"; then
    differs constraints_matter "$tmp/base.obj" "$tmp/cons.obj"
    nm=$(awk '$1 == "vt" && $4 > 0.25 { n++ } END { print n + 0 }' "$tmp/cons.obj")
    n0=$(awk '$1 == "vt" && $4 != 0 { n++ } END { print n + 0 }' "$tmp/base.obj")
    if [ "$nm" -gt 0 ] && [ "$n0" -eq 0 ]; then pass constraints_material; else fail constraints_material "$nm corners with m > 0.25 (constrained), $n0 with m != 0 (default)"; fi
    problem=$(check_obj "$tmp/cons.obj" "$(reported "$tmp/cons.log" triangles)" "$(reported "$tmp/cons.log" singular)")
    if [ -z "$problem" ]; then pass constraints_obj; else fail constraints_obj "$problem"; fi
fi

# ---- tiles from files -------------------------------------------------------------------

# the NRRD tile written above reads back, and is written again byte for byte
if [ -s "$o/x.nrrd" ] && run_tile from_nrrd --tile "$o/x.nrrd"; then
    differs nrrd_roundtrip "$o/x.nrrd" "$tmp/from_nrrd.nrrd" same
fi
# a 2D image is a one-layer tile, through --texture and through --tile
awk 'BEGIN { print "P3\n16 8\n255"; for (y = 0; y < 8; y++) for (x = 0; x < 16; x++) print (x * 16) % 256, y * 32, 128 }' > "$tmp/tex.ppm"
if run_tile texture --texture "$tmp/tex.ppm"; then
    if [ "$(nrrd_field "$tmp/texture.nrrd" sizes)" = "3 16 8 1" ]; then pass texture_one_layer
    else fail texture_one_layer "sizes $(nrrd_field "$tmp/texture.nrrd" sizes)"; fi
fi
run_tile image_tile --tile "$tmp/tex.ppm" && differs image_as_tile "$tmp/texture.nrrd" "$tmp/image_tile.nrrd" same
if pgp texture_render --mesh procedural:torus --texture "$tmp/tex.ppm" --size 48x36 --out-image "$tmp/tex.png" &&
   [ "$(png_size "$tmp/tex.png")" = 48x36 ]; then pass texture_render; else fail texture_render "no 48x36 PNG"; fi
run_tile stripes --tile procedural:stripes &&
    if [ "$(nrrd_field "$tmp/stripes.nrrd" sizes)" = "3 256 256 1" ]; then pass stripes_tile; else fail stripes_tile "sizes $(nrrd_field "$tmp/stripes.nrrd" sizes)"; fi

# ---- errors ---------------------------------------------------------------------------------

grid="--mesh procedural:grid"
out="--out-image $tmp/out/x.png --out-obj $tmp/out/x.obj --out-tile $tmp/out/x.nrrd"
expect_error no_mesh "--mesh" $bricks $out
expect_error no_tile "--tile or --texture" $grid $out
expect_error tile_and_texture "--tile or --texture" $grid $bricks --texture "$tmp/tex.ppm" $out
expect_error nothing_to_write "nothing to write" $grid $bricks
expect_error unknown_option "unknown option" $grid $bricks --frobnicate $out
expect_error missing_mesh_file "$tmp/nope.obj" --mesh "$tmp/nope.obj" $bricks $out
expect_error missing_tile_file "$tmp/nope.nrrd" $grid --tile "$tmp/nope.nrrd" $out
expect_error missing_texture_file "$tmp/nope.png" $grid --texture "$tmp/nope.png" $out
expect_error unknown_builtin_mesh "unknown built-in mesh" --mesh procedural:teapot $bricks $out
expect_error unknown_builtin_tile "unknown built-in tile" $grid --tile procedural:plaid $out
expect_error texture_procedural "--tile procedural:bricks" $grid --texture procedural:bricks $out
expect_error out_tile_extension "give a .nrrd file" $grid $bricks --out-tile "$tmp/out/x.png"
expect_error show_unknown "--show" $grid $bricks --show everything $out
expect_error field_unknown "--field: 'sideways'" $grid $bricks --field sideways $out
expect_error field_isotropic "--field" $grid $bricks --field isotropic $out
expect_error field_up_two "--field: 'up:1,0'" $grid $bricks --field up:1,0 $out
expect_error field_zero_up "zero up vector" $grid $bricks --field up:0,0,0 $out
expect_error field_up_nan "up" $grid $bricks --field up:nan,0,0 $out
expect_error field_no_value "needs a value" $grid $bricks $out --field
for s in 0 -1 1e31 nan abc; do
    expect_error "scale_$s" "scale" $grid $bricks --scale "$s" $out
done
# issue 17: tile sides the mesh cannot carry are refused with the range (the grid: diagonal 2.83,
# mean edge 0.071)
expect_error scale_huge "tile side 1e+06 is outside \[0.14[0-9]*, 28.28[0-9]*\]" $grid $bricks --scale 1e6 $out
expect_error scale_tiny "tile side 0.001 is outside" $grid $bricks --scale 0.001 $out
expect_error fix_unknown "--fix (clean, paper or all)" $grid $bricks --fix none $out
expect_error zoom_small "--zoom" $grid $bricks --zoom 0.5 $out
expect_error center_bad "--center" $grid $bricks --center 1,2 $out
expect_error center_no_vortex "the map has 0 vortices" $grid $bricks --zoom 4 --center vortex:0 $out
for s in 10x10 160 160x abc; do
    expect_error "size_$s" "--size" $grid $bricks --size "$s" $out
done
expect_error seed_negative "--seed" $grid $bricks --seed -3 $out

printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n' > "$tmp/short.off"
expect_error off_truncated "short.off" --mesh "$tmp/short.off" $bricks $out
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n' > "$tmp/fin.obj"
expect_error non_manifold "non-manifold" --mesh "$tmp/fin.obj" $bricks $out
printf 'NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 4 4 2\nencoding: raw\n\nabc' > "$tmp/short.nrrd"
expect_error nrrd_truncated "short.nrrd" $grid --tile "$tmp/short.nrrd" $out
printf 'NRRD0004\ntype: double\ndimension: 3\nsizes: 4 4 2\nencoding: raw\nendian: little\n\n' > "$tmp/double.nrrd"
expect_error nrrd_type "double.nrrd" $grid --tile "$tmp/double.nrrd" $out

# constraints files: the error names the file and the line
cons_error() {
    name=$1 pattern=$2
    printf "$3" > "$tmp/$name.txt"
    expect_error "$name" "$name.txt$pattern" $grid $bricks --constraints "$tmp/$name.txt" $out
}
cons_error cons_keyword ":2: unknown keyword 'colour'" 'material 3 1\ncolour 1 0 0\n'
cons_error cons_number ":1: .*malformed" 'scale 3 abc\n'
cons_error cons_nan ":3: .*not a finite number" '# c\n\nmaterial 3 nan\n'
cons_error cons_face_range ":1: .*triangle 2048 does not exist" 'orient 2048 1 0 0\n'
cons_error cons_vertex_range ":2: .*vertex 5000 does not exist" 'radius 0.5\nscale 5000 0.2\n'
cons_error cons_range_line ":5: .*triangle 9999 does not exist" '\357\273\277# c\n\nmaterial 3 1\n  radius 0.2\n\torient 9999 1 0 0\n'
cons_error cons_material_range ":1: .*material" 'material 3 2\n'
cons_error cons_extra ":1: unexpected text" 'scale 3 0.5 0.6\n'
cons_error cons_empty ": no constraints" '# nothing here\n'
expect_error cons_missing "$tmp/nope.txt" $grid $bricks --constraints "$tmp/nope.txt" $out

# bad outputs are refused before any work (nothing written, nothing left)
expect_error early_bad_extension "give an image (.png .ppm .pgm .pam)" $grid $bricks \
    --out-tile "$tmp/out/x.nrrd" --out-obj "$tmp/out/x.obj" --out-image "$tmp/out/x.gif"
expect_error early_no_folder "x.png: cannot write there (No such file or directory)" $grid $bricks \
    --out-tile "$tmp/out/x.nrrd" --out-obj "$tmp/out/x.obj" --out-image "$tmp/out/nowhere/x.png"
expect_error obj_extension "give an .obj file" $grid $bricks --out-obj "$tmp/out/x.nrrd" --out-tile "$tmp/out/x.nrrd"
expect_error glb_extension "give a .glb file" $grid $bricks --out-glb "$tmp/out/x.gltf"
expect_error glb_st_extension "give a .glb file" $grid $bricks --out-glb-st "$tmp/out/x.gltf"
expect_error glb_no_folder "x.glb: cannot write there (No such file or directory)" $grid $bricks \
    --out-glb "$tmp/out/nowhere/x.glb"
expect_error atlas_size "--atlas-size: '5' is not a whole number in 16..8192" $grid $bricks --atlas-size 5 \
    --out-glb "$tmp/out/x.glb"
expect_error glb_material "--glb-material: '2' is not a number in 0..1" $grid $bricks --glb-material 2 \
    --out-glb-st "$tmp/out/x.glb"
