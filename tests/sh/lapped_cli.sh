#!/bin/sh
# `patchwork lapped` tests: every output and its format, the paste file's
# structure, determinism, every field and alpha mode, several textures, and
# clear one-line errors (no crash, no output or .partial file left behind) on
# bad input of every kind. Real data from `make data` when present.
suite=lapped_cli cmd=lapped
. "$(dirname "$0")/lib.sh"

# ---- helpers -------------------------------------------------------------

# lapped NAME ARGS...: runs `patchwork lapped ARGS` (stdout in $tmp/NAME.log);
# prints a FAIL line and returns 1 unless it exits 0 with a quiet stderr.
lapped() { run_ok "$@"; }

# reported LOG WORD: the number before WORD in the summary line
# "lapped: T triangles covered by K pastes, ..." of a run's stdout.
reported() {
    sed -n "s/^lapped: \([0-9]*\) triangles covered by \([0-9]*\) pastes.*/\1 \2/p" "$1" |
        awk -v w="$2" '{ print (w == "triangles") ? $1 : $2 }'
}

# check_pastes FILE NTRIS NPASTES [NPATCHES]: validates a paste file (see
# src/lapped/io.c). Prints nothing when it is valid, else what is wrong.
# On success $tmp/used holds the distinct patch indices the pastes use.
check_pastes() {
    awk -v ntris="$2" -v npastes="$3" -v npatches="${4:-}" -v used="$tmp/used" '
    function bad(m) { if (err == "") err = "line " NR ": " m }
    function isint(s) { return s ~ /^[0-9]+$/ }
    function isnum(s) { return s ~ /^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$/ }
    err != "" { next }
    NR == 1 { if ($0 != "lapped-pastes 1") bad("first line is \"" $0 "\", not \"lapped-pastes 1\""); next }
    state == 0 {
        if ($1 != "patches" || NF != 2 || !isint($2) || $2 < 1) bad("expected \"patches P\"")
        P = $2 + 0; seen = 0; state = (P > 0) ? 1 : 2; next
    }
    state == 1 {
        if ($1 != "patch" || NF != 4 || $2 != seen || !isint($3) || !isint($4) || $3 < 1 || $4 < 1)
            bad("expected \"patch " seen " W H\"")
        if (++seen == P) state = 2
        next
    }
    state == 2 {
        if ($1 != "pastes" || NF != 2 || !isint($2)) bad("expected \"pastes K\"")
        K = $2 + 0; k = 0; state = 3; next
    }
    state == 3 {
        if ($1 != "paste" || NF != 3 || !isint($2) || !isint($3)) { bad("expected \"paste PATCH N\""); next }
        if ($2 >= P) bad("paste " k " uses patch " $2 " of " P)
        patch_used[$2 + 0] = 1
        left = $3 + 0; k++
        state = (left > 0) ? 4 : 3; next
    }
    state == 4 {
        if (NF != 7) { bad("a face line has " NF " fields, not 7"); next }
        if (!isint($1) || $1 >= ntris) bad("face index " $1 " is not in 0.." ntris - 1)
        for (i = 2; i <= 7; i++) if (!isnum($i)) bad("texture coordinate \"" $i "\" is not a finite number")
        if (--left == 0) state = 3
        next
    }
    END {
        if (err == "" && NR == 0) err = "empty file"
        if (err == "" && state != 3) err = "truncated (state " state ", " left " face lines missing)"
        if (err == "" && k != K) err = K " pastes announced, " k " present"
        if (err == "" && npastes != "" && K != npastes) err = K " pastes in the file, " npastes " reported"
        if (err == "" && npatches != "" && P != npatches) err = P " patches in the file, " npatches " expected"
        if (err != "") print err
        else { for (p in patch_used) print p > used }
    }' "$1"
}

# png_size FILE: "WxH" from a PNG's IHDR, or nothing if FILE is no PNG.

