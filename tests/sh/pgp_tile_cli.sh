#!/bin/sh
# `patchwork pgp-tile` tests: the NRRD tile (sizes C W H M) and its slices
# and masks in PNG and PPM, the tile read back by `patchwork pgp`,
# determinism and the options that must change the result (seed, layers,
# size, single-tile mode, mask mode, uniform subsampling, a given mask),
# real GIMP exemplars (spots to stripes and back, when `make data` was run),
# and clear one-line errors with no output or .partial file left behind on
# bad input of every kind.
suite=pgp_tile_cli cmd=pgp-tile
. "$(dirname "$0")/lib.sh"
data=${PW_DATA:-data}

# ---- helpers -------------------------------------------------------------

# tile NAME ARGS...: runs `patchwork pgp-tile ARGS`; a FAIL line and status
# 1 unless it exits 0 with a quiet stderr.
tile() { run_ok "$@"; }

nrrd_field() { head -c 400 "$1" | awk -v f="$2" 'NF == 0 { exit } index($0, f ": ") == 1 { print substr($0, length(f) + 3) }'; }

differs() {
    if [ -s "$2" ] && [ -s "$3" ]; then
        if [ "$4" = same ]; then
            if cmp -s "$2" "$3"; then pass "$1"; else fail "$1" "$(basename "$2") and $(basename "$3") differ"; fi
        elif ! cmp -s "$2" "$3"; then pass "$1"; else fail "$1" "$(basename "$2") and $(basename "$3") are identical"; fi
    else
        fail "$1" "missing output files"
    fi
}

# Keys written as ASCII netpbm: spots (dark discs on orange, 48x48), their
# mask, stripes (period 12, 48x40), masks of all zeros, all ones and the
# wrong size.
awk 'BEGIN { n = 48; print "P3"; print n, n; print 255
    for (y = 0; y < n; y++) for (x = 0; x < n; x++) {
        dx = (x % 16) - 7.5; dy = (y % 16) - 7.5; v = ((x * 7 + y * 13) % 11) * 3
        if (dx * dx + dy * dy < 25) print 40 + v, 25 + v, 10 + v; else print 220 - v, 140 - v, 60 }
    }' > "$tmp/spots.ppm"
awk 'BEGIN { n = 48; print "P2"; print n, n; print 255
    for (y = 0; y < n; y++) for (x = 0; x < n; x++) {
        dx = (x % 16) - 7.5; dy = (y % 16) - 7.5; print (dx * dx + dy * dy < 25) ? 255 : 0 } }' > "$tmp/spots_mask.pgm"
awk 'BEGIN { print "P3"; print 48, 40; print 255
    for (y = 0; y < 40; y++) for (x = 0; x < 48; x++) { v = ((x * 5 + y * 3) % 7) * 4
        if (y % 10 < 5) print 30 + v, 40 + v, 90 + v; else print 200 - v, 210 - v, 230 } }' > "$tmp/stripes.ppm"
for v in 0 255; do
    awk -v v=$v 'BEGIN { print "P2"; print 48, 48; print 255; for (i = 0; i < 48 * 48; i++) print v }' > "$tmp/mask$v.pgm"
done
awk 'BEGIN { print "P2"; print 20, 20; print 255; for (i = 0; i < 400; i++) print (i % 3) ? 0 : 255 }' > "$tmp/small.pgm"
printf 'this is not an image\n' > "$tmp/junk.ppm"

spots="$tmp/spots.ppm"
stripes="$tmp/stripes.ppm"
keys="--key $spots:$tmp/spots_mask.pgm --key $stripes"

# ---- usage -------------------------------------------------------------------

if "$bin" pgp-tile --help > "$tmp/help" 2>&1 && grep -q -- '--out-slices' "$tmp/help" && grep -q -- '--single' "$tmp/help"
then pass help; else fail help "no option list (or non-zero exit)"; fi
if "$bin" --help | grep -q '^  pgp-tile '; then pass listed; else fail listed "pgp-tile is not in patchwork --help"; fi

# ---- a run with every output ------------------------------------------------------

o="$tmp/all"
mkdir -p "$o"
if tile outputs $keys --layers 4 --size 32 --out "$o/t.nrrd" --out-slices "$o/s" --out-masks "$o/m.ppm"; then
    if grep -q '^pgp-tile: 4 layers of 32x32 texels, 3 channels, from 2 keys$' "$tmp/outputs.log"; then pass summary
    else fail summary "$(cat "$tmp/outputs.log")"; fi
    if [ "$(head -1 "$o/t.nrrd")" = NRRD0004 ] && [ "$(nrrd_field "$o/t.nrrd" sizes)" = "3 32 32 4" ] &&
       [ "$(nrrd_field "$o/t.nrrd" type)" = uint8 ] && [ "$(wc -c < "$o/t.nrrd")" -gt 12288 ]
    then pass nrrd; else fail nrrd "header: $(head -c 200 "$o/t.nrrd" | head -6 | tr '\n' '|')"; fi
    ok=1
    for k in 00 01 02 03; do
        [ "$(png_size "$o/s_$k.png")" = 32x32 ] || ok=0
        [ "$(head -c 2 "$o/m_$k.ppm")" = P6 ] || ok=0
    done
    if [ $ok -eq 1 ] && [ ! -e "$o/s_04.png" ]; then pass slices; else fail slices "$(ls "$o" | tr '\n' ' ')"; fi
    if [ -z "$(ls "$o" | grep partial)" ]; then pass no_partial; else fail no_partial "$(ls "$o")"; fi
    # the mapping half reads the tile
    if "$bin" pgp --mesh procedural:sphere --tile "$o/t.nrrd" --size 64x48 --out-image "$o/r.png" > "$tmp/map.log" 2>&1 &&
       grep -q 'tile 32x32 with 4 layers' "$tmp/map.log"; then pass mapped; else fail mapped "$(cat "$tmp/map.log")"; fi
