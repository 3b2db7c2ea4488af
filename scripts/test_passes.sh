#!/usr/bin/env bash
# The suite's three passes (`make test`); the first two run at once:
#   in front, at normal priority: the tests that time what a user feels on a real clock (`measures`: most
#     are browser tests) and the `alone` ones, one at a time;
#   behind, at the lowest CPU priority (nice 19): every other test outside tests/browser, on two workers;
#   then: the other browser tests on two workers (a module per worker, sharing its Chromium and pendants).
# The timed pass mostly waits on its real clock (a 10 s hold, a path drawn at a hand's pace, a 3 s look at
# a stopped arm): the tests behind it fill that idle CPU, and niced they never take a core it wants (Linux
# gives a nice-19 task about 1/70 of a normal one's share), so its figures are taken as on an idle machine.
# The browser tests without figures stay out of that overlap: Chromium's software WebGL wants both cores.
# The pass behind writes to test-artifacts/behind.log, shown when it is done; each pass prints its count.
set -uo pipefail
bin=${BIN:-.venv/bin}
read -r -a extra <<<"${PYTEST_ARGS:-}"
mkdir -p test-artifacts
behind_log=test-artifacts/behind.log

nice -n 19 "$bin/pytest" -q -n 2 --dist worksteal --ignore=tests/browser -m "not measures" "${extra[@]}" >"$behind_log" 2>&1 &
behind=$!
# Whoever stops `make test` (Ctrl-C, CI's time-out) stops the pass behind too: it is in our process group.
trap 'trap - INT TERM; kill 0' INT TERM

"$bin/pytest" -q -m "measures or alone" --reruns 1 tests "${extra[@]}"
front=$?
echo "== the timed tests: exit $front; the tests outside tests/browser (run behind them, nice 19):"
wait "$behind"
behind_status=$?
cat "$behind_log"
echo "== the tests outside tests/browser: exit $behind_status; the other browser tests:"

"$bin/pytest" -q -n 2 --dist loadfile -m "not measures and not alone" --reruns 1 tests/browser "${extra[@]}"
rest=$?
[ "$front" -eq 0 ] && [ "$behind_status" -eq 0 ] && [ "$rest" -eq 0 ]
