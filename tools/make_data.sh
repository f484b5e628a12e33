#!/bin/sh
# make data: real test data from installed Debian packages, converted into
# data/ (git-ignored). Whatever is absent is skipped with a message; the
# tests that need it skip too.
#   data/meshes/*.off *.ply   CGAL's mesh corpus   (package libcgal-demo)
#   data/textures/*.ppm        GIMP's patterns      (gimp-data, gimp-data-extras);
#   data/textures/*.pam        those with transparency, alpha kept
# Usage: tools/make_data.sh path/to/patchwork
set -u
cli=${1:-build/patchwork}
mkdir -p data/meshes data/textures

cgal=""
for f in /usr/share/doc/libcgal-demo/data.tar.gz /usr/share/doc/libcgal-dev/data.tar.gz \
         /usr/share/doc/libcgal-dev/examples/data.tar.gz; do
    if [ -f "$f" ]; then cgal=$f; break; fi
done
if [ -n "$cgal" ]; then
    tmp=$(mktemp -d)
    tar -xzf "$cgal" -C "$tmp" 2>/dev/null
    find "$tmp" -path '*/meshes/*' \( -name '*.off' -o -name '*.ply' \) -exec cp {} data/meshes/ \;
    rm -rf "$tmp"
    echo "make data: $(ls data/meshes | wc -l) meshes from $cgal into data/meshes/"
else
    echo "make data: CGAL's data.tar.gz not found (apt-get install libcgal-demo): no meshes"
fi

n=0
if [ -d /usr/share/gimp/2.0/patterns ]; then
    for p in $(find /usr/share/gimp/2.0/patterns -name '*.pat' | sort); do
        name=$(basename "$p" .pat)
        if "$cli" convert "$p" "data/textures/$name.ppm" >/dev/null; then n=$((n + 1)); fi
        # PPM has no alpha: patterns drawn in their alpha channel (the stripes)
        # are also kept whole, as PAM
        if "$cli" convert "$p" "data/textures/$name.pam" >/dev/null &&
            ! head -c 100 "data/textures/$name.pam" | grep -q '_ALPHA'; then rm -f "data/textures/$name.pam"; fi
    done
    echo "make data: $n GIMP patterns converted into data/textures/"
else
    echo "make data: /usr/share/gimp/2.0/patterns not found (apt-get install gimp-data gimp-data-extras): no textures"
fi