fi

# ---- determinism and options that matter -------------------------------------------------

run() { name=$1; shift; tile "$name" --size 32 --layers 4 --out "$tmp/$name.nrrd" "$@"; }
run base $keys && run again $keys && differs same_run "$tmp/base.nrrd" "$tmp/again.nrrd" same
run seed $keys --seed 3 && differs seed_matters "$tmp/base.nrrd" "$tmp/seed.nrrd"
run automask --key "$spots" --key "$stripes" && differs given_mask_matters "$tmp/base.nrrd" "$tmp/automask.nrrd"
run bright --key "$spots" --key "$stripes" --mask-mode bright && differs mask_mode_matters "$tmp/automask.nrrd" "$tmp/bright.nrrd"
run uniform $keys --uniform && differs uniform_matters "$tmp/base.nrrd" "$tmp/uniform.nrrd"
run single --key "$spots" --single && [ "$(nrrd_field "$tmp/single.nrrd" sizes)" = "3 32 32 4" ] && pass single
if tile layers $keys --size 24 --layers 3 --out "$tmp/layers.nrrd" && [ "$(nrrd_field "$tmp/layers.nrrd" sizes)" = "3 24 24 3" ]
then pass size_and_layers; else fail size_and_layers "$(nrrd_field "$tmp/layers.nrrd" sizes)"; fi
if tile three --key "$spots" --key "$stripes" --key "$spots" --size 24 --layers 5 --out "$tmp/three.nrrd" &&
   [ "$(nrrd_field "$tmp/three.nrrd" sizes)" = "3 24 24 5" ]; then pass three_keys; else fail three_keys "no 5-layer tile"; fi

# ---- real exemplars ------------------------------------------------------------------------

leo="$data/textures/leopard.ppm"
str="$data/textures/Stripes2px.pam"
if [ -f "$leo" ] && [ -f "$str" ]; then
    if tile real --key "$leo" --key "$str" --key "$leo" --size 64 --layers 5 --out "$tmp/real.nrrd" --out-slices "$tmp/real" &&
       [ "$(nrrd_field "$tmp/real.nrrd" sizes)" = "4 64 64 5" ] && [ "$(png_size "$tmp/real_04.png")" = 64x64 ]
    then pass real_spots_stripes_spots; else fail real_spots_stripes_spots "$(nrrd_field "$tmp/real.nrrd" sizes)"; fi
else
    skip real_spots_stripes_spots "$leo or $str absent (run \`make data\`)"
fi

# ---- bad input -------------------------------------------------------------------------------

out="--out $tmp/out/t.nrrd"
expect_error no_out '--out FILE.nrrd is required' $keys
expect_error out_not_nrrd 'give a .nrrd file' $keys --out "$tmp/out/t.png"
expect_error one_key 'a morph needs two or more --key (1 given' --key "$spots" $out
expect_error single_two_keys '--single takes exactly one --key (2 given)' $keys --single $out
expect_error not_an_image 'unknown image format' --key "$tmp/junk.ppm" --key "$stripes" $out
expect_error missing_file 'cannot open' --key "$tmp/nope.ppm" --key "$stripes" $out
expect_error missing_mask 'cannot open' --key "$spots:$tmp/nope.pgm" --key "$stripes" $out
expect_error empty_mask 'key 0 mask: no feature texel (empty mask)' --key "$spots:$tmp/mask0.pgm" --key "$stripes" $out
expect_error full_mask 'key 0 mask: every texel is a feature' --key "$spots:$tmp/mask255.pgm" --key "$stripes" $out
expect_error mask_size 'key 0: the mask is 20x20 but the image 48x48' --key "$spots:$tmp/small.pgm" --key "$stripes" $out
expect_error too_few_layers '2 layers for 3 keys' $keys --key "$spots" --layers 2 $out
expect_error bad_layers "not a whole number in 1..1024" $keys --layers 0 $out
expect_error bad_size "not a whole number in 16..4096" $keys --size 8 $out
expect_error bad_mask_mode "mask-mode: 'stripy' is not valid" $keys --mask-mode stripy $out
expect_error same_slices 'name the same files' $keys $out --out-slices "$tmp/out/a" --out-masks "$tmp/out/a.png"
expect_error unknown_option "unknown option '--frobnicate'" $keys $out --frobnicate
expect_error unwritable 'cannot write there (No such file or directory)' $keys --size 16 --layers 2 --out "$tmp/out/no/such/dir/t.nrrd"
