#!/bin/sh
# Style checks on the sources the headers are made from (src/, cli/,
# examples/): the layout is clang-format's with the project's .clang-format
# (`make format` applies it), and no statement is a comma expression
# (clang's -Wcomma on each header's implementation; a comma still
# separates for-loop clauses and declarations). Both need clang tools;
# without them the checks are skipped. Independent of the build flags, so the
# sanitizer run skips them.
if [ "${SANITIZE:-0}" = 1 ]; then
    echo "SKIP style: independent of the build flags, checked by the plain make test"
    exit 0
fi
suite=style cmd=
. "$(dirname "$0")/lib.sh"

# The version the tree is formatted with: other versions lay out some
# constructs differently, so they skip rather than fail.
format_version=14
if ! command -v clang-format > /dev/null 2>&1; then
    skip format "clang-format is not installed"
elif [ "$(clang-format --version | sed -n 's/.*version \([0-9]*\).*/\1/p')" != "$format_version" ]; then
    skip format "clang-format $(clang-format --version | sed -n 's/.*version \([0-9.]*\).*/\1/p') is not $format_version, the version the tree is laid out with"
elif clang-format --dry-run --Werror $(make -s print-format-files) > "$tmp/log" 2>&1; then
    pass format
else
    fail format "$(grep -c 'warning:' "$tmp/log") places differ from clang-format, first: $(grep -m1 'warning:' "$tmp/log") (make format)"
fi

if ! command -v clang > /dev/null 2>&1; then
    skip comma "clang is not installed"
else
    for h in $(make -s print-headers); do
        up=$(echo "$h" | tr 'a-z' 'A-Z')
        printf '#define %s_IMPLEMENTATION\n#include "%s.h"\n' "$up" "$h" > "$tmp/$h.c"
        if clang -std=c99 -I. -Wcomma -Werror -fsyntax-only "$tmp/$h.c" > "$tmp/log" 2>&1; then
            pass "comma/$h"
        else
            fail "comma/$h" "$(grep -c 'misuse of comma' "$tmp/log") comma expressions, first: $(grep -m1 'error:' "$tmp/log")"
        fi
    done
fi

# Every part of a method compiles on its own (it includes what it uses),
# as C99 with warnings as errors: a header is its parts in order, but a
# reader opens one part at a time.
for h in $(make -s print-headers); do
    up=$(echo "$h" | tr 'a-z' 'A-Z')
    bad=""
    for p in src/$h/*.c; do
        ${CC:-cc} -std=c99 -Wall -Wextra -pedantic -Werror -fsyntax-only -D${up}_IMPLEMENTATION -I. "$p" > "$tmp/log" 2>&1 ||
            bad="$bad $(basename "$p"): $(grep -m1 'error' "$tmp/log")"
    done
    if [ -z "$bad" ]; then pass "parts_alone/$h"; else fail "parts_alone/$h" "$bad"; fi
done

# The same for every shared module (src/common/*.h and a method's own
# src/NAME/MODULE.h): it includes the modules it uses.
bad=""
for m in src/common/*.h src/*/*.h; do
    [ "$(basename "$m" .h)" = "$(basename "$(dirname "$m")")" ] && continue # the public API of a method
    printf '#include "%s"\n' "$m" > "$tmp/module.c"
    ${CC:-cc} -std=c99 -Wall -Wextra -pedantic -Werror -fsyntax-only -I. "$tmp/module.c" > "$tmp/log" 2>&1 ||
        bad="$bad $m: $(grep -m1 'error' "$tmp/log")"
done
if [ -z "$bad" ]; then pass modules_alone; else fail modules_alone "$bad"; fi
