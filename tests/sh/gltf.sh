#!/bin/sh
# glTF output read by other people's programs. For tiled, lapped, pgp and
# lst results on built-in data (and on CGAL and GIMP data when `make data`
# has run; lst's after cuts, the cut faces included):
#   - `patchwork ... --out-glb` writes a .glb, the same run an OBJ and a PPM
#     rendering; the .glb is deterministic;
#   - gltf_roundtrip: the .glb read back matches the OBJ bit for bit (pgp:
#     its raw-coordinate file, --out-glb-st, whose (s, t) the OBJ holds; its
#     baked atlas has coordinates no OBJ of pgp's holds);
#   - gltf_validator: Khronos' glTF validator reports no error and no warning;
#   - gltf_view: three.js's GLTFLoader in headless Chromium, through the
#     camera the file carries, draws what patchwork drew (tests/js/view.mjs
#     states the bounds); not for pgp's raw coordinates, whose singular
#     triangles show seams by design.
# The node checks need `make js` (npm packages in tests/js/node_modules) and
# are skipped, saying so, without it; the view needs Debian's chromium.
# Also: a --out-glb that is not .glb is refused before any work.
suite=gltf cmd=
. "$(dirname "$0")/lib.sh"
js=$(dirname "$0")/../js

# NAME METHOD ARGS...: the glb, obj and ppm of one result (METHOD pgp-st:
# pgp's raw-coordinate file)
make_case() {
    name=$1 method=$2 glb=--out-glb
    shift 2
    case $method in
        tiled) extra="--out-obj $tmp/$name.obj --out-tiles $tmp/$name.tiles.png" ;;
        lapped | lst) extra="--out-obj $tmp/$name.obj --out-atlas $tmp/$name.atlas.png" ;;
        pgp) extra="" ;;
        pgp-st) extra="--out-obj $tmp/$name.obj" method=pgp glb=--out-glb-st ;;
    esac
    ambient=0.3 # the renderer's ambient light: lst_render's is 0.35
    [ "$method" = lst ] && ambient=0.35
    eval "ambient_$name=$ambient"
    if "$bin" "$method" "$@" $extra $glb "$tmp/$name.glb" --out-image "$tmp/$name.ppm" > "$tmp/$name.log" 2>&1 &&
        "$bin" "$method" "$@" $glb "$tmp/$name.again.glb" > /dev/null 2>&1 &&
        cmp -s "$tmp/$name.glb" "$tmp/$name.again.glb"; then
        pass "$name"
        cases="$cases $name"
        [ -n "$extra" ] && roundtrips="$roundtrips $name"
        [ "$glb" = --out-glb ] && views="$views $name"
    else
        fail "$name" "$(tail -1 "$tmp/$name.log") (or the second run's file differs)"
    fi
}

cases="" roundtrips="" views=""
make_case tiled_torus tiled --mesh procedural:torus --exemplar procedural:pebbles --size 400x300
make_case lapped_bumpy lapped --mesh procedural:bumpy --texture procedural:scales --size 400x300
make_case pgp_torus pgp --mesh procedural:torus --tile procedural:bricks --size 400x300
make_case pgp_torus_st pgp-st --mesh procedural:torus --tile procedural:bricks --size 400x300
# lst: the surface after cuts and the cut faces
make_case lst_kiwi_cut lst --mesh procedural:kiwi --type 2b --exemplar procedural:kiwi \
    --constraints procedural:kiwi --tet-count 4000 --tet-uniform --cut "1 0 0.3 0" --size 400x300
make_case lst_torus_cuts lst --mesh procedural:torus --exemplar procedural:spots --tet-count 3000 --tet-uniform \
    --cut "0 0 1 0.1" --cut "0.2 1 0 0.3" --size 400x300
data=$(dirname "$0")/../../data
if [ -f "$data/meshes/double-torus-example.off" ] && [ -f "$data/textures/leopard.ppm" ]; then
    make_case tiled_cgal_double_torus tiled --mesh "$data/meshes/double-torus-example.off" \
        --exemplar "$data/textures/leopard.ppm" --size 400x300
else
    echo "SKIP gltf/tiled_cgal_double_torus: needs make data (CGAL meshes, GIMP patterns)"
fi
if [ -f "$data/meshes/elephant.off" ] && [ -f "$data/textures/leopard.ppm" ]; then
    make_case lapped_cgal_elephant lapped --mesh "$data/meshes/elephant.off" --texture "$data/textures/leopard.ppm" \
        --size 400x300
else
    echo "SKIP gltf/lapped_cgal_elephant: needs make data (CGAL meshes, GIMP patterns)"
fi
if [ -f "$data/meshes/cow.off" ]; then
    make_case pgp_cgal_cow pgp --mesh "$data/meshes/cow.off" --tile procedural:bricks --size 400x300
else
    echo "SKIP gltf/pgp_cgal_cow: needs make data (CGAL meshes)"
fi
if [ -f "$data/meshes/elephant.off" ]; then
    make_case lst_cgal_elephant lst --mesh "$data/meshes/elephant.off" --exemplar procedural:spots --cut "0 0 1 0.05" \
        --size 400x300
else
    echo "SKIP gltf/lst_cgal_elephant: needs make data (CGAL meshes)"
fi

"$bin" tiled --mesh procedural:torus --exemplar procedural:pebbles --out-glb "$tmp/x.gltf" > /dev/null 2> "$tmp/err"
if [ $? -eq 1 ] && grep -q "give a .glb file" "$tmp/err" && [ ! -e "$tmp/x.gltf" ]; then pass bad_extension
else fail bad_extension "$(cat "$tmp/err")"; fi
"$bin" lst --mesh procedural:sphere --exemplar procedural:spots --out-glb "$tmp/x.gltf" > /dev/null 2> "$tmp/err"
if [ $? -eq 1 ] && grep -q "give a .glb file" "$tmp/err" && ! grep -q "lst: type" "$tmp/err" && [ ! -e "$tmp/x.gltf" ]; then
    pass lst_bad_extension
else fail lst_bad_extension "$(cat "$tmp/err")"; fi

if ! command -v node > /dev/null 2>&1 || [ ! -d "$js/node_modules/gltf-validator" ]; then
    echo "SKIP gltf/validator: node or tests/js/node_modules missing (apt-get install nodejs npm; make js)"
    exit 0
fi
for c in $roundtrips; do node "$js/roundtrip.mjs" "$tmp/$c.glb" "$tmp/$c.obj"; done
globs=""
for c in $cases; do globs="$globs $tmp/$c.glb"; done
node "$js/validate.mjs" $globs
chromium=${CHROMIUM:-/usr/bin/chromium}
if [ ! -x "$chromium" ]; then
    echo "SKIP gltf/view: no Chromium at $chromium (apt-get install chromium)"
    exit 0
fi
jobs=""
for c in $views; do jobs="$jobs $tmp/$c.glb:$tmp/$c.ppm:$(eval echo "\$ambient_$c")"; done
out=${GLTF_VIEW_OUT:-$tmp}
mkdir -p "$out"
CHROMIUM=$chromium node "$js/view.mjs" "$out" $jobs
