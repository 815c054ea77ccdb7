"""The console's task routes (docs/console-api.md, "Tasks"): list, schema, add, cancel.

Everyone logged in sees the tasks; only an operator adds or cancels (the archive is the console's
own, so no access policy at a callee decides this). A RAPID_RESPONSE group added is also announced
by a RapidResponseEvent sent in the person's role (``console:operator``), so the mastermind
pre-empts for it if the policy gives that role the right (docs/rapid-response.md).
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

from aiohttp import web

from nightcrew.events import RapidResponseEvent, TasksChangedEvent
from nightcrew.modules.console._http import ApiError, json_body, require_operator, require_session
from nightcrew.modules.console._tasks import (
    BODY_TYPES,
    EditableTaskArchive,
    PlanView,
    latest_plan,
    parse_body,
    task_rows,
)
from nightcrew.robotic.tasks import (
    InvalidTaskError,
    InvalidTransitionError,
    ObservationType,
    TaskNotFoundError,
    request_group_schema,
)

if TYPE_CHECKING:
    from nightcrew.modules.console.console import WebConsole

__all__ = ["add_task_routes"]

log = logging.getLogger(__name__)

#: Longest cancel reason stored.
_MAX_REASON = 500


def add_task_routes(app: web.Application, console: WebConsole) -> None:
    routes = _TaskRoutes(console)
    app.router.add_get("/api/tasks", routes.list)
    app.router.add_get("/api/tasks/schema", routes.schema)
    app.router.add_post("/api/tasks", routes.add)
    app.router.add_post("/api/tasks/{id}/cancel", routes.cancel)


class _TaskRoutes:
    def __init__(self, console: WebConsole) -> None:
        self.console = console

    def _archive(self) -> EditableTaskArchive:
        archive = self.console.task_archive
        if archive is None:
            raise ApiError(404, "ConfigError", "the console has no task archive configured (option 'tasks')")
        return archive

    async def list(self, request: web.Request) -> web.Response:
        require_session(request)
        tasks = await self._archive().list_tasks()
        now = self.console.clock.now()
        plan = PlanView(*await latest_plan(self.console.comm, self.console.directory), now)
        return web.json_response(
            {"time": now.isoformat(), "plan": plan.describe(), "tasks": task_rows(tasks, plan)}
        )

    async def schema(self, request: web.Request) -> web.Response:
        require_session(request)
        return web.json_response(request_group_schema())

    async def add(self, request: web.Request) -> web.Response:
        session = require_session(request)
        require_operator(session, "add tasks")
        archive = self._archive()
        if request.content_type not in BODY_TYPES:
            accepted = ", ".join(BODY_TYPES)
            raise ApiError(400, "InvalidArgumentError", f"expected Content-Type {accepted}")
        try:
            group = parse_body(await request.text(), request.content_type)
        except InvalidTaskError as exc:
            problems = [{"path": p.path, "message": p.message} for p in exc.problems]
            raise ApiError(400, "InvalidTaskError", str(exc), details={"problems": problems}) from None
        tasks = await archive.add_request_group(group)
        ids = tuple(task.id for task in tasks)
        log.info("%s: %s added %r (tasks %s)", self.console.name, session.user, group.name, ", ".join(ids))
        await self.console.announce(TasksChangedEvent(ids=ids, change="added"))
        if group.observation_type is ObservationType.RAPID_RESPONSE:
            # Sent for the person: the right to pre-empt is the operator's, not the console's.
            with self.console.comm.acting_as(session.role.value):
                await self.console.announce(RapidResponseEvent(ids=ids))
        plan = PlanView(None, None, self.console.clock.now())
        return web.json_response({"group_id": tasks[0].group_id, "tasks": task_rows(tasks, plan)}, status=201)

    async def cancel(self, request: web.Request) -> web.Response:
        session = require_session(request)
        require_operator(session, "cancel tasks")
        archive = self._archive()
        task_id = request.match_info["id"]
        given = (await json_body(request)).get("reason") if request.can_read_body else None
        if given is not None and not isinstance(given, str):
            raise ApiError(400, "InvalidArgumentError", "field 'reason' must be text")
        said = (given or "").strip()[:_MAX_REASON]
        reason = f"{said} ({session.user}, console)" if said else f"canceled by {session.user} in the console"
        try:
            task = await archive.cancel(task_id, reason)
        except TaskNotFoundError as exc:
            raise ApiError(404, "TaskNotFoundError", str(exc)) from None
        except InvalidTransitionError as exc:  # it ended meanwhile
            raise ApiError(409, "InvalidTransitionError", f"task {task_id}: {exc}") from None
        log.info("%s: %s canceled task %s (%s)", self.console.name, session.user, task.id, task.name)
        await self.console.announce(TasksChangedEvent(ids=(task.id,), change="cancelled"))
        plan = PlanView(None, None, self.console.clock.now())
        return web.json_response({"task": task_rows([task], plan)[0]})