# pam_header FILE: the text header of a PAM (up to ENDHDR), one line each.
pam_header() { head -c 200 "$1" | awk '{ print } /^ENDHDR$/ { exit }'; }

# pam_alpha FILE X Y: the alpha byte of pixel (X,Y) of an 8-bit RGBA PAM.
pam_alpha() {
    hdr=$(pam_header "$1" | wc -c)
    w=$(pam_header "$1" | sed -n 's/^WIDTH //p')
    od -An -tu1 -j $((hdr + ($3 * w + $2) * 4 + 3)) -N1 "$1" | tr -d ' '
}

# ---- usage -----------------------------------------------------------------

if "$bin" lapped --help > "$tmp/help" 2>&1 && grep -q -- '--out-pastes' "$tmp/help" &&
   grep -q -- '--field' "$tmp/help"; then pass help; else fail help "no option list (or non-zero exit)"; fi

# ---- a run with every output -------------------------------------------------

mesh="--mesh procedural:sphere"
dots="--texture procedural:dots"
o=$tmp/all
mkdir -p "$o"
if lapped outputs $mesh $dots --scale 0.8 --size 160x120 --atlas-size 128 --out-image "$o/x.png" \
        --out-pastes "$o/x.pastes" --out-patch "$o/patch.pam" --out-obj "$o/x.obj" --out-atlas "$o/atlas.png"; then
    missing=""
    for f in x.png x.pastes patch.pam x.obj x.mtl atlas.png; do [ -s "$o/$f" ] || missing="$missing $f"; done
    partial=$(find "$o" -name '*.partial' | wc -l)
    if [ -z "$missing" ] && [ "$partial" -eq 0 ]; then pass outputs
    else fail outputs "missing or empty:$missing; $partial .partial files"; fi

    size=$(png_size "$o/x.png")
    if [ "$size" = "160x120" ]; then pass image_png; else fail image_png "x.png is '${size:-not a PNG}', expected a 160x120 PNG"; fi
    size=$(png_size "$o/atlas.png")
    if [ "$size" = "128x128" ]; then pass atlas_png; else fail atlas_png "atlas.png is '${size:-not a PNG}', expected a 128x128 PNG"; fi

    # the patch: a P7 header with RGB_ALPHA, and exactly W*H*4 bytes after it
    pam_header "$o/patch.pam" > "$tmp/pam.hdr"
    w=$(sed -n 's/^WIDTH //p' "$tmp/pam.hdr")
    h=$(sed -n 's/^HEIGHT //p' "$tmp/pam.hdr")
    bytes=$(($(wc -c < "$o/patch.pam") - $(wc -c < "$tmp/pam.hdr")))
    if [ "$(head -1 "$tmp/pam.hdr")" = P7 ] && grep -q '^TUPLTYPE RGB_ALPHA$' "$tmp/pam.hdr" &&
       grep -q '^DEPTH 4$' "$tmp/pam.hdr" && grep -q '^MAXVAL 255$' "$tmp/pam.hdr" &&
       [ -n "$w" ] && [ -n "$h" ] && [ "$bytes" -eq $((w * h * 4)) ]; then
        pass patch_pam
    else
        fail patch_pam "bad PAM: $(tr '\n' '|' < "$tmp/pam.hdr") and $bytes data bytes"
    fi

    # the OBJ: mtllib naming the MTL beside it, one vt per triangle corner
    # in [0,1], faces v/vt; the MTL names the atlas
    ntris=$(reported "$tmp/outputs.log" triangles)
    nf=$(grep -c '^f ' "$o/x.obj")
    nvt=$(grep -c '^vt ' "$o/x.obj")
    badvt=$(awk '/^vt / && !($2 >= 0 && $2 <= 1 && $3 >= 0 && $3 <= 1)' "$o/x.obj" | wc -l)
    if grep -q '^mtllib x.mtl$' "$o/x.obj" && [ "$nf" -eq "${ntris:-0}" ] && [ "$nvt" -gt 0 ] &&
       [ "$badvt" -eq 0 ] && [ "$(grep -c '^f [0-9]*/[0-9]* [0-9]*/[0-9]* [0-9]*/[0-9]*$' "$o/x.obj")" -eq "$nf" ] &&
       grep -q '^map_Kd atlas.png$' "$o/x.mtl" && grep -q '^newmtl ' "$o/x.mtl"; then
        pass obj_mtl
    else
        fail obj_mtl "mtllib: $(grep -c '^mtllib x.mtl' "$o/x.obj"), $nf faces for ${ntris:-?} triangles, $nvt vt ($badvt outside [0,1]), MTL: $(tr '\n' '|' < "$o/x.mtl")"
    fi

    # the paste file
    npastes=$(reported "$tmp/outputs.log" pastes)
    problem=$(check_pastes "$o/x.pastes" "${ntris:-0}" "${npastes:-x}" 1)
    if [ -z "$problem" ] && [ "${npastes:-0}" -gt 0 ]; then pass pastes_format; else fail pastes_format "${problem:-no pastes reported}"; fi
