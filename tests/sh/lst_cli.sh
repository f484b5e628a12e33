#!/bin/sh
# `patchwork lst` tests: every output and its format (the model file's
# structure, masks as NRRD, TetGen and MEDIT meshes, images), determinism,
# the options that must change the result (type, seed, constraints, manual
# pastes, cuts, views), meshes and exemplars read back from the files the
# command wrote, and clear one-line errors (no crash, no output or
# .partial file left behind) on bad input of every kind.
suite=lst_cli cmd=lst
. "$(dirname "$0")/lib.sh"

# run NAME ARGS...: `patchwork lst ARGS` must exit 0 with a quiet stderr.
run() { run_ok "$@"; }

# reported LOG: the tetrahedron count of "lst: N tetrahedra, ..."
reported() { sed -n 's/^lst: \([0-9]*\) tetrahedra,.*/\1/p' "$1"; }

# check_lst FILE NEXEMPLARS: validates a model file (src/lst/io.c); prints
# nothing when valid, else what is wrong.
check_lst() {
    awk -v nex="$2" '
    function bad(m) { if (err == "") err = "line " NR ": " m }
    function isint(s) { return s ~ /^[0-9]+$/ }
    function isnum(s) { return s ~ /^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$/ }
    err != "" { next }
    NR == 1 { if ($0 != "lst 1") bad("bad magic"); state = "nodes"; next }
    state == "nodes" { if ($1 != "nodes" || !isint($2)) bad("expected nodes"); nn = $2; k = 0; state = nn ? "node" : "tets"; next }
    state == "node" { if (NF != 3 || !isnum($1) || !isnum($2) || !isnum($3)) bad("bad node"); if (++k == nn) state = "tets"; next }
    state == "tets" { if ($1 != "tets" || !isint($2)) bad("expected tets"); nt = $2; k = 0; state = nt ? "tet" : "ex"; next }
    state == "tet" { if (NF != 4) bad("bad tet"); for (i = 1; i <= 4; i++) if (!isint($i) || $i >= nn) bad("bad node index");
                     if (++k == nt) state = "ex"; next }
    state == "ex" { if ($1 != "exemplars" || $2 != nex) bad("expected exemplars " nex); ne = $2; k = 0; state = "exl"; next }
    state == "exl" { if ($1 != "exemplar" || $2 != k || NF != 5) bad("bad exemplar line"); if (++k == ne) state = "pastes"; next }
    state == "pastes" { if ($1 != "pastes" || !isint($2)) bad("expected pastes"); np = $2; p = 0; state = np ? "paste" : "end"; next }
    state == "paste" { if ($1 != "paste" || !isint($2) || $2 >= ne || !isint($3) || $3 < 1) bad("bad paste header");
                       left = $3; state = "entry"; next }
    state == "entry" { if (NF != 13 || !isint($1) || $1 >= nt) bad("bad entry");
                       for (i = 2; i <= 13; i++) if (!isnum($i)) bad("bad coordinate");
                       entries++; if (--left == 0) { p++; state = p == np ? "end" : "paste" } next }
    state == "end" { bad("text after the last paste") }
    END { if (err == "" && state != "end") err = "truncated in state " state; if (err != "") print err; else if (entries == 0) print "no entries" }
    ' "$1"
}



# ---- the whole pipeline ------------------------------------------------------

o=$tmp/k
kiwi="--mesh procedural:kiwi --exemplar procedural:kiwi --exemplar-size 32 --type 2b --depth procedural:kiwi
      --directions procedural:kiwi --tet-count 1500 --tet-uniform"
if run all $kiwi --cut "0 0 1 0.1" --out-lst $o.lst --out-masks $o.mask --out-tets $o.node --out-image $o.png \
       --out-section $o.sec.png --out-volume $o.vol.png --out-exemplar $o.ex.nrrd --size 160x120 --slices 20; then
    nt=$(reported "$tmp/all.log")
    bad=$(check_lst $o.lst 3)
    if [ -n "$bad" ]; then fail model_file "$bad"; else pass model_file; fi
    if [ "$(head -1 $o.mask0.nrrd)" = "NRRD0004" ] && [ -f $o.mask2.nrrd ] && [ ! -f $o.mask3.nrrd ]; then pass masks
    else fail masks "expected three NRRD masks"; fi
    if [ "$(grep -v '^#' $o.node | head -1 | awk '{ print $2 }')" = 3 ] &&
       [ "$(grep -v '^#' $o.ele | head -1 | awk '{ print $1 }')" = "$nt" ]; then pass out_tets
    else fail out_tets "the .node/.ele headers do not match $nt tetrahedra"; fi
    ok=1
    for f in $o.png $o.sec.png $o.vol.png; do is_png "$f" && [ "$(png_size "$f")" = 160x120 ] || ok=0; done
    if [ $ok = 1 ]; then pass images; else fail images "a rendering is not a 160x120 PNG"; fi
    grep -q '^lst: cut in' "$tmp/all.log" && pass cut_reported || fail cut_reported "no cut line"
    grep -q 'dihedral angles' "$tmp/all.log" && pass dihedral_reported || fail dihedral_reported "no dihedral angles"
