#!/usr/bin/env bash
# The suite (`make test`): the checks and three passes of tests.
#   In front, at normal priority, one at a time: the tests that time what a user feels on a real clock
#     (`measures`: jog shares, stop times; most are browser tests) and the `alone` ones.
#   Behind them at the same time, at the lowest CPU priority (nice 19): the checks (ruff, import-linter, mypy)
#     and every other test outside tests/browser on two workers (--dist worksteal).
#   Once both are done, the other browser tests on two workers, a module per worker (--dist loadfile: it
#     shares its Chromium and pendants, tests/browser/conftest.py).
# The timed pass mostly waits on its real clock (a 10 s hold, a path drawn at a hand's pace, a 3 s look at a
# stopped arm): the work behind it fills that idle CPU, and niced it never takes a core the timed pass wants
# (Linux gives a nice-19 task about 1/70 of a normal one's share). The other browser tests overlap neither:
# with them behind the timed pass (27 Nov) its jog holds failed, and started beside what was still behind
# (1 Dec, CI) their two Chromiums most likely left the niced tests so little CPU that a dozen of them, and the pendants
# they started, missed their time-outs. Each has the machine to itself now; the CPU is the same.
# Each pass behind writes its own log in test-artifacts/, shown when it is done; each pass prints its count
# and its 15 slowest tests (where the ten minutes go); the last lines list every failure of every pass.
set -uo pipefail
bin=${BIN:-.venv/bin}
read -r -a extra <<<"${PYTEST_ARGS:-}"
mkdir -p test-artifacts

behind() { # name, command...: run the command at nice 19, its output to test-artifacts/<name>.log
    local name=$1
    shift
    nice -n 19 "$@" >"test-artifacts/$name.log" 2>&1 &
    pids+=($!)
    logs+=("$name")
    names+=("$name (behind, nice 19)")
}
pids=()
logs=()
names=()
behind checks make -s --no-print-directory lint layers typecheck
behind tests "$bin/pytest" -q --durations=15 -n 2 --dist worksteal --ignore=tests/browser -m "not measures and not alone" "${extra[@]}"
# Whoever stops `make test` (Ctrl-C, CI's time-out) stops the passes behind too: they are in our process group.
trap 'trap - INT TERM; kill 0' INT TERM

"$bin/pytest" -q --durations=15 -m "measures or alone" --reruns 1 tests "${extra[@]}" 2>&1 | tee test-artifacts/timed-tests.log
failed=${PIPESTATUS[0]}
echo "== the timed tests (in front): exit $failed"
for i in "${!pids[@]}"; do
    wait "${pids[$i]}"
    status=$?
    echo "== ${names[$i]}: exit $status"
    cat "test-artifacts/${logs[$i]}.log"
    [ "$status" -eq 0 ] || failed=1
done
"$bin/pytest" -q --durations=15 -n 2 --dist loadfile -m "not measures and not alone" --reruns 1 tests/browser "${extra[@]}" \
    2>&1 | tee test-artifacts/browser-tests.log
status=${PIPESTATUS[0]}
echo "== the other browser tests (after the others): exit $status"
[ "$status" -eq 0 ] || failed=1
# Every failure of every pass, last, where a truncated log still shows them.
echo "== failures and errors of all passes:"
grep -h -E "^(FAILED|ERROR) " test-artifacts/timed-tests.log test-artifacts/tests.log test-artifacts/browser-tests.log || echo "none"
exit "$failed"