fi

# ---- determinism -------------------------------------------------------------

run_seed() { lapped "$1" $mesh $dots --scale 0.8 --size 96x72 --seed "$2" --out-pastes "$tmp/$1.pastes" --out-image "$tmp/$1.png"; }
if run_seed seed7a 7 && run_seed seed7b 7 && run_seed seed8 8; then
    if cmp -s "$tmp/seed7a.pastes" "$tmp/seed7b.pastes" && cmp -s "$tmp/seed7a.png" "$tmp/seed7b.png"; then
        pass same_seed
    else
        fail same_seed "two runs with seed 7 wrote different files"
    fi
    if ! cmp -s "$tmp/seed7a.pastes" "$tmp/seed8.pastes"; then pass other_seed
    else fail other_seed "seeds 7 and 8 wrote the same paste file"; fi
fi

# ---- field modes ---------------------------------------------------------------

# field_run NAME MESH ARGS...: a run must succeed and write a valid paste file
field_run() {
    name=$1 fmesh=$2
    shift 2
    lapped "$name" --mesh "$fmesh" $dots --size 64x48 --out-pastes "$tmp/$name.pastes" --out-image "$tmp/$name.png" "$@" ||
        return 1
    problem=$(check_pastes "$tmp/$name.pastes" "$(reported "$tmp/$name.log" triangles)" "$(reported "$tmp/$name.log" pastes)")
    if [ -n "$problem" ]; then fail "$name" "$problem"; return 1; fi
    if [ -z "$(png_size "$tmp/$name.png")" ]; then fail "$name" "no PNG image"; return 1; fi
    pass "$name"
}

printf '# orient face dx dy dz [scale [radius [weight]]]\norient 0 1 0 0\norient 700 0 0 1 0.6 1.5 2\n\norient 2000 0 1 0 0.9\n' > "$tmp/cons.txt"
printf '# face dx dy dz [scale [radius [weight]]]\n0 1 0 0\n700 0 0 1 0.6 1.5 2\n\n2000 0 1 0 0.9\n' > "$tmp/old_cons.txt"
field_run field_default procedural:sphere --scale 0.8
field_run field_up procedural:sphere --scale 0.8 --field up
field_run field_up_x procedural:sphere --scale 0.8 --field up:1,0,0
field_run field_isotropic procedural:sphere --scale 0.8 --field isotropic
field_run field_lscm procedural:sphere --scale 0.8 --field isotropic --lscm
field_run field_curvature procedural:bumpy --scale 0.8 --field curvature
field_run field_constraints procedural:sphere --scale 0.8 --field "constraints:$tmp/cons.txt"
field_run field_equals procedural:sphere --scale 0.8 --field=up:1,0,0