fi

# ---- determinism and options that must matter --------------------------------

small="--mesh procedural:sphere --tet-count 800 --tet-uniform --exemplar procedural:spots --exemplar-size 16"
run det1 $small --out-lst $tmp/d1.lst --out-image $tmp/d1.png --size 64x48 &&
run det2 $small --out-lst $tmp/d2.lst --out-image $tmp/d2.png --size 64x48 &&
if cmp -s $tmp/d1.lst $tmp/d2.lst && cmp -s $tmp/d1.png $tmp/d2.png; then pass determinism; else fail determinism "outputs differ"; fi
run seed $small --seed 5 --out-lst $tmp/d3.lst && { cmp -s $tmp/d1.lst $tmp/d3.lst && fail seed "same model" || pass seed; }
run type1b $small --type 1b --out-lst $tmp/d4.lst && { [ "$(sed -n 's/^exemplars //p' $tmp/d4.lst)" = 3 ] && pass type_1b_masks || fail type_1b_masks "not 3 exemplars"; }
for t in 1a 2a; do run "type$t" $small --type $t --out-lst $tmp/t$t.lst && pass "type_$t"; done
run paste $small --paste "0 0 0 1 0 0 0 1 0 0.8" --out-lst $tmp/d5.lst &&
if [ "$(sed -n 's/^pastes //p' $tmp/d5.lst)" -gt "$(sed -n 's/^pastes //p' $tmp/d1.lst)" ]; then pass manual_paste; else fail manual_paste "no extra paste"; fi
run stroke $small --cut-stroke "0.2 -0.8 0 0.2 0.8 0" --view 0,0,-1 --out-lst $tmp/d6.lst &&
maxx=$(awk '$1 == "nodes" { n = $2; next } n > 0 { if ($1 > m || m == "") m = $1; n-- } END { print m }' $tmp/d6.lst)
if awk -v m="$maxx" 'BEGIN { exit !(m < 0.21) }'; then pass cut_stroke; else fail cut_stroke "a node at x = $maxx is right of the stroke"; fi
run show $small --show pastes --out-image $tmp/d7.png --size 64x48 && { cmp -s $tmp/d1.png $tmp/d7.png && fail show "same image" || pass show; }
printf 'fill 0 0\npoint 0 0 0 1\n' > $tmp/depth.txt
printf 'dir 0 0 0 0 0 1\nscale 0 0 0 0.5\n' > $tmp/dirs.txt
run files $small --type 2b --depth $tmp/depth.txt --directions $tmp/dirs.txt --out-lst $tmp/d8.lst && pass constraint_files
cat $tmp/depth.txt $tmp/dirs.txt > $tmp/both.txt
run one_file $small --type 2b --constraints $tmp/both.txt --out-lst $tmp/d9.lst &&
if cmp -s $tmp/d8.lst $tmp/d9.lst; then pass constraints_one_file; else fail constraints_one_file "--constraints gives another model"; fi
run surface $small --out-surface $tmp/s.obj &&
if grep -q '^v ' $tmp/s.obj && [ "$(grep -c '^f [0-9]* [0-9]* [0-9]*$' $tmp/s.obj)" -gt 100 ]; then pass out_surface
else fail out_surface "no vertices or triangles in $tmp/s.obj"; fi
run atlas $small --cut "0 0 1 0" --out-glb $tmp/g.glb --out-obj $tmp/g.obj --out-atlas $tmp/g.png --atlas-size 128 &&
if [ "$(head -c 4 $tmp/g.glb)" = glTF ] && grep -q '^vt ' $tmp/g.obj && grep -q '^f [0-9]*/[0-9]* ' $tmp/g.obj &&
    grep -q '^map_Kd g.png$' $tmp/g.mtl && grep -q 'atlas of [0-9]* charts, [0-9]*% of 128x128 filled' $tmp/atlas.log
then pass out_glb_obj_atlas; else fail out_glb_obj_atlas "$(tail -1 $tmp/atlas.log)"; fi

# ---- what the fill reports; self-intersecting surfaces ------------------------------

