"""Task states: every change goes through the transition table; progress survives failures."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.tasks import (
    ALLOWED_TRANSITIONS,
    FINAL_STATES,
    CutShortFrame,
    InvalidTransitionError,
    TaskProgress,
    TaskState,
    TaskStatus,
    parse_request_group,
    tasks_of_group,
)
from tests.robotic.test_tasks_model import valid_group_data

T0 = datetime(2026, 11, 10, 18, tzinfo=UTC)
S = TaskState


def test_the_table_covers_every_state_and_has_three_final_states() -> None:
    assert set(ALLOWED_TRANSITIONS) == set(TaskState)
    assert {S.COMPLETED, S.CANCELED, S.WINDOW_EXPIRED} == FINAL_STATES


@pytest.mark.parametrize(
    ("start", "end"),
    [(a, b) for a in TaskState for b in TaskState if b in ALLOWED_TRANSITIONS[a]],
)
def test_allowed_transitions_happen(start: TaskState, end: TaskState) -> None:
    status = TaskStatus(state=start).transition(end, at=T0, reason="why")
    assert status.state is end
    assert status.modified_at == T0


@pytest.mark.parametrize(
    ("start", "end"),
    [(a, b) for a in TaskState for b in TaskState if b not in ALLOWED_TRANSITIONS[a]],
)
def test_other_transitions_are_refused(start: TaskState, end: TaskState) -> None:
    with pytest.raises(InvalidTransitionError, match=f"a {start} task cannot become {end}"):
        TaskStatus(state=start).transition(end, at=T0, reason="why")


def test_failing_and_canceling_need_a_reason() -> None:
    running = TaskStatus(state=S.RUNNING)
    with pytest.raises(InvalidTransitionError, match="only become FAILED with a reason"):
        running.transition(S.FAILED, at=T0)
    with pytest.raises(InvalidTransitionError, match="only become CANCELED with a reason"):
        TaskStatus().transition(S.CANCELED, at=T0, reason="  ")


def test_a_run_records_times_progress_and_a_failure_keeps_what_was_done() -> None:
    task = tasks_of_group(parse_request_group(valid_group_data()), "1", ["1", "2"])[0]
    request = task.request
    status = task.status.transition(S.SCHEDULED, at=T0).transition(S.RUNNING, at=T0 + timedelta(minutes=1))
    assert status.started_at == T0 + timedelta(minutes=1) and status.finished_at is None
    progress = TaskProgress.nothing_done(request)
    assert progress.exposures_done == ((0, 0), ())
    progress = progress.with_exposures(request, 0, 0, 2)
    status = status.with_progress(progress, at=T0 + timedelta(minutes=3))
    failed = status.transition(S.FAILED, at=T0 + timedelta(minutes=4), reason="clouds")
    assert (failed.reason, failed.finished_at) == ("clouds", T0 + timedelta(minutes=4))
    assert failed.progress.count(0, 0) == 2 and failed.progress.total_exposures == 2
    assert failed.progress.exposure_time_done(request) == 60.0
    assert not failed.progress.configuration_complete(request, 0)
    # A retry starts from what is there; a success clears the reason.
    retried = failed.transition(S.RUNNING, at=T0 + timedelta(hours=1))
    assert retried.progress == failed.progress and retried.finished_at is None
    done = retried.progress.with_exposures(request, 0, 0).with_exposures(request, 0, 1)
    assert done.configuration_complete(request, 0)
    completed = retried.transition(S.COMPLETED, at=T0 + timedelta(hours=2), progress=done)
    assert completed.reason == "" and completed.progress.total_exposures == 4


def test_progress_only_while_running_and_only_of_the_right_shape() -> None:
    task = tasks_of_group(parse_request_group(valid_group_data()), "1", ["1", "2"])[1]
    with pytest.raises(InvalidTransitionError, match="only be recorded while RUNNING, not PENDING"):
        task.status.with_progress(TaskProgress(), at=T0)
    TaskProgress().check_fits(task.request)  # nothing recorded fits anything
    TaskProgress(exposures_done=((3,),)).check_fits(task.request)
    with pytest.raises(InvalidArgumentError, match=r"progress has \[2\] instrument configs"):
        TaskProgress(exposures_done=((1, 1),)).check_fits(task.request)
    with pytest.raises(ValueError, match="greater than or equal to 0"):
        TaskProgress(exposures_done=((-1,),))


def test_a_frame_cut_short_is_recorded_but_not_done_and_survives_storage() -> None:
    task = tasks_of_group(parse_request_group(valid_group_data()), "1", ["1", "2"])[0]
    request = task.request  # EXPOSE (3 x 30 s, 1 x 20 s), then a SCRIPT
    progress = TaskProgress().with_cut_short(request, 0, 0, 14.5).with_exposures(request, 0, 0)
    assert progress.exposures_done == ((1, 0), ())  # the cut-short frame satisfies no exposure
    assert progress.cut_short == (CutShortFrame(configuration=0, instrument_config=0, exposed=14.5),)
    assert (progress.cut_short_count(0, 0), progress.cut_short_count(0, 1)) == (1, 0)
    assert progress.cut_short_time == 14.5 and progress.exposure_time_done(request) == 30.0
    assert progress.remaining(request, 0, 0) == 2  # the retry takes it again
    progress.check_fits(request)
    # One configuration seen alone (what a script runs) and put back: nothing lost or moved.
    alone = progress.of_configuration(0)
    assert alone.cut_short == progress.cut_short and progress.of_configuration(1).cut_short == ()
    assert TaskProgress.nothing_done(request).with_configuration(0, alone) == progress
    # Kept in the stored status (JSON, as the SQLite archive stores it); a row from before
    # cut_short existed still reads, with none.
    status = TaskStatus(state=S.FAILED, reason="rain", progress=progress)
    assert TaskStatus.model_validate_json(status.model_dump_json()) == status
    old_row = '{"state": "FAILED", "reason": "rain", "progress": {"exposures_done": [[1, 0], []]}}'
    assert TaskStatus.model_validate_json(old_row).progress.cut_short == ()
    with pytest.raises(
        InvalidArgumentError, match=r"cut_short\[0\] names instrument config 2 of configuration 0"
    ):
        TaskProgress().with_cut_short(request, 0, 2, 1.0).check_fits(request)
    with pytest.raises(ValueError, match="greater than or equal to 0"):
        CutShortFrame(configuration=0, instrument_config=0, exposed=-1.0)


def test_tasks_carry_their_group() -> None:
    group = parse_request_group(valid_group_data())
    tasks = tasks_of_group(group, "g1", ["a", "b"])
    assert [t.id for t in tasks] == ["a", "b"] and tasks[1].request_index == 1
    assert tasks[0].effective_priority == 3.0  # priority 2 x ipp 1.5
    assert tasks[0].schedulable and tasks[0].state is S.PENDING
    failed = tasks[0].with_status(TaskStatus(state=S.FAILED, reason="x"))
    assert failed.schedulable  # tried again while a window is left
    assert not tasks[0].with_status(TaskStatus(state=S.COMPLETED)).schedulable
    with pytest.raises(ValueError, match="2 requests need as many task ids, got 1"):
        tasks_of_group(group, "g1", ["a"])
