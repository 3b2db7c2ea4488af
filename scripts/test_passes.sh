#!/usr/bin/env bash
# The suite (`make test`): the checks and three passes of tests, one pass after another.
#   1. The tests that time what a user feels on a real clock (`measures`: jog shares, stop times, a hold
#      beside 30 viewers; most are browser tests) and the `alone` ones, one at a time, with nothing beside
#      them: their figures are the product's at the load it states (a page and its pendant, <= 3-4).
#   2. Every other test outside tests/browser on three workers (--dist worksteal), with the checks (ruff,
#      import-linter, mypy) beside them at nice 19. Alone on two workers it kept the load at ~2: its tests
#      wait on processes and clocks, and a third worker fills that wait.
#   3. The other browser tests on two workers, a module per worker (--dist loadfile: it shares its Chromium
#      and pendants, tests/browser/conftest.py).
# Each pass had the others beside it once, to fill the CPU the timed pass leaves while it waits on its
# clock. On this 2-core machine the suite's ~5,000 CPU-s keep both cores busy all along (the whole run took
# about as long as its CPU on two cores), so the overlap saved no time, and it failed tests: the timed pass's
# holds cut by the deadman beside the niced pass (1 Dec, a clean clone: J1 0.89 deg in a 10 s hold; the hold
# beside 30 viewers cut with the operator on time), and the niced pass starved by the browser tests' two
# Chromiums (1 Dec, CI: a dozen tests that start pendants failed at once).
# Each pass writes its log in test-artifacts/ and prints its count and its 15 slowest tests (where the ten
# minutes go); the last lines list every failure of every pass.
set -uo pipefail
bin=${BIN:-.venv/bin}
read -r -a extra <<<"${PYTEST_ARGS:-}"
mkdir -p test-artifacts

behind() { # name, command...: run the command at nice 19, its output to test-artifacts/<name>.log
    nice -n 19 "${@:2}" >"test-artifacts/$1.log" 2>&1
}
# Whoever stops `make test` (Ctrl-C, CI's time-out) stops what runs beside it too: it is in our process group.
trap 'trap - INT TERM; kill 0' INT TERM
failed=0
run_pass() { # name, log, pytest arguments...: one pass of tests, shown as it runs and kept in test-artifacts/
    local name=$1 log=$2
    "$bin/pytest" -q -rfER --durations=15 "${@:3}" "${extra[@]}" 2>&1 | tee "test-artifacts/$log.log"
    local status=${PIPESTATUS[0]}
    echo "== $name: exit $status"
    [ "$status" -eq 0 ] || failed=1
}

run_pass "the timed tests" timed-tests -m "measures or alone" --reruns 1 tests
behind checks make -s --no-print-directory lint layers typecheck &
checks=$!
run_pass "the tests outside tests/browser" tests -n 3 --dist worksteal --ignore=tests/browser -m "not measures and not alone"
wait "$checks"
status=$?
echo "== checks (beside them, nice 19): exit $status"
cat test-artifacts/checks.log
[ "$status" -eq 0 ] || failed=1
run_pass "the other browser tests" browser-tests -n 2 --dist loadfile -m "not measures and not alone" --reruns 1 tests/browser
# Every failure of every pass, last, where a truncated log still shows them, and every test run again
# (-rR: a rerun that passed is a flaky test, named here so it is seen).
echo "== failures, errors and reruns of all passes:"
grep -h -E "^(FAILED|ERROR|RERUN) " test-artifacts/timed-tests.log test-artifacts/tests.log test-artifacts/browser-tests.log || echo "none"
exit "$failed"
