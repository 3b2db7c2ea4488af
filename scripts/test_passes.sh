#!/usr/bin/env bash
# The suite's three passes (`make test`), two of them at once:
#   in front, at normal priority: the browser tests that time what a user feels on a real clock
#     (`measures`) and the `alone` ones, one at a time;
#   behind, at the lowest CPU priority (nice 19): every other test on two workers, then the other browser
#     tests on two workers (a module per worker, sharing its Chromium and pendants).
# The timed pass waits mostly on its real clock (a 10 s hold, a path drawn at a hand's pace), so the other
# two fill its idle CPU; niced, they never take a core it wants (Linux gives a nice-19 task about 1/70 of a
# normal one's share), so its figures are measured as on an idle machine. Each pass prints its count; the
# pass behind writes to test-artifacts/behind.log, shown when both are done. Exit status: 0 when all passed.
set -uo pipefail
bin=${BIN:-.venv/bin}
extra=${PYTEST_ARGS:-}
mkdir -p test-artifacts
behind_log=test-artifacts/behind.log

# shellcheck disable=SC2086  # PYTEST_ARGS is a list of words
(
    nice -n 19 "$bin/pytest" -q -n 2 --dist worksteal --ignore=tests/browser $extra &&
        nice -n 19 "$bin/pytest" -q -n 2 --dist loadfile -m "not measures and not alone" --reruns 1 \
            tests/browser $extra
) >"$behind_log" 2>&1 &
behind=$!
# Whoever stops `make test` (Ctrl-C, CI's time-out) stops the pass behind too: it is in our process group.
trap 'trap - INT TERM; kill 0' INT TERM

# shellcheck disable=SC2086
"$bin/pytest" -q -m "measures or alone" --reruns 1 tests/browser $extra
front=$?
echo "== the timed browser tests (in front): exit $front; the rest (behind, at nice 19):"
wait "$behind"
behind_status=$?
cat "$behind_log"
echo "== the rest: exit $behind_status"
[ "$front" -eq 0 ] && [ "$behind_status" -eq 0 ]
