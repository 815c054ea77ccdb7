"""``nightcrew tasks``: add, list, show, cancel and explain tasks in the SQLite task archive.

``add FILE...`` validates request group files (YAML or JSON) and stores each with one task per
request, printing the defaults it filled in; if any file is invalid, every problem is printed on one
line with the file and its field path, nothing is stored and the exit code is 2. ``list`` prints a
table, ``show ID`` one task in full, ``cancel ID`` withdraws a task, ``why ID`` says when the task
is planned in a night or why not, ``schema`` prints the request format as JSON Schema. The database
is ``--db PATH``, else ``$NIGHTCREW_TASKS_DB``, else ``./tasks.sqlite`` (run it in the observatory
directory). With ``--comm FILE`` (or ``$NIGHTCREW_COMM``), ``add`` and ``cancel`` tell the
scheduler at once (TasksChangedEvent; rapid-response tasks also RapidResponseEvent, on which the
mastermind may pre-empt); without, it sees the change at its next poll.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import sys
from collections.abc import Sequence
from datetime import datetime
from pathlib import Path
from typing import Any

import yaml

from nightcrew.cli._operator import add_comm_argument, load_comm, operator_module
from nightcrew.cli._tasks_why import add_why_parser
from nightcrew.comm.base import Comm
from nightcrew.errors import NightcrewError
from nightcrew.events import RapidResponseEvent, TasksChangedEvent
from nightcrew.robotic.archives import DEFAULT_TASKS_DB, SqliteTaskArchive
from nightcrew.robotic.tasks import (
    InvalidTaskError,
    ObservationType,
    RequestGroup,
    TaskState,
    cadence_progress,
    estimate_duration,
    filled_defaults,
    load_request_group_file,
    request_group_schema,
)

__all__ = ["add_parser", "announce_change", "database_path"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "tasks", help="add, list, show and cancel tasks", description=__doc__.split("\n\n", 1)[1]
    )
    # --db works before and after the action; SUPPRESS keeps the later one from hiding the first.
    db = argparse.ArgumentParser(add_help=False)
    db.add_argument("--db", type=Path, default=argparse.SUPPRESS, help="the task database")
    parser.add_argument("--db", type=Path, default=None, help="the task database")
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)

    add = actions.add_parser("add", parents=[db], help="validate request group files and store them")
    add.add_argument("files", metavar="FILE", type=Path, nargs="+", help="request group (YAML or JSON)")
    add_comm_argument(add)
    add.set_defaults(func=_run(_add))

    listing = actions.add_parser("list", parents=[db], help="print a table of the tasks")
    listing.add_argument(
        "--state", type=_state, action="append", help="only tasks in this state (repeatable)"
    )
    listing.set_defaults(func=_run(_list))

    show = actions.add_parser("show", parents=[db], help="print one task in full")
    show.add_argument("task_id", metavar="ID")
    show.set_defaults(func=_run(_show))

    cancel = actions.add_parser("cancel", parents=[db], help="cancel a task that has not ended")
    cancel.add_argument("task_id", metavar="ID")
    cancel.add_argument("--reason", default="canceled from the command line", help="why (stored with it)")
    add_comm_argument(cancel)
    cancel.set_defaults(func=_run(_cancel))

    add_why_parser(actions, db, _run, database_path)

    schema = actions.add_parser("schema", help="print the request format as JSON Schema")
    schema.set_defaults(func=_schema)
    return parser


def database_path(args: argparse.Namespace) -> Path:
    """--db, else $NIGHTCREW_TASKS_DB, else ./tasks.sqlite."""
    if args.db is not None:
        return Path(args.db)
    return Path(os.environ.get("NIGHTCREW_TASKS_DB") or DEFAULT_TASKS_DB)


def _run(action: Any) -> Any:
    def run(args: argparse.Namespace) -> int:
        code: int = asyncio.run(action(args))
        return code

    return run


async def _add(args: argparse.Namespace) -> int:
    comm = _comm(args)  # a bad comm file fails before anything is stored
    groups: list[RequestGroup] = []
    invalid: list[InvalidTaskError] = []
    for path in args.files:
        try:
            groups.append(load_request_group_file(path))
        except InvalidTaskError as exc:
            invalid.append(exc)
    if invalid:
        for error in invalid:
            for problem in error.problems:  # one line each: the file, the field and what is wrong
                print(
                    f"nightcrew: error: {error.source}: invalid request group: {problem}; nothing was stored",
                    file=sys.stderr,
                )
        return 2
    added: list[str] = []
    rapid: list[str] = []
    async with _archive(args) as archive:
        for group in groups:
            tasks = await archive.add_request_group(group)
            added += [task.id for task in tasks]
            if group.observation_type is ObservationType.RAPID_RESPONSE:
                rapid += [task.id for task in tasks]
            ids = ", ".join(task.id for task in tasks)
            print(
                f"added {group.name!r} (group {tasks[0].group_id}): task{'s' if len(tasks) > 1 else ''} {ids}"
            )
            defaults = filled_defaults(group)
            if defaults:
                print("  defaults filled in:")
                for path, value in defaults:
                    note = "  (can keep a target out of the plan)" if _can_exclude(path) else ""
                    print(f"    {path}: {json.dumps(value, ensure_ascii=False)}{note}")
    await _tell_scheduler(comm, added, "added", rapid=rapid)
    return 0


async def _list(args: argparse.Namespace) -> int:
    async with _archive(args) as archive:
        tasks = await archive.list_tasks(states=args.state)
        unreadable = await archive.list_unreadable(states=args.state)
    rows = [["ID", "STATE", "NAME", "PROPOSAL", "PRIORITY", "DURATION", "WINDOWS", "CONFIGURATIONS"]]
    for task in tasks:
        rows.append(
            [
                task.id,
                task.state.value,
                task.name,
                task.proposal,
                f"{task.effective_priority:g}",
                _duration(estimate_duration(task.request).total_s),
                f"{_time(task.request.first_start)} - {_time(task.request.last_end)}",
                " ".join(_configuration_summary(c.type.value, c.target) for c in task.request.configurations),
            ]
        )
    # A row stored before a bound it breaks existed is shown, named, never a crash for everyone.
    rows.extend([row.id, "UNREADABLE", row.name, "-", "-", "-", "-", row.problem] for row in unreadable)
    print(_table(rows))
    if not tasks and not unreadable:
        print("(no tasks)")
    return 0


async def _show(args: argparse.Namespace) -> int:
    async with _archive(args) as archive:
        task = await archive.get_task(args.task_id)
        group = (
            [t for t in await archive.list_tasks() if t.group_id == task.group_id]
            if task.request.cadence
            else []
        )
    status = task.status
    estimate = estimate_duration(task.request)
    print(f"task {task.id}: request {task.request_index} of group {task.group_id} {task.name!r}")
    print(f"state: {status.state.value}" + (f" ({status.reason})" if status.reason else ""))
    kind = task.observation_type.value
    print(f"proposal: {task.proposal}, {kind}, priority {task.priority:g} x ipp {task.ipp:g}")
    print(f"duration: {_duration(estimate.total_s)} (set-up {_duration(estimate.setup_s)})")
    cadence = cadence_progress(task, group)
    if cadence is not None:
        print(f"cadence: {cadence}")
    for label, when in (("started", status.started_at), ("finished", status.finished_at)):
        if when is not None:
            print(f"{label}: {when.isoformat()}")
    for c, configuration in enumerate(task.request.configurations):
        for i, instrument_config in enumerate(configuration.instrument_configs):
            done = status.progress.count(c, i)
            print(f"done: configuration {c} series {i}: {done}/{instrument_config.exposure_count} exposures")
    print("request:")
    text = yaml.safe_dump(task.request.model_dump(mode="json"), sort_keys=False, allow_unicode=True)
    print("  " + text.rstrip().replace("\n", "\n  "))
    return 0


async def _cancel(args: argparse.Namespace) -> int:
    comm = _comm(args)
    async with _archive(args) as archive:
        task = await archive.cancel(args.task_id, args.reason)
    print(f"task {task.id} ({task.name}): {task.state.value}")
    await _tell_scheduler(comm, [task.id], "cancelled")
    return 0


#: Constraints whose defaults can exclude a target without the file saying so (docs/tasks.md).
_EXCLUDING_DEFAULTS = (
    "constraints.min_lunar_distance",
    "constraints.max_airmass",
    "constraints.max_sun_altitude",
)


def _can_exclude(path: str) -> bool:
    return path.endswith(_EXCLUDING_DEFAULTS)


def _schema(args: argparse.Namespace) -> int:
    print(json.dumps(request_group_schema(), indent=2, ensure_ascii=False))
    return 0


def _comm(args: argparse.Namespace) -> Comm | None:
    """The operator's comm from --comm / $NIGHTCREW_COMM (built, not connected), or None."""
    return load_comm(args.comm) if args.comm else None


