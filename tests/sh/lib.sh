# What the shell tests share; a test sets `suite` (the name before the
# slash of its PASS/FAIL/SKIP lines) and, for expect_error, `cmd` (the
# patchwork subcommand, empty for none), then sources this file:
#     suite=pgp_cli cmd=pgp
#     . "$(dirname "$0")/lib.sh"
# It sets bin (the patchwork command of the build under test) and tmp (a
# folder removed on exit).
bin=${BUILD:-build}/patchwork
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
pass() { echo "PASS $suite/$1"; }
fail() { echo "FAIL $suite/$1: $2"; }
skip() { echo "SKIP $suite/$1: $2"; }

# NAME PATTERN ARGS...: `patchwork $cmd ARGS` must fail as the CLI fails:
# exit status 1, one line on stderr that contains PATTERN, and no file left
# in $tmp/out (give outputs there).
expect_error() {
    name=$1 pattern=$2
    shift 2
    rm -rf "$tmp/out" && mkdir -p "$tmp/out"
    "$bin" $cmd "$@" > "$tmp/stdout" 2> "$tmp/stderr"
    status=$?
    lines=$(wc -l < "$tmp/stderr")
    left=$(ls -A "$tmp/out" | wc -l)
    if [ $status -ge 128 ]; then fail "$name" "crashed (exit status $status): $(head -3 "$tmp/stderr" | tr '\n' '|')"
    elif [ $status -ne 1 ]; then fail "$name" "exit status $status, expected 1"
    elif [ "$lines" -ne 1 ]; then fail "$name" "$lines lines on stderr: $(head -3 "$tmp/stderr" | tr '\n' '|')"
    elif ! grep -q -- "$pattern" "$tmp/stderr"; then fail "$name" "stderr lacks '$pattern': $(cat "$tmp/stderr")"
    elif [ "$left" -ne 0 ]; then fail "$name" "left files behind: $(ls -A "$tmp/out" | tr '\n' ' ')"
    else pass "$name"; fi
}

is_png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ]; }

# WxH of a PNG (nothing for another file)
png_size() {
    is_png "$1" || return 0
    od -An -tu1 -j16 -N8 "$1" | awk '{ printf "%dx%d\n", (($1*256+$2)*256+$3)*256+$4, (($5*256+$6)*256+$7)*256+$8 }'
}

# NAME ARGS...: `patchwork $cmd ARGS` must succeed with nothing on stderr;
# its output in $tmp/NAME.log and .err.
run_ok() {
    name=$1
    shift
    "$bin" $cmd "$@" > "$tmp/$name.log" 2> "$tmp/$name.err"
    status=$?
    if [ $status -ne 0 ]; then fail "$name" "exit status $status: $(head -2 "$tmp/$name.err" | tr '\n' '|')"; return 1; fi
    if [ -s "$tmp/$name.err" ]; then fail "$name" "stderr not empty: $(head -2 "$tmp/$name.err" | tr '\n' '|')"; return 1; fi
    return 0
}