# Two octahedra overlapping along x: closed, consistently oriented, crossing.
oct() { # X: the 6 vertices of an octahedron of radius 1 centred at (X, 0, 0)
    printf '%s 0 0\n%s 0 0\n%s 1 0\n%s -1 0\n%s 0 1\n%s 0 -1\n' $(($1 + 1)) $(($1 - 1)) $1 $1 $1 $1
}
octf() { # B: its 8 triangles, counter-clockwise seen from outside, vertex numbers from B
    for f in "0 2 4" "2 1 4" "1 3 4" "3 0 4" "2 0 5" "1 2 5" "3 1 5" "0 3 5"; do
        echo $f | awk -v b=$1 '{ print 3, $1 + b, $2 + b, $3 + b }'
    done
}
{ printf 'OFF\n12 16 0\n'; oct 0; oct 1; octf 0; octf 6; } > $tmp/cross.off
cross="--mesh $tmp/cross.off --tet-count 2000 --exemplar procedural:spots --exemplar-size 16"
"$bin" lst $cross --out-lst $tmp/c1.lst > $tmp/cross.log 2> $tmp/cross.err
if [ $? -eq 0 ] && grep -q 'crosses itself ([0-9]* triangle pairs)' $tmp/cross.err && [ "$(wc -l < $tmp/cross.err)" -eq 1 ]
then pass crossing_filled; else fail crossing_filled "$(head -2 $tmp/cross.err | tr '\n' '|')"; fi
if grep -q '^lst: [0-9]* tetrahedra, [0-9]* vertices, boundary within [0-9.]*% of the surface (99%: [0-9.]*%), 1 piece,' \
    $tmp/cross.log; then pass fit_reported; else fail fit_reported "$(head -1 $tmp/cross.log)"; fi
"$bin" lst --mesh procedural:dumbbell --tet-count 3000 --tet-uniform --exemplar procedural:spots --exemplar-size 16 \
    --out-lst $tmp/db.lst > $tmp/db.log 2> $tmp/db.err
if [ $? -eq 0 ] && grep -q 'warning: the tetrahedra make 2 pieces where the surface encloses 1' $tmp/db.err
then pass pieces_warning; else fail pieces_warning "$(head -2 $tmp/db.err | tr '\n' '|')"; fi
# the default graded lattice keeps the neck: one piece, within 0.5% of the diagonal, no warning
"$bin" lst --mesh procedural:dumbbell --tet-count 3000 --exemplar procedural:spots --exemplar-size 16 \
    --out-lst $tmp/dg.lst > $tmp/dg.log 2> $tmp/dg.err
fit=$(sed -n 's/.*boundary within \([0-9.]*\)% .*/\1/p' $tmp/dg.log)
if [ -n "$fit" ] && grep -q ', 1 piece,' $tmp/dg.log && [ ! -s $tmp/dg.err ] &&
    awk -v f="$fit" 'BEGIN { exit !(f < 0.5) }'
then pass graded_keeps_neck; else fail graded_keeps_neck "$(head -1 $tmp/dg.log) $(head -1 $tmp/dg.err)"; fi
"$bin" lst --mesh procedural:dumbbell --tet-count 3000 --tet-fit 0.02 --exemplar procedural:spots --exemplar-size 16 \
    --out-lst $tmp/dl.lst > $tmp/dl.log 2>&1
n1=$(sed -n 's/^lst: \([0-9]*\) tetrahedra.*/\1/p' $tmp/dg.log)
n2=$(sed -n 's/^lst: \([0-9]*\) tetrahedra.*/\1/p' $tmp/dl.log)
if [ -n "$n1" ] && [ -n "$n2" ] && [ "$n2" -lt "$n1" ]; then pass tet_fit; else fail tet_fit "counts $n1 / $n2"; fi
expect_error bad_tet_fit "tet-fit" --mesh procedural:sphere --tet-fit 0.5 --exemplar procedural:spots --out-lst $tmp/out/x.lst
"$bin" lst $cross --allow-self-intersections --out-lst $tmp/c2.lst > /dev/null 2>&1
if cmp -s $tmp/c1.lst $tmp/c2.lst; then pass allow_is_default; else fail allow_is_default "outputs differ"; fi

# ---- inputs read back from the command's own outputs ------------------------------

if [ -f $o.node ]; then
    run tets_node --tets $o.node --exemplar $o.ex.nrrd --out-image $tmp/r1.png --size 64x48 &&
    [ "$(reported "$tmp/tets_node.log")" = "$nt" ] && pass tets_node_read
    run out_mesh --tets $o.node --exemplar procedural:layers --exemplar-size 16 --out-tets $tmp/r.mesh &&
    run tets_mesh --tets $tmp/r.mesh --exemplar procedural:layers --exemplar-size 16 --type 1b --out-lst $tmp/r.lst &&
    [ "$(reported "$tmp/tets_mesh.log")" = "$nt" ] && pass tets_medit_read
