#!/bin/sh
# Another project's corpus: every OBJ, OFF, PLY and STL file under
# /usr/share/assimp/models (Debian's assimp-testmodels), the malformed and
# invalid ones included, goes through `patchwork pgp` and `patchwork tiled`.
# Each run either succeeds (status 0, the output written) or fails cleanly
# (status 1, one line on stderr naming the problem, nothing left behind);
# no crash, no hang. Files under invalid/ must fail. Skipped when the
# package is absent.
suite=assimp_corpus cmd=
. "$(dirname "$0")/lib.sh"
root=/usr/share/assimp/models
if [ ! -d "$root" ]; then
    skip corpus "$root absent (Debian package assimp-testmodels)"
    exit 0
fi
list=$(find "$root" -type f \( -iname '*.obj' -o -iname '*.off' -o -iname '*.ply' -o -iname '*.stl' \) | sort)
loaded=0 refused=0 bad=0
for f in $list; do
    rel=${f#"$root"/}
    for cmd in pgp tiled; do
        rm -rf "$tmp/out" && mkdir -p "$tmp/out"
        if [ $cmd = pgp ]; then
            timeout 120 "$bin" pgp --mesh "$f" --tile procedural:stripes --size 48x36 --out-image "$tmp/out/x.png" \
                > /dev/null 2> "$tmp/err"
        else
            timeout 120 "$bin" tiled --mesh "$f" --out-obj "$tmp/out/x.obj" > /dev/null 2> "$tmp/err"
        fi
        status=$?
        lines=$(wc -l < "$tmp/err")
        left=$(ls "$tmp/out" | wc -l)
        case "$rel" in invalid/*) must_fail=1 ;; *) must_fail=0 ;; esac
        if [ $status -eq 0 ] && [ $must_fail -eq 0 ] && [ "$left" -gt 0 ]; then
            loaded=$((loaded + 1))
        elif [ $status -eq 1 ] && [ "$lines" -eq 1 ] && [ "$left" -eq 0 ] && grep -q "^patchwork $cmd: " "$tmp/err"; then
            refused=$((refused + 1))
        else
            bad=$((bad + 1))
            fail "$cmd/$rel" "status $status, $lines stderr lines, $left files left: $(head -2 "$tmp/err" | tr '\n' '|')"
        fi
    done
done
n=$(echo "$list" | wc -l)
echo "INFO assimp_corpus: $n files x 2 commands: $loaded runs succeeded, $refused refused cleanly, $bad wrong"
if [ $bad -eq 0 ] && [ $loaded -gt 0 ] && [ $refused -gt 0 ]; then pass corpus; else fail corpus "see above"; fi