# the field must matter: +Y is the default, another up or mode changes the pastes
differs() {
    if [ -s "$tmp/$2.pastes" ] && [ -s "$tmp/$3.pastes" ]; then
        if [ "$4" = same ]; then
            if cmp -s "$tmp/$2.pastes" "$tmp/$3.pastes"; then pass "$1"; else fail "$1" "$2 and $3 differ"; fi
        elif ! cmp -s "$tmp/$2.pastes" "$tmp/$3.pastes"; then pass "$1"; else fail "$1" "$2 and $3 are identical"; fi
    else
        fail "$1" "missing paste files"
    fi
}
differs field_up_is_default field_default field_up same
differs field_equals_form field_up_x field_equals same
differs field_up_matters field_up field_up_x
differs field_lscm_matters field_isotropic field_lscm
differs field_constraints_matter field_up field_constraints

# the old positional constraint lines: the same field, and one warning naming the first such line
"$bin" lapped --mesh procedural:sphere $dots --size 64x48 --scale 0.8 --field "constraints:$tmp/old_cons.txt" \
    --out-pastes "$tmp/field_constraints_old.pastes" > "$tmp/old.log" 2> "$tmp/old.err"
status=$?
if [ $status -ne 0 ]; then fail field_constraints_positional "exit status $status: $(head -2 "$tmp/old.err" | tr '\n' '|')"
elif [ "$(wc -l < "$tmp/old.err")" -ne 1 ] ||
    ! grep -q "^patchwork lapped: warning: $tmp/old_cons.txt: line 2: positional constraint lines are deprecated; write 'orient F dx dy dz \.\.\.'\$" "$tmp/old.err"; then
    fail field_constraints_positional "stderr: $(cat "$tmp/old.err")"
else pass field_constraints_positional; fi
differs field_constraints_positional_same field_constraints field_constraints_old same

# ---- alpha modes -----------------------------------------------------------------

# a mask opaque on its left half only (ASCII PGM, the size of the texture)
awk 'BEGIN { print "P2\n128 128\n255"; for (y = 0; y < 128; y++) { l = ""
             for (x = 0; x < 128; x++) l = l (x < 64 ? "255 " : "0 "); print l } }' > "$tmp/half.pgm"
for mode in splotch circle mask; do
    case $mode in
        mask) flag="--mask $tmp/half.pgm" ;;
        *) flag="--$mode" ;;
    esac
    lapped "alpha_$mode" $mesh $dots --scale 0.8 $flag --out-patch "$tmp/$mode.pam" --out-pastes "$tmp/$mode.pastes" || continue
    problem=$(check_pastes "$tmp/$mode.pastes" "$(reported "$tmp/alpha_$mode.log" triangles)" "$(reported "$tmp/alpha_$mode.log" pastes)")
    corner=$(pam_alpha "$tmp/$mode.pam" 0 0)
    centre=$(pam_alpha "$tmp/$mode.pam" 32 64)
    right=$(pam_alpha "$tmp/$mode.pam" 100 64)
    if [ -n "$problem" ]; then fail "alpha_$mode" "$problem"
    elif [ "$corner" != 0 ]; then fail "alpha_$mode" "corner alpha $corner, expected 0"
    elif [ "$mode" = mask ] && { [ "$centre" != 255 ] || [ "$right" != 0 ]; }; then
        fail "alpha_$mode" "alpha $centre inside and $right outside the mask, expected 255 and 0"
    elif [ "$mode" = circle ] && [ "$(pam_alpha "$tmp/$mode.pam" 64 64)" != 255 ]; then
        fail "alpha_$mode" "centre alpha $(pam_alpha "$tmp/$mode.pam" 64 64), expected 255"
    else pass "alpha_$mode"; fi
done
if [ -s "$tmp/splotch.pam" ] && [ -s "$tmp/circle.pam" ]; then
    if ! cmp -s "$tmp/splotch.pam" "$tmp/circle.pam"; then pass alpha_modes_differ
    else fail alpha_modes_differ "--splotch and --circle made the same patch"; fi
