# tests/integration/lib.bash — shared helpers for integration scripts (sourced, not a test).
: "${LUMESH:?LUMESH must point at the lumesh binary}"
failures=0
# LUMESH_TEST_LIGHT=1 (the sanitizer run of scripts/test.sh): the heavy scripts do less of the
# same (fewer worker counts, shorter runs); every behaviour is still checked.
light=${LUMESH_TEST_LIGHT:-0}
checks=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
# expect_exit CODE CMD... — run CMD, check its exit code.
expect_exit() {
  local want=$1; shift
  checks=$((checks + 1))
  "$@" >/dev/null 2>"${TMPDIR:-/tmp}/lumesh-it-err.$$"
  local got=$?
  [ "$got" = "$want" ] || fail "'$*' exited $got, expected $want: $(head -c 300 "${TMPDIR:-/tmp}/lumesh-it-err.$$")"
  rm -f "${TMPDIR:-/tmp}/lumesh-it-err.$$"
}
# expect_fail_line CMD... — CMD exits 1 and prints exactly one non-empty line on stderr besides
# progress lines (the phase meter's ", ... so far" / ", ... to go": on a loaded machine a phase
# before the error can last long enough for the heartbeat to speak).
expect_fail_line() {
  checks=$((checks + 1))
  local err
  err=$("$@" 2>&1 >/dev/null)
  local got=$?
  [ "$got" = 1 ] || fail "'$*' exited $got, expected 1 (stderr: $err)"
  local lines
  lines=$(printf '%s\n' "$err" | grep -v -E ', [^,]+ (so far|to go)$' | grep -c .)
  [ "$lines" = 1 ] || fail "'$*' printed $lines lines on stderr besides progress, expected 1: $err"
}
# run_out CMD... — CMD succeeds (a check); its stdout in $tmp/out.txt, its stderr in
# $tmp/err.txt (after scratch)
run_out() {
  checks=$((checks + 1))
  "$@" >"$tmp/out.txt" 2>"$tmp/err.txt" || fail "'$*' failed: $(head -c 300 "$tmp/err.txt")"
}
# wait_for SECONDS CMD... — run CMD every 0.2 s until it succeeds (0) or SECONDS have passed (1):
# for states a loaded machine reaches late, never a fixed sleep.
wait_for() {
  local end=$((SECONDS + $1)); shift
  until "$@"; do
    [ "$SECONDS" -lt "$end" ] || return 1
    sleep 0.2
  done
}
finish() {
  echo "$((checks - failures)) passed, $failures failed"
  [ "$failures" = 0 ]
}
# scratch — a fresh folder in $tmp and an empty $pids; at exit every process in $pids is killed
# (and reaped) and the folder removed (kept with KEEP_TMP=1, to look at after a failure). Scripts
# add the background processes they start to pids.
scratch() {
  tmp=$(mktemp -d)
  pids=()
  trap scratch_cleanup EXIT
}
scratch_cleanup() {
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null; done
  [ "${#pids[@]}" = 0 ] || wait "${pids[@]}" 2>/dev/null
  [ -n "${KEEP_TMP:-}" ] || rm -rf "$tmp"
}
