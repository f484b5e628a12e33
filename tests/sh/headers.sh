#!/bin/sh
# Header checks: every generated header is current, compiles alone as C99
# and as C++ with warnings as errors, exports nothing when made static, can
# be included twice, compiles with PW_NO_RENDER, PW_NO_PNG and both, and all
# of them compile together in one translation unit (C++ and the
# allocator-macro variants through the front end only: -fsyntax-only). Generic over the Makefile's HEADERS list. The checks compile with
# their own flags, not the build's, so the sanitizer run (SANITIZE=1) skips
# them: plain `make test` runs them.
if [ "${SANITIZE:-0}" = 1 ]; then
    echo "SKIP headers: independent of the build flags, checked by the plain make test"
    exit 0
fi
CC=${CC:-cc}
CXX=${CXX:-c++}
suite=headers cmd=
. "$(dirname "$0")/lib.sh"
headers=$(make -s print-headers)

if make -s check-headers > "$tmp/log" 2>&1; then pass current; else fail current "$(head -1 "$tmp/log")"; fi

cflags="-std=c99 -Wall -Wextra -pedantic -Werror -I."
cxxflags="-x c++ -Wall -Wextra -Werror -I."
for h in $headers; do
    up=$(echo "$h" | tr 'a-z' 'A-Z')
    # declarations only, then twice with the implementation the second time
    printf '#include "%s.h"\n#include "%s.h"\n#define %s_IMPLEMENTATION\n#include "%s.h"\n#include "%s.h"\nint main(void) { return 0; }\n' \
        "$h" "$h" "$up" "$h" "$h" > "$tmp/alone.c"
    if $CC $cflags -o "$tmp/a.out" "$tmp/alone.c" -lm > "$tmp/log" 2>&1; then pass "$h/c99"; else fail "$h/c99" "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
    if $CXX $cxxflags -fsyntax-only "$tmp/alone.c" > "$tmp/log" 2>&1; then pass "$h/c++"; else fail "$h/c++" "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
    printf '#define %s_STATIC\n#define %s_IMPLEMENTATION\n#include "%s.h"\n' "$up" "$up" "$h" > "$tmp/static.c"
    if $CC $cflags -c -o "$tmp/static.o" "$tmp/static.c" > "$tmp/log" 2>&1; then
        exported=$(nm -g --defined-only "$tmp/static.o" | wc -l)
        if [ "$exported" -eq 0 ]; then pass "$h/static"; else fail "$h/static" "$exported symbols exported: $(nm -g --defined-only "$tmp/static.o" | head -3 | tr '\n' ' ')"; fi
    else
        fail "$h/static" "$(head -3 "$tmp/log" | tr '\n' ' ')"
    fi
    # custom allocator macros: all three, or a clear #error
    printf '#include <stdlib.h>\n#define PW_MALLOC(s) malloc(s)\n#define PW_REALLOC(p, s) realloc(p, s)\n#define PW_FREE(p) free(p)\n#define %s_IMPLEMENTATION\n#include "%s.h"\nint main(void) { return 0; }\n' "$up" "$h" > "$tmp/alloc.c"
    if $CC $cflags -fsyntax-only "$tmp/alloc.c" > "$tmp/log" 2>&1; then pass "$h/alloc_macros"; else fail "$h/alloc_macros" "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
    printf '#define PW_MALLOC(s) malloc(s)\n#define %s_IMPLEMENTATION\n#include "%s.h"\n' "$up" "$h" > "$tmp/half.c"
    if $CC $cflags -fsyntax-only "$tmp/half.c" > "$tmp/log" 2>&1; then fail "$h/alloc_macros_partial" "compiled with only PW_MALLOC defined";
    elif grep -q 'define all of PW_MALLOC' "$tmp/log"; then pass "$h/alloc_macros_partial"; else fail "$h/alloc_macros_partial" "$(head -2 "$tmp/log" | tr '\n' ' ')"; fi
    # compute-only builds: the renderer and/or PNG left out, the API still declared and linked
    for opts in PW_NO_RENDER PW_NO_PNG "PW_NO_RENDER PW_NO_PNG"; do
        tag=$(echo "$opts" | tr 'A-Z ' 'a-z+' | sed 's/pw_//g')
        printf '#define %s\n' $opts > "$tmp/compute.c"
        printf '#define %s_IMPLEMENTATION\n#include "%s.h"\nint main(void) { return 0; }\n' "$up" "$h" >> "$tmp/compute.c"
        if $CC $cflags -o "$tmp/a.out" "$tmp/compute.c" -lm > "$tmp/log" 2>&1; then pass "$h/$tag/c99"; else fail "$h/$tag/c99" "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
        if $CXX $cxxflags -fsyntax-only "$tmp/compute.c" > "$tmp/log" 2>&1; then pass "$h/$tag/c++"; else fail "$h/$tag/c++" "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
    done
    printf '#define PW_NO_STDIO\n#define %s_IMPLEMENTATION\n#include "%s.h"\nint main(void) { return 0; }\n' "$up" "$h" > "$tmp/nostdio.c"
    if $CC $cflags -o "$tmp/a.out" "$tmp/nostdio.c" -lm > "$tmp/log" 2>&1 && ! nm "$tmp/a.out" | grep -q ' U fopen'; then pass "$h/no_stdio"; else fail "$h/no_stdio" "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
done

# all headers in one translation unit, C and C++
: > "$tmp/all.c"
echo '#define PATCHWORK_IMPLEMENTATION' >> "$tmp/all.c"
for h in $headers; do echo "#include \"$h.h\"" >> "$tmp/all.c"; done
echo 'int main(void) { return 0; }' >> "$tmp/all.c"
if $CC $cflags -o "$tmp/a.out" "$tmp/all.c" -lm > "$tmp/log" 2>&1; then pass all_together_c99; else fail all_together_c99 "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
if $CXX $cxxflags -fsyntax-only "$tmp/all.c" > "$tmp/log" 2>&1; then pass all_together_c++; else fail all_together_c++ "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
# and all of them compute-only
{ printf '#define PW_NO_RENDER\n#define PW_NO_PNG\n'; cat "$tmp/all.c"; } > "$tmp/all_compute.c"
if $CC $cflags -o "$tmp/a.out" "$tmp/all_compute.c" -lm > "$tmp/log" 2>&1; then pass all_together_no_render+no_png_c99; else fail all_together_no_render+no_png_c99 "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
if $CXX $cxxflags -fsyntax-only "$tmp/all_compute.c" > "$tmp/log" 2>&1; then pass all_together_no_render+no_png_c++; else fail all_together_no_render+no_png_c++ "$(head -3 "$tmp/log" | tr '\n' ' ')"; fi