fi

# ---- errors ------------------------------------------------------------------------

mkdir -p "$tmp/out"
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 3 1\n' > $tmp/open.off
printf 'face 0 0\nfill x 1\n' > $tmp/baddepth.txt
printf 'stroke 1 0 0 0 0 0 1\n' > $tmp/oldstroke.txt
printf 'NRRD0004\ntype: float\n' > $tmp/bad.nrrd
expect_error no_input "required" --exemplar procedural:spots --out-lst $tmp/out/x.lst
expect_error no_output "nothing to write" $small
expect_error unknown_option "unknown option" $small --frobnicate --out-lst $tmp/out/x.lst
expect_error bad_type "--type" $small --type 3c --out-lst $tmp/out/x.lst
# a 2D image as the exemplar: refused by name, before the tetrahedralization
printf 'P6\n2 2\n255\n%012d' 0 > "$tmp/flat.ppm"
expect_error flat_exemplar "2D image" --mesh procedural:sphere --exemplar "$tmp/flat.ppm" --out-image $tmp/out/x.png
if [ -s "$tmp/stdout" ]; then fail flat_exemplar_first "worked before refusing: $(head -1 "$tmp/stdout")"; else pass flat_exemplar_first; fi
expect_error bad_cut "--cut" $small --cut "1 2 3" --out-lst $tmp/out/x.lst
expect_error section_needs_cut "needs a --cut" $small --out-section $tmp/out/x.png
expect_error missing_mesh "cannot open" --mesh $tmp/none.off --exemplar procedural:spots --out-lst $tmp/out/x.lst
expect_error open_mesh "not closed: 4 boundary edges in 1 hole (the largest: 4 edges" --mesh $tmp/open.off --exemplar procedural:spots --out-lst $tmp/out/x.lst
expect_error strict "intersects itself: [0-9]* triangle pairs cross" $cross --strict --out-lst $tmp/out/x.lst
expect_error unknown_surface "unknown built-in surface" --mesh procedural:cube --exemplar procedural:spots --out-lst $tmp/out/x.lst
expect_error unknown_exemplar "unknown built-in exemplar" $small --exemplar procedural:marble --out-lst $tmp/out/x.lst
expect_error bad_nrrd "bad.nrrd" --mesh procedural:sphere --tet-count 800 --exemplar $tmp/bad.nrrd --out-lst $tmp/out/x.lst
expect_error bad_depth "baddepth.txt:2" $small --type 1b --depth $tmp/baddepth.txt --out-lst $tmp/out/x.lst
expect_error old_stroke "oldstroke.txt:1: 'stroke' is ambiguous: write 'depth-stroke" $small --type 1b --constraints $tmp/oldstroke.txt --out-lst $tmp/out/x.lst
expect_error out_surface_extension "--out-surface" $small --out-surface $tmp/out/x.off
expect_error tets_extension "--tets" --tets $tmp/x.off --exemplar procedural:spots --out-lst $tmp/out/x.lst
expect_error out_tets_extension "--out-tets" $small --out-tets $tmp/out/x.vtk
expect_error paste_outside "outside the model" $small --paste "5 0 0 1 0 0 0 1 0 0.5" --out-lst $tmp/out/x.lst
expect_error cut_everything "cut away" $small --cut "1 0 0 -5" --out-image $tmp/out/x.png
expect_error glb_extension "give a .glb file" $small --out-glb $tmp/out/x.gltf
expect_error obj_needs_atlas "--out-obj and --out-atlas go together" $small --out-obj $tmp/out/x.obj
expect_error glb_cut_everything "cut away" $small --cut "1 0 0 -5" --out-glb $tmp/out/x.glb
expect_error same_file "two outputs" $small --out-image $tmp/out/x.png --out-volume $tmp/out/x.png --slices 2

# --out-exemplar alone writes a built-in exemplar without filling anything
if "$bin" lst --exemplar procedural:layers --exemplar-size 16 --out-exemplar "$tmp/layers.nrrd" > "$tmp/stdout" 2>&1 &&
    head -c 8 "$tmp/layers.nrrd" | grep -q NRRD0004 && grep -q 'sizes: 3 16 16 16' "$tmp/layers.nrrd" &&
    ! grep -q 'tetrahedra' "$tmp/stdout"; then pass exemplar_only
else fail exemplar_only "$(tail -1 "$tmp/stdout")"; fi