fi

# ---- several textures --------------------------------------------------------------

if lapped textures $mesh --scale 0.6 --texture procedural:dots --texture procedural:stripes \
        --texture procedural:scales --out-pastes "$tmp/three.pastes"; then
    rm -f "$tmp/used"
    problem=$(check_pastes "$tmp/three.pastes" "$(reported "$tmp/textures.log" triangles)" "$(reported "$tmp/textures.log" pastes)" 3)
    nused=$(cat "$tmp/used" 2> /dev/null | wc -l)
    if [ -n "$problem" ]; then fail textures "$problem"
    elif [ "$nused" -lt 2 ]; then fail textures "the pastes use $nused of 3 patches"
    else pass textures; fi
fi

# ---- errors --------------------------------------------------------------------------

out="--out-pastes $tmp/out/x.pastes --out-image $tmp/out/x.png --out-patch $tmp/out/p.pam"
atlas="--out-obj $tmp/out/x.obj --out-atlas $tmp/out/a.png --atlas-size 64"
expect_error no_mesh "--mesh" $dots $out
expect_error no_texture "--texture" $mesh $out
expect_error nothing_to_write "nothing to write" $mesh $dots
expect_error obj_needs_atlas "go together" $mesh $dots --out-obj "$tmp/out/x.obj"
expect_error unknown_option "unknown option" $mesh $dots --frobnicate $out
expect_error missing_mesh_file "$tmp/nope.obj" --mesh "$tmp/nope.obj" $dots $out
expect_error missing_texture_file "$tmp/nope.png" $mesh --texture "$tmp/nope.png" $out
expect_error unknown_builtin_mesh "unknown built-in mesh" --mesh procedural:teapot $dots $out
expect_error unknown_builtin_texture "unknown built-in texture" $mesh --texture procedural:plaid $out

printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n' > "$tmp/syntax.obj"
expect_error obj_syntax "syntax.obj:4" --mesh "$tmp/syntax.obj" $dots $out $atlas
printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n' > "$tmp/short.off"
expect_error off_truncated "short.off" --mesh "$tmp/short.off" $dots $out
# three triangles sharing the edge v1-v2
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n' > "$tmp/fin.obj"
expect_error non_manifold "non-manifold" --mesh "$tmp/fin.obj" $dots $out $atlas
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n' > "$tmp/flat.obj"
expect_error zero_area "zero area" --mesh "$tmp/flat.obj" $dots $out

# masks: all transparent, and not the size of the texture
{ printf 'P5\n128 128\n255\n'; head -c 16384 /dev/zero; } > "$tmp/zero.pgm"
expect_error transparent_mask "mask is all zero" $mesh $dots --mask "$tmp/zero.pgm" $out $atlas
{ printf 'P5\n4 4\n255\n'; head -c 16 /dev/zero | tr '\0' '\377'; } > "$tmp/small.pgm"
expect_error mask_size "mask is 4x4" $mesh $dots --mask "$tmp/small.pgm" $out

for s in 0 -1 1e30 nan inf abc 0.0001; do
    expect_error "scale_$s" "scale" $mesh $dots --scale "$s" $out
done
for s in 10x10 0x0 160 160x 160x120x 99999x100 -160x120 abc; do
    expect_error "size_$s" "--size" $mesh $dots --size "$s" $out
done
expect_error field_unknown "--field: 'sideways'" $mesh $dots --field sideways $out
expect_error field_empty "--field" $mesh $dots --field "" $out
expect_error field_up_two "--field: 'up:1,0'" $mesh $dots --field up:1,0 $out
expect_error field_up_four "--field" $mesh $dots --field up:1,0,0,0 $out
expect_error field_up_nan "up vector" $mesh $dots --field up:nan,0,0 $out
expect_error field_constraints_no_file "--field" $mesh $dots --field constraints: $out
expect_error field_no_value "needs a value" $mesh $dots $out --field

