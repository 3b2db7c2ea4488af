"""Taking control in the page: wrong tokens typed into a page are slowed per address, as on the API (finding
8), and a hand-over never leaves nobody in control while a browser that may have it is waiting (finding 9).
Headless: the desk and its event log, as the page's sessions use them."""

from __future__ import annotations

from pendant.access.throttle import FailedAttempts
from pendant.eventlog import EventLog
from pendant.ui.page.roles import MSG_TOO_MANY, MSG_WRONG_TOKEN, ControlDesk

TOKEN = "a-long-enough-token-for-the-page"


class Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_wrong_tokens_from_one_address_are_slowed_and_others_are_not() -> None:
    clock = Clock()
    desk = ControlDesk(EventLog(), token=TOKEN, attempts=FailedAttempts(free=3, interval_s=1.0, now=clock))
    desk.join(1, "10.0.0.66")
    desk.join(2, "10.0.0.7")
    assert [desk.take(1, f"guess-{i}") for i in range(3)] == [MSG_WRONG_TOKEN] * 3
    # The fourth guess at once is not even checked: the right token too has to wait its turn.
    assert desk.take(1, "guess-3") == MSG_TOO_MANY
    assert desk.take(1, TOKEN) == MSG_TOO_MANY
    assert desk.operator is None
    assert desk.take(2, TOKEN) is None  # another address is not held up
    assert desk.release(2)
    clock.t += 5.0
    assert desk.take(1, TOKEN) is None  # its turn came: the right token works


def test_a_browser_that_joined_while_the_operator_was_there_gets_control_when_the_operator_leaves() -> None:
    desk = ControlDesk(EventLog())  # loopback, no token: any browser may have control
    desk.join(1)
    desk.join(2)  # joins a moment before the operator leaves: a viewer, for now
    assert desk.operator == 1
    desk.leave(1)
    assert desk.operator == 2


def test_with_a_token_control_passes_only_to_a_browser_that_presented_it() -> None:
    desk = ControlDesk(EventLog(), token=TOKEN)
    for client_id in (1, 2, 3):
        desk.join(client_id)
    assert desk.take(2, TOKEN) is None
    assert desk.release(2)
    assert desk.take(1, TOKEN) is None
    desk.leave(1)
    assert desk.operator == 2  # 3 never showed the token: it is not handed control
    desk.leave(2)
    assert desk.operator is None