async def _tell_scheduler(
    comm: Comm | None, ids: list[str], change: str, *, rapid: Sequence[str] = ()
) -> None:
    """Send TasksChangedEvent (and RapidResponseEvent for the ``rapid`` ones) on the operator's comm,
    if one is configured; else say so. The tasks are stored already: a comm that cannot connect is
    reported, not an error."""
    if comm is None:
        print("the scheduler will see it at its next poll (no --comm or $NIGHTCREW_COMM to tell it now)")
        return
    try:
        await announce_change(comm, ids, change, rapid=rapid)
    except NightcrewError as exc:
        print(f"could not tell the scheduler ({exc}): it will see it at its next poll")
        return
    print(f"told the scheduler: tasks {', '.join(ids)} {change}")
    if rapid:
        print(f"told the mastermind: rapid-response tasks {', '.join(rapid)}")


async def announce_change(comm: Comm, ids: Sequence[str], change: str, *, rapid: Sequence[str] = ()) -> None:
    """Tell every module on ``comm`` (the scheduler) that tasks ``ids`` were ``change``d, and the
    mastermind of the ``rapid`` (rapid-response) ones, as the operator; the comm is opened and
    closed here (the access policy decides whether the rapid ones may pre-empt)."""
    async with operator_module(comm) as module:
        await module.comm.send_event(TasksChangedEvent(ids=tuple(ids), change=change))
        if rapid:
            await module.comm.send_event(RapidResponseEvent(ids=tuple(rapid)))


def _archive(args: argparse.Namespace) -> SqliteTaskArchive:
    return SqliteTaskArchive(database_path(args), poll_interval=0)


def _state(text: str) -> TaskState:
    try:
        return TaskState(text.upper())
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"unknown state {text!r} (one of {', '.join(s.value for s in TaskState)})"
        ) from None


def _configuration_summary(kind: str, target: Any) -> str:
    return f"{kind}({target.name})" if target is not None else kind


def _duration(seconds: float) -> str:
    minutes, secs = divmod(round(seconds), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}h{minutes:02d}m" if hours else f"{minutes}m{secs:02d}s"


def _time(when: datetime) -> str:
    return when.strftime("%Y-%m-%d %H:%M")


def _table(rows: Sequence[Sequence[str]]) -> str:
    widths = [max(len(row[column]) for row in rows) for column in range(len(rows[0]))]
    return "\n".join(
        "  ".join(cell.ljust(width) for cell, width in zip(row, widths, strict=True)).rstrip() for row in rows
    )
