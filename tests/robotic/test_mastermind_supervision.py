"""run_watched: the work ends, fails, is aborted when a check finds a cause, or with its caller; all_done."""

from __future__ import annotations

import asyncio

import pytest

from nightcrew.clock import AcceleratedClock
from nightcrew.errors import MoveError
from nightcrew.robotic.mastermind import all_done, run_watched

CLOCK = AcceleratedClock("2024-01-15T22:00:00+00:00", speed=1000.0)


class Work:
    """Sleeps ``seconds`` of clock time; notes whether it was cancelled and cleaned up."""

    def __init__(self, seconds: float, error: Exception | None = None) -> None:
        self.seconds, self.error = seconds, error
        self.cleaned_up = False

    async def __call__(self) -> str:
        try:
            await CLOCK.sleep(self.seconds)
        except asyncio.CancelledError:
            self.cleaned_up = True
            raise
        if self.error is not None:
            raise self.error
        return "done"


async def _never() -> str | None:
    return None


async def test_work_that_completes_gives_none_and_errors_pass_through() -> None:
    wake = asyncio.Event()
    assert (
        await run_watched(Work(30.0)(), _never, wake=wake, clock=CLOCK, poll_interval=5.0, abort_timeout=10.0)
        is None
    )
    with pytest.raises(MoveError, match="slew failed"):
        await run_watched(
            Work(3.0, MoveError("slew failed"))(),
            _never,
            wake=wake,
            clock=CLOCK,
            poll_interval=5.0,
            abort_timeout=10.0,
        )


async def test_a_cause_found_on_waking_aborts_at_once_and_calls_on_abort() -> None:
    wake, work, aborted = asyncio.Event(), Work(3600.0), []
    cause: list[str] = []

    async def check() -> str | None:
        return cause[0] if cause else None

    async def on_abort() -> None:
        aborted.append(CLOCK.time())

    async def rain_after(seconds: float) -> None:
        await CLOCK.sleep(seconds)
        cause.append("bad weather")
        wake.set()

    start = CLOCK.time()
    rain = asyncio.create_task(rain_after(20.0))
    result = await run_watched(
        work(), check, wake=wake, clock=CLOCK, poll_interval=600.0, abort_timeout=10.0, on_abort=on_abort
    )
    await rain
    assert result == "bad weather" and work.cleaned_up and len(aborted) == 1
    assert 20.0 <= CLOCK.time() - start < 20.0 + 10.0  # woken, not the 600 s poll


async def test_the_poll_finds_a_cause_without_waking() -> None:
    start = CLOCK.time()

    async def dawn() -> str | None:
        return "dawn" if CLOCK.time() - start > 100.0 else None

    result = await run_watched(
        Work(3600.0)(), dawn, wake=asyncio.Event(), clock=CLOCK, poll_interval=30.0, abort_timeout=10.0
    )
    assert result == "dawn" and 100.0 < CLOCK.time() - start < 150.0


async def test_cancelling_the_caller_cancels_the_work_first() -> None:
    work = Work(3600.0)
    watcher = asyncio.create_task(
        run_watched(work(), _never, wake=asyncio.Event(), clock=CLOCK, poll_interval=5.0, abort_timeout=10.0)
    )
    await CLOCK.sleep(10.0)
    watcher.cancel()
    with pytest.raises(asyncio.CancelledError):
        await watcher
    assert work.cleaned_up


async def test_all_done_runs_everything_and_reports_each_failure(caplog: pytest.LogCaptureFixture) -> None:
    ran: list[str] = []

    async def ok() -> None:
        ran.append("park")

    async def broken() -> None:
        raise MoveError("roof motor stalled")

    assert await all_done({"park the telescope": ok(), "close the roof": broken()}, who="mm") is False
    assert ran == ["park"]
    assert "mm: could not close the roof: roof motor stalled" in caplog.text
    assert await all_done({"park the telescope": ok()}, who="mm") is True