printf 'orient 0 1 0\n' > "$tmp/short_cons.txt"
expect_error constraints_short "short_cons.txt:1" $mesh $dots --field "constraints:$tmp/short_cons.txt" $out
printf 'orient 0 1 0 0\norient 1 0 x 0\n' > "$tmp/bad_cons.txt"
expect_error constraints_syntax "bad_cons.txt:2" $mesh $dots --field "constraints:$tmp/bad_cons.txt" $out
printf 'orient 0 nan 0 0\n' > "$tmp/nan_cons.txt"
expect_error constraints_nan "non-finite" $mesh $dots --field "constraints:$tmp/nan_cons.txt" $out
printf 'orient 0 0 0 0\n' > "$tmp/zero_cons.txt"
expect_error constraints_zero_direction "direction" $mesh $dots --field "constraints:$tmp/zero_cons.txt" $out
printf 'orient 0 1 0 0 -1\n' > "$tmp/neg_cons.txt"
expect_error constraints_negative_scale "scale" $mesh $dots --field "constraints:$tmp/neg_cons.txt" $out
printf '# nothing\n' > "$tmp/empty_cons.txt"
expect_error constraints_empty "no constraints" $mesh $dots --field "constraints:$tmp/empty_cons.txt" $out
printf 'orient 0 1 0 0\norient 2880 0 1 0\n' > "$tmp/range_cons.txt" # the sphere has 2880 triangles
expect_error constraints_range "out of range" $mesh $dots --field "constraints:$tmp/range_cons.txt" $out $atlas
expect_error constraints_missing "$tmp/nope.txt" $mesh $dots --field "constraints:$tmp/nope.txt" $out
printf 'orient 0 1 0 0\nscale 3 0.5\n' > "$tmp/keyword_cons.txt"
expect_error constraints_unknown_keyword "keyword_cons.txt:2: unknown keyword 'scale'" $mesh $dots \
    --field "constraints:$tmp/keyword_cons.txt" $out

# bad outputs are refused before any work (nothing written, nothing left)
expect_error early_bad_extension "give an image (.png .ppm .pgm .pam)" $mesh $dots --scale 0.8 \
    --out-pastes "$tmp/out/x.pastes" --out-patch "$tmp/out/p.pam" --out-image "$tmp/out/x.gif"
expect_error early_no_folder "a.png: cannot write there (No such file or directory)" $mesh $dots --scale 0.8 \
    --out-pastes "$tmp/out/x.pastes" --out-image "$tmp/out/x.png" --out-obj "$tmp/out/x.obj" \
    --out-atlas "$tmp/out/nowhere/a.png" --atlas-size 64

# ---- real data (make data) -------------------------------------------------------------

emesh=data/meshes/elephant.off
tex1=data/textures/bark.ppm
tex2=data/textures/Craters.ppm
if [ -f "$emesh" ] && [ -f "$tex1" ] && [ -f "$tex2" ]; then
    if lapped real_data --mesh "$emesh" --texture "$tex1" --texture "$tex2" --size 160x120 \
            --out-pastes "$tmp/real.pastes" --out-image "$tmp/real.png"; then
        ntris=$(reported "$tmp/real_data.log" triangles)
        faces=$(sed -n '2{s/^OFF//;p;q}' "$emesh" | awk '{ print $2 }') # "nv nf ne" follows OFF
        problem=$(check_pastes "$tmp/real.pastes" "$ntris" "$(reported "$tmp/real_data.log" pastes)" 2)
        if [ -n "$problem" ]; then fail real_data "$problem"
        elif [ "$(png_size "$tmp/real.png")" != 160x120 ]; then fail real_data "no 160x120 PNG"
        elif [ -n "$faces" ] && [ "$ntris" -lt "$faces" ]; then fail real_data "$ntris triangles for $faces faces"
        else pass real_data; fi
    fi
else
    skip real_data "no $emesh or GIMP patterns (run make data)"
