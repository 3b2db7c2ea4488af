"""The page's slow jobs (kit/jobs.py): one per browser, refused beyond with a message; viewers share two;
the operator's never waits for theirs; a failure is told to the browser. Real threads, held by events."""

from __future__ import annotations

import functools
import threading
from collections.abc import Iterator

import pytest

from pendant.ui.kit.jobs import VIEWER_JOBS, PageJobs
from tests.support.doubles import OPERATOR, FakeBrowser
from tests.support.waiting import SAFETY_NET_S, wait_until

JOB_TIMEOUT_S = SAFETY_NET_S


@pytest.fixture
def jobs() -> Iterator[PageJobs]:
    jobs = PageJobs(is_operator=lambda client: client is not None and client.client_id == OPERATOR)
    yield jobs
    jobs.shutdown()


def held(started: list[str], release: threading.Event, name: str) -> object:
    started.append(name)
    release.wait(JOB_TIMEOUT_S)
    return name


def test_a_second_click_in_the_same_browser_is_refused_until_the_first_job_ends(jobs: PageJobs) -> None:
    viewer, release, started = FakeBrowser(5), threading.Event(), list[str]()
    first = jobs.start("Replay", viewer.handle, lambda: held(started, release, "replay"))
    assert first is not None
    assert jobs.start("Download MCAP", viewer.handle, lambda: started.append("download")) is None
    assert viewer.notifications == [
        "Download MCAP refused: Replay is still running in this browser: wait for it to finish"
    ]
    release.set()
    assert first.result(JOB_TIMEOUT_S) == "replay"
    again = jobs.start("Download MCAP", viewer.handle, lambda: started.append("download"))
    assert again is not None
    again.result(JOB_TIMEOUT_S)
    assert started == ["replay", "download"]


def test_viewers_share_two_jobs_and_the_operator_still_gets_one(jobs: PageJobs) -> None:
    release, started = threading.Event(), list[str]()
    viewers = [FakeBrowser(10 + k) for k in range(VIEWER_JOBS + 1)]
    running = [
        jobs.start("Replay", viewer.handle, functools.partial(held, started, release, f"viewer {k}"))
        for k, viewer in enumerate(viewers[:VIEWER_JOBS])
    ]
    assert all(job is not None for job in running)
    last = viewers[-1]
    assert jobs.start("Replay", last.handle, lambda: started.append("one too many")) is None
    assert last.notifications == [
        f"Replay refused: the pendant is busy with {VIEWER_JOBS} other viewers' jobs: try again in a moment"
    ]
    operator = FakeBrowser(OPERATOR)
    mine = jobs.start("Download MCAP", operator.handle, lambda: held(started, release, "operator"))
    assert mine is not None
    wait_until(lambda: "operator" in started, JOB_TIMEOUT_S, "the operator's job beside the viewers'")
    assert operator.notifications == []
    release.set()
    for job in [*running, mine]:
        assert job is not None
        job.result(JOB_TIMEOUT_S)
    assert "one too many" not in started


def test_a_job_that_fails_tells_its_browser_and_frees_it(jobs: PageJobs) -> None:
    viewer = FakeBrowser(7)

    def broken() -> object:
        raise OSError("Permission denied: 'pendant-20260101-000000.mcap'")

    failed = jobs.start("Download MCAP", viewer.handle, broken)
    assert failed is not None
    with pytest.raises(OSError):
        failed.result(JOB_TIMEOUT_S)
    assert viewer.notifications == ["Download MCAP failed: Permission denied: 'pendant-20260101-000000.mcap'"]
    assert jobs.running(viewer.handle) is None
