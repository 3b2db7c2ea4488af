#!/usr/bin/env bash
# The suite (`make test`): the checks and three passes of tests, all at once.
#   In front, at normal priority, one at a time: the tests that time what a user feels on a real clock
#     (`measures`: jog shares, stop times; most are browser tests) and the `alone` ones.
#   Behind them, at the lowest CPU priority (nice 19): the checks (ruff, import-linter, mypy); every other
#     test outside tests/browser on three workers (--dist worksteal); the other browser tests on two workers,
#     a module per worker (--dist loadfile: it shares its Chromium and pendants, tests/browser/conftest.py).
# Every pass mostly waits (on a real clock, a process starting, a page drawing: the timed pass used 0.3 of
# a core over its 9 minutes), so side by side they fill each other's idle time. Niced, the passes behind never
# take a core the timed one wants: Linux gives a nice-19 task about 1/70 of a normal one's share. Chromium
# raises some of its threads to nice 0 and -8 when it may (as root it may: CAP_SYS_NICE); behind, it runs
# without that capability, so the browser tests behind stay behind.
# Each pass behind writes its own log in test-artifacts/, shown when it is done; each prints its count.
set -uo pipefail
bin=${BIN:-.venv/bin}
read -r -a extra <<<"${PYTEST_ARGS:-}"
mkdir -p test-artifacts

low=(nice -n 19)
if [ "$(id -u)" -eq 0 ] && command -v setpriv >/dev/null 2>&1; then
    low=(setpriv --bounding-set=-sys_nice --inh-caps=-sys_nice nice -n 19)
fi

behind() { # name, command...: run the command behind, its output to test-artifacts/<name>.log
    local name=$1
    shift
    "${low[@]}" "$@" >"test-artifacts/$name.log" 2>&1 &
    pids+=($!)
    names+=("$name")
}
pids=()
names=()
behind checks make -s --no-print-directory lint layers typecheck
behind tests "$bin/pytest" -q -n 3 --dist worksteal --ignore=tests/browser -m "not measures" "${extra[@]}"
behind browser-tests "$bin/pytest" -q -n 2 --dist loadfile -m "not measures and not alone" --reruns 1 \
    tests/browser "${extra[@]}"
# Whoever stops `make test` (Ctrl-C, CI's time-out) stops the passes behind too: they are in our process group.
trap 'trap - INT TERM; kill 0' INT TERM

"$bin/pytest" -q -m "measures or alone" --reruns 1 tests "${extra[@]}"
failed=$?
echo "== the timed tests (in front): exit $failed"
for i in "${!pids[@]}"; do
    wait "${pids[$i]}"
    status=$?
    echo "== ${names[$i]} (behind, nice 19): exit $status"
    cat "test-artifacts/${names[$i]}.log"
    [ "$status" -eq 0 ] || failed=1
done
exit "$failed"