fi
pat=$(ls /usr/share/gimp/2.0/patterns/*.pat 2> /dev/null | head -1)
if [ -n "$pat" ]; then
    if lapped real_pat $mesh --texture "$pat" --scale 0.8 --out-patch "$tmp/pat.pam" --out-pastes "$tmp/pat.pastes"; then
        problem=$(check_pastes "$tmp/pat.pastes" "$(reported "$tmp/real_pat.log" triangles)" "$(reported "$tmp/real_pat.log" pastes)" 1)
        if [ -z "$problem" ] && pam_header "$tmp/pat.pam" | grep -q '^TUPLTYPE RGB_ALPHA$'; then pass real_pat
        else fail real_pat "${problem:-no RGBA patch}"; fi
    fi
else
    skip real_pat "no GIMP .pat patterns installed"
fi

# --channel: another per-texel channel (here a gray copy of the texture, made
# with `patchwork convert`) through the same pastes, rendered and baked into
# an atlas with the same layout as the colour atlas
if "$bin" lapped $mesh $dots --out-image "$tmp/ch_src.ppm" --size 64x48 > /dev/null 2>&1 &&
   "$bin" lapped $mesh $dots --out-patch "$tmp/ch_patch.pam" > /dev/null 2>&1 &&
   "$bin" convert "$tmp/ch_patch.pam" "$tmp/ch_gray.pgm" > /dev/null 2>&1; then
    rm -rf "$tmp/out" && mkdir -p "$tmp/out"
    if lapped channel $mesh $dots --channel "$tmp/ch_gray.pgm" --size 160x120 --atlas-size 256 \
            --out-image "$tmp/out/c.png" --out-channel-image "$tmp/out/cc.png" \
            --out-obj "$tmp/out/c.obj" --out-atlas "$tmp/out/ca.png" --out-channel-atlas "$tmp/out/cca.png"; then
        if [ "$(png_size "$tmp/out/cc.png")" != 160x120 ] || [ "$(png_size "$tmp/out/cca.png")" != 256x256 ]; then
            fail channel "channel image or atlas missing or of the wrong size"
        elif cmp -s "$tmp/out/c.png" "$tmp/out/cc.png"; then
            fail channel "the channel rendering equals the colour rendering"
        else pass channel; fi
    fi
else
    fail channel "could not make the channel input"
fi
expect_error channel_count "one per texture" $mesh $dots --texture procedural:scales --channel "$tmp/ch_gray.pgm" \
    --out-channel-image "$tmp/out/cc.png"
expect_error channel_alone "go together" $mesh $dots --channel "$tmp/ch_gray.pgm" --out-image "$tmp/out/x.png"
expect_error channel_size "size" $mesh $dots --channel "$tmp/ch_src.ppm" --out-channel-image "$tmp/out/cc.png"
expect_error same_path "named by two outputs" $mesh $dots --out-image "$tmp/out/x.png" --out-pastes "$tmp/out/x.png"
expect_error zero_up "zero up vector" $mesh $dots --field up:0,0,0 $out

# a scale needing more pastes than --max-pastes is refused before any work,
# with the estimate (the elephant at 0.006 used to run 71 s and 388 MB
# before stopping at the limit)
expect_error max_pastes_up_front "would take about [0-9]* pastes, over the limit of 50" \
    --mesh procedural:bumpy --texture procedural:dots --max-pastes 50 --out-image "$tmp/out/x.png"
expect_error max_pastes_range "--max-pastes: '0' is not a whole number in 1..100000000" \
    --mesh procedural:bumpy --texture procedural:dots --max-pastes 0 --out-image "$tmp/out/x.png"
expect_error scale_positive "--scale: '0' is not a positive number" $mesh $dots --scale 0 --out-image "$tmp/out/x.png"
expect_error falloff_range "--falloff: '2000' is not a number in 0..1000" $mesh $dots --falloff 2000 --out-image "$tmp/out/x.png"
