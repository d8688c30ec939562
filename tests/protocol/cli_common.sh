# What the command-line scripts of tests/protocol share, sourced after they set `name`: a
# temporary folder `$out` removed at exit, `fail MESSAGE`, and `expect STATUS PATTERN`, which checks
# the last run's exit status (`$status`) and that its output (`$log`) has a line matching PATTERN.
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "$name: $*" >&2; exit 1; }
expect() {
  [ "$status" -eq "$1" ] || fail "exit status $status, expected $1"
  grep -Eq -- "$2" <<< "$log" || fail "no line matching: $2"
}
