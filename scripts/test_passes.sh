#!/usr/bin/env bash
# The suite (`make test`): the checks and three passes of tests, in two phases.
#   1. The tests that time what a user feels on a real clock (`measures`: jog shares, stop times, a hold
#      beside 30 viewers; most are browser tests) and the `alone` ones, one at a time, at normal priority;
#      beside them, in Linux's idle scheduling class (SCHED_IDLE, `chrt -i 0`), every other test outside
#      tests/browser on three workers (--dist worksteal) and the checks (ruff, import-linter, mypy).
#   2. The other browser tests on two workers, a module per worker (--dist loadfile: it shares its Chromium
#      and pendants, tests/browser/conftest.py); beside them, back in the normal class, what is left of the
#      passes of the first phase.
# The timed pass waits on its clock half the time (~0.5 of the 2 cores here); the idle class gets only what
# it leaves: the kernel takes the core from an idle-class task at once for a timed test's thread that wakes
# (a nice 19 task only weighs less). At nice 19 beside the timed pass its holds were cut by the deadman
# (1 Dec, load 7-10); in the idle class all 31 timed tests passed beside the 1,676 (2 Dec, a clean clone:
# the first phase 7 min 09 s, against 5 min 36 s + 4 min 11 s one after the other). Where `chrt` cannot set
# the idle class, nice 19 stands in. The browser tests stay out of the first phase: their two Chromiums would leave
# the timed pass's page too little (27 Nov, at nice 19: its jog holds failed).
# Each pass writes its log in test-artifacts/ and prints its count and its 15 slowest tests (where the ten
# minutes go); the last lines list every failure of every pass.
set -uo pipefail
bin=${BIN:-.venv/bin}
read -r -a extra <<<"${PYTEST_ARGS:-}"
pytest_args=(-q -rfER --durations=15)
mkdir -p test-artifacts

if chrt -i 0 true 2>/dev/null; then low=(chrt -i 0); else low=(nice -n 19); fi
behind() { # name, command...: run the command in the idle class, its output to test-artifacts/<name>.log
    "${low[@]}" "${@:2}" >"test-artifacts/$1.log" 2>&1
}
# Whoever stops `make test` (Ctrl-C, CI's time-out) stops what runs beside it too: it is in our process group.
trap 'trap - INT TERM; kill 0' INT TERM
failed=0
# The machine's busy and total CPU seconds so far (/proc/stat, every core): each phase prints what it used,
# the figure that says how far a 2-core machine is from the suite's minutes (its CPU over two).
cpu_now() {
    awk -v hz="$(getconf CLK_TCK)" '/^cpu / { busy = $2 + $3 + $4 + $7 + $8 + $9; print busy / hz, (busy + $5 + $6) / hz }' /proc/stat
}
phase_cpu() { # name, "busy total" at its start: what the machine's cores did during the phase
    local busy0 total0 busy1 total1
    read -r busy0 total0 <<<"$2"
    read -r busy1 total1 < <(cpu_now)
    awk -v n="$1" -v b="$busy0" -v t="$total0" -v B="$busy1" -v T="$total1" \
        'BEGIN { printf "== %s: the machine busy %.0f of %.0f CPU-s (%.0f %%)\n", n, B - b, T - t, 100 * (B - b) / (T - t) }'
}
to_normal_class() { # pid: it and its descendants, every thread, in the normal class (top down: a child
    # started meanwhile inherits its parent's class); gone already, nothing to do
    local pid=$1 child
    if [ "${low[0]}" = chrt ]; then chrt -a -o -p 0 "$pid" >/dev/null 2>&1; else renice -n 0 -p "$pid" >/dev/null 2>&1; fi
    for child in $(cat /proc/"$pid"/task/*/children 2>/dev/null); do to_normal_class "$child"; done
}
report_behind() { # name, log, pid: how a pass beside the timed tests ended, and its log
    wait "$3"
    local status=$?
    echo "== $1 (beside the timed tests, ${low[*]}): exit $status"
    cat "test-artifacts/$2.log"
    [ "$status" -eq 0 ] || failed=1
}
run_pass() { # name, log, pytest arguments...: one pass of tests, shown as it runs and kept in test-artifacts/
    local name=$1 log=$2
    "$bin/pytest" "${pytest_args[@]}" "${@:3}" "${extra[@]}" 2>&1 | tee "test-artifacts/$log.log"
    local status=${PIPESTATUS[0]}
    echo "== $name: exit $status"
    [ "$status" -eq 0 ] || failed=1
}

start=$(cpu_now)
behind checks make -s --no-print-directory lint layers typecheck &
checks=$!
behind tests "$bin/pytest" "${pytest_args[@]}" -n 3 --dist worksteal --ignore=tests/browser \
    -m "not measures and not alone" "${extra[@]}" &
outside=$!
run_pass "the timed tests" timed-tests -m "measures or alone" --reruns 1 tests
phase_cpu "the first phase" "$start"
# Nothing is timed any more: what is left of the passes behind goes on at normal priority, beside the
# other browser tests, rather than keeping them waiting (the pass outside tests/browser ended 60 s after
# the timed pass on 4 Dec, the machine's two cores busy).
to_normal_class "$outside"
to_normal_class "$checks"
start=$(cpu_now)
run_pass "the other browser tests" browser-tests -n 2 --dist loadfile -m "not measures and not alone" --reruns 1 tests/browser
report_behind "the tests outside tests/browser" tests "$outside"
report_behind "the checks" checks "$checks"
phase_cpu "the second phase" "$start"
# Every failure of every pass, last, where a truncated log still shows them, and every test run again
# (-rR: a rerun that passed is a flaky test, named here so it is seen).
echo "== failures, errors and reruns of all passes:"
grep -h -E "^(FAILED|ERROR|RERUN) " test-artifacts/timed-tests.log test-artifacts/tests.log test-artifacts/browser-tests.log || echo "none"
exit "$failed"
