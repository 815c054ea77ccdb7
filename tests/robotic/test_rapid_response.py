"""Rapid-response requests: the choice of the task that pre-empts, the right to send it, and a
simulated night in which one stops a running task (its frame kept) that comes back afterwards; the
rapid-response task does not wait for a due refocus (the first focus of the night it does)."""

from __future__ import annotations

import re
from datetime import UTC, datetime, timedelta

from nightcrew.events import (
    NewImageEvent,
    RapidResponseEvent,
    TaskFailedEvent,
    TaskFinishedEvent,
    TaskStartedEvent,
)
from nightcrew.robotic.mastermind import preempting_task
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import ObservationType, Task, TaskState, parse_request_group, tasks_of_group
from nightcrew.security import parse_policy, starting_policy

from .mastermind_night import ORION, PLEIADES, Parts, group, start_mastermind, start_night


def task(task_id: str, kind: ObservationType, priority: float) -> Task:
    data = {**group(PLEIADES), "observation_type": kind.value, "priority": priority}
    (only,) = tasks_of_group(parse_request_group(data), "g", [task_id])
    return only


def test_only_a_rapid_response_task_of_higher_priority_that_fits_pre_empts() -> None:
    running = task("run", ObservationType.NORMAL, 5.0)
    urgent = task("rr", ObservationType.RAPID_RESPONSE, 50.0)
    fits = lambda t: True  # noqa: E731
    assert preempting_task([urgent], running, fits) is urgent
    assert preempting_task([urgent], None, fits) is urgent  # nothing runs: it runs at once
    assert preempting_task([urgent], running, lambda t: False) is None  # not observable now
    assert preempting_task([task("rr", ObservationType.RAPID_RESPONSE, 5.0)], running, fits) is None
    assert preempting_task([task("tc", ObservationType.TIME_CRITICAL, 50.0)], running, fits) is None
    assert preempting_task([urgent], urgent, fits) is None  # it runs already
    done = urgent.with_status(
        urgent.status.transition(
            TaskState.CANCELED, at=datetime(2024, 1, 15, 20, tzinfo=UTC), reason="withdrawn"
        )
    )
    assert preempting_task([done], running, fits) is None


def test_the_starting_policy_gives_the_right_of_rapid_response_to_modules_and_operators() -> None:
    policy = parse_policy(
        starting_policy(["alerts", "mastermind", "weather"], {"alice": "operator", "bob": "observer"})
    )
    senders = {
        a for a in policy.accounts if policy.accepts_event(a, "RapidResponseEvent", moves_hardware=True)
    }
    assert senders == {"alerts", "mastermind", "weather", "alice"}


async def test_a_rapid_response_task_pre_empts_a_running_task_that_comes_back(parts: Parts) -> None:
    slow = group(PLEIADES, count=8, exposure_time=60.0)
    site = await start_night(parts, [slow], [{"at": 0, "temperature": 8.0}])
    (normal,) = site.tasks
    now = site.obs.clock.now()
    await site.archive.write_schedule(
        [PlannedSlot(normal.id, now, now + timedelta(hours=1))], replace_from=now
    )
    # A refocus is due every minute: before the rapid-response task it is skipped.
    await start_mastermind(site, autofocus="recorder", refocus_interval=60.0)
    rec, clock = site.recorder, site.obs.clock

    async def frames_of(task_id: str) -> int:
        return len((await site.archive.get_task(task_id)).status.progress.exposures_done)

    for _ in range(300):  # bounded: until two frames of the running task are done
        if rec.of(NewImageEvent) and len(rec.of(NewImageEvent)) >= 2:
            break
        await clock.sleep(5.0)
    assert [e.id for e in rec.of(TaskStartedEvent)] == [normal.id]
    urgent = {
        **group(ORION, count=2, exposure_time=10.0),
        "observation_type": "RAPID_RESPONSE",
        "priority": 50,
    }
    (rapid,) = await site.archive.add_request_group(parse_request_group(urgent))
    submitted = clock.time()
    await rec.comm.send_event(RapidResponseEvent(ids=(rapid.id,)))

    for _ in range(600):
        if (await site.archive.get_task(normal.id)).state is TaskState.COMPLETED:
            break
        await clock.sleep(5.0)
    started = [(t, e.id) for t, e in rec.events if isinstance(e, TaskStartedEvent)]
    assert [task_id for _, task_id in started] == [normal.id, rapid.id, normal.id]
    rapid_start = started[1][0]
    print(f"\nrapid response: started {rapid_start - submitted:.1f} clock s after it was submitted")
    assert rapid_start - submitted <= 60.0
    (failed,) = rec.of(TaskFailedEvent)
    assert failed.id == normal.id and failed.retryable
    said = re.fullmatch(
        rf"interrupted by rapid-response task {rapid.id} \(M42 in V\): \d of 8 exposures done, "
        r"1 cut short after [\d.]+ of 60 s \(kept\)",
        failed.reason,
    )
    assert said is not None, failed.reason
    assert [e.id for e in rec.of(TaskFinishedEvent)] == [rapid.id, normal.id]
    rapid_end = next(t for t, e in rec.events if isinstance(e, TaskFinishedEvent) and e.id == rapid.id)
    first, *again = rec.focus_runs  # the night's first focus; a refocus only for the pre-empted task
    assert first < started[0][0] and again and all(t > rapid_end for t in again), rec.focus_runs
    headers = await site.headers()
    (cut,) = [h for h in headers if h.get("CUTSHORT")]
    assert cut["TASK-ID"] == normal.id and cut["EXPTIME"] < cut["EXPREQ"]
    assert sum(h["TASK-ID"] == normal.id and not h.get("CUTSHORT") for h in headers) == 8
