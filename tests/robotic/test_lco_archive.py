"""The LCO portal archive against a local HTTP server that replays the portal's documented API.

The real observation portal (a Django application with PostgreSQL and a configuration database)
cannot run in this environment, so this server answers with the shapes of the portal's documented
examples and endpoints (schedulable requests, last changed, observations with DRF pagination,
observation cancel, configuration status PATCH). It is a real aiohttp server on 127.0.0.1, so the
client's HTTP, token header, pagination and errors are exercised for real.
"""

from __future__ import annotations

import copy
import re
from collections.abc import AsyncIterator
from datetime import UTC, datetime, timedelta
from typing import Any

import pytest
from aiohttp import web

from nightcrew.robotic.archives import (
    LcoPortalArchive,
    LcoPortalClient,
    PortalError,
    TaskChange,
)
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import ConfigurationType, Target, TaskNotFoundError, TaskProgress, TaskState
from tests.robotic.test_archives_sqlite import NIGHT, ManualClock

TOKEN = "0123456789abcdef"

#: One request group as schedulable_requests lists it (fields as in the portal's documented examples).
REQUEST_GROUP: dict[str, Any] = {
    "id": 1350420,
    "submitter": "ellie_arroway",
    "name": "K2-22 transit",
    "observation_type": "NORMAL",
    "operator": "SINGLE",
    "ipp_value": 1.05,
    "state": "PENDING",
    "proposal": "PROPOSAL-A-2021",
    "is_staff": False,
    "requests": [
        {
            "id": 2722445,
            "state": "PENDING",
            "acceptability_threshold": 90,
            "observation_note": "",
            "extra_params": {},
            "duration": 1999,
            "location": {"telescope_class": "0m4", "site": "", "enclosure": None, "telescope": None},
            "windows": [{"start": "2026-11-10T17:00:00Z", "end": "2026-11-11T05:00:00Z"}],
            "configurations": [
                {
                    "id": 7011091,
                    "instrument_type": "0M4-SCICAM",
                    "type": "EXPOSE",
                    "priority": 1,
                    "extra_params": {},
                    "instrument_configs": [
                        {
                            "optical_elements": {"filter": "V"},
                            "mode": "FAST",
                            "exposure_time": 120,
                            "exposure_count": 3,
                            "rotator_mode": "",
                            "extra_params": {"bin_x": 2, "bin_y": 2, "defocus": 0},
                            "rois": [],
                        }
                    ],
                    "constraints": {
                        "max_airmass": 2,
                        "min_lunar_distance": 20,
                        "max_lunar_phase": 0.8,
                        "max_seeing": None,
                        "extra_params": {},
                    },
                    "acquisition_config": {"mode": "OFF", "extra_params": {}},
                    "guiding_config": {
                        "optional": False,
                        "mode": "ON",
                        "optical_elements": {},
                        "exposure_time": None,
                        "extra_params": {},
                    },
                    "target": {
                        "type": "ICRS",
                        "name": "K2-22",
                        "ra": 169.4978489167,
                        "dec": 2.6100554444,
                        "proper_motion_ra": -27.108,
                        "proper_motion_dec": -4.712,
                        "parallax": 4.0729,
                        "epoch": 2000,
                        "hour_angle": None,
                        "extra_params": {},
                    },
                },
                {
                    "id": 7011092,
                    "instrument_type": "0M4-SCICAM",
                    "type": "BIAS",
                    "priority": 2,
                    "extra_params": {},
                    "instrument_configs": [
                        {"optical_elements": {}, "exposure_time": 0, "exposure_count": 2, "extra_params": {}}
                    ],
                    "constraints": {"max_airmass": 2, "min_lunar_distance": 0, "max_lunar_phase": None},
                    "acquisition_config": {"mode": "OFF"},
                    "guiding_config": {"mode": "OFF", "optional": True},
                    "target": {},
                },
            ],
        }
    ],
    "created": "2026-11-01T14:15:22Z",
    "modified": "2026-11-01T14:15:22Z",
}


class ReplayPortal:
    """Records what the client sends and answers as the documented API does."""

    def __init__(self) -> None:
        self.groups = [copy.deepcopy(REQUEST_GROUP)]
        self.last_change = "2026-11-10T12:00:00Z"
        self.observations: list[dict[str, Any]] = []
        self.canceled: list[dict[str, Any]] = []
        self.patches: list[tuple[int, dict[str, Any]]] = []
        self.queries: list[dict[str, str]] = []
        self.page_size = 1

    def app(self) -> web.Application:
        app = web.Application(middlewares=[self._auth])
        app.router.add_get("/api/requestgroups/schedulable_requests/", self._schedulable)
        app.router.add_get("/api/last_changed/", self._last_changed)
        app.router.add_get("/api/observations/", self._list_observations)
        app.router.add_post("/api/observations/", self._create_observations)
        app.router.add_post("/api/observations/cancel/", self._cancel)
        app.router.add_patch("/api/configurationstatus/{id}/", self._patch_status)
        return app

    @web.middleware
    async def _auth(self, request: web.Request, handler: Any) -> web.StreamResponse:
        if request.headers.get("Authorization") != f"Token {TOKEN}":
            return web.json_response({"detail": "Invalid token."}, status=401)
        response: web.StreamResponse = await handler(request)
        return response

    async def _schedulable(self, request: web.Request) -> web.Response:
        self.queries.append(dict(request.query))
        return web.json_response(self.groups)  # a plain list, as the portal answers

    async def _last_changed(self, request: web.Request) -> web.Response:
        return web.json_response({"last_change_time": self.last_change})

    async def _create_observations(self, request: web.Request) -> web.Response:
        created = await request.json()
        for document in created:
            statuses = [
                {"id": 900 + len(self.observations) * 10 + i, "state": "PENDING", **status}
                for i, status in enumerate(document["configuration_statuses"])
            ]
            self.observations.append(
                {
                    **document,
                    "id": 333978933 + len(self.observations),
                    "state": "PENDING",
                    "configuration_statuses": statuses,
                }
            )
        return web.json_response({"num_created": len(created), "errors": {}}, status=201)

    async def _cancel(self, request: web.Request) -> web.Response:
        selection = await request.json()
        self.canceled.append(selection)
        count = 0
        for observation in self.observations:
            if observation["state"] == "PENDING" and observation["end"] > selection["start"]:
                observation["state"] = "CANCELED"
                count += 1
        return web.json_response({"canceled": count})

    async def _list_observations(self, request: web.Request) -> web.Response:
        query = request.query
        found = [o for o in self.observations if "state" not in query or o["state"] == query["state"]]
        if "request_num" in query:
            found = [o for o in found if str(o["request"]) == query["request_num"]]
        offset = int(query.get("offset", 0))
        page = found[offset : offset + self.page_size]
        following = str(request.url.update_query(offset=offset + self.page_size))
        return web.json_response(
            {
                "count": len(found),
                "next": following if offset + self.page_size < len(found) else None,
                "previous": None,
                "results": page,
            }
        )

    async def _patch_status(self, request: web.Request) -> web.Response:
        body = await request.json()
        self.patches.append((int(request.match_info["id"]), body))
        return web.json_response({"id": int(request.match_info["id"]), **body})


@pytest.fixture
async def portal() -> AsyncIterator[tuple[ReplayPortal, str]]:
    replay = ReplayPortal()
    runner = web.AppRunner(replay.app())
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    port = site._server.sockets[0].getsockname()[1]  # type: ignore[union-attr]
    yield replay, f"http://127.0.0.1:{port}"
    await runner.cleanup()


def _archive(url: str, clock: ManualClock) -> LcoPortalArchive:
    return LcoPortalArchive(
        url,
        TOKEN,
        site="sim",
        enclosure="doma",
        telescope="0m4a",
        instrument_name="simcam",
        telescope_classes=["0m4"],
        clock=clock,
        poll_interval=0,
    )


async def test_schedulable_requests_become_tasks(portal: tuple[ReplayPortal, str]) -> None:
    replay, url = portal
    async with _archive(url, ManualClock(NIGHT)) as archive:
        tasks = await archive.get_schedulable_tasks()
    assert [t.id for t in tasks] == ["2722445"]
    task = tasks[0]
    assert (task.group_id, task.name, task.proposal, task.ipp) == (
        "1350420",
        "K2-22 transit",
        "PROPOSAL-A-2021",
        1.05,
    )
    expose, bias = task.request.configurations
    assert expose.type is ConfigurationType.EXPOSE and bias.type is ConfigurationType.BIAS
    assert isinstance(expose.target, Target) and expose.target.proper_motion_ra == -27.108
    assert expose.instrument_configs[0].binning == 2 and expose.instrument_configs[0].extra_params == {
        "defocus": 0
    }
    assert expose.constraints.max_lunar_phase == 0.8 and bias.constraints.max_lunar_phase == 1.0
    assert task.request.location.site is None  # "" means any
    assert replay.queries == [
        {"start": NIGHT.isoformat(), "end": (NIGHT + timedelta(days=2)).isoformat(), "telescope_class": "0m4"}
    ]


async def test_a_group_the_model_rejects_is_skipped_with_its_field_named(
    portal: tuple[ReplayPortal, str], caplog: pytest.LogCaptureFixture
) -> None:
    replay, url = portal
    bad = copy.deepcopy(REQUEST_GROUP)
    bad["id"] = 7
    bad["requests"][0]["id"] = 8
    bad["requests"][0]["configurations"][0]["instrument_configs"][0]["exposure_time"] = 0
    replay.groups.append(bad)
    async with _archive(url, ManualClock(NIGHT)) as archive:
        assert [t.id for t in await archive.get_schedulable_tasks()] == ["2722445"]
        with pytest.raises(TaskNotFoundError, match="no schedulable request '8'"):
            await archive.get_task("8")
    assert (
        "request group 7: requests[0].configurations[0].instrument_configs[0].exposure_time: must be > 0"
        in (caplog.text)
    )


async def test_schedule_upload_read_back_and_status_updates(portal: tuple[ReplayPortal, str]) -> None:
    replay, url = portal
    clock = ManualClock(NIGHT)
    heard: list[TaskChange] = []
    async with _archive(url, clock) as archive:
        archive.add_listener(heard.append)
        task = (await archive.get_schedulable_tasks())[0]
        entry = PlannedSlot(task.id, NIGHT, NIGHT + timedelta(minutes=20))
        later = PlannedSlot(task.id, NIGHT + timedelta(hours=3), NIGHT + timedelta(hours=3, minutes=20))
        await archive.write_schedule([entry, later], replace_from=NIGHT)
        assert replay.canceled[0]["site"] == "sim" and replay.canceled[0]["start"] == NIGHT.isoformat()
        assert replay.observations[0] | {"id": 0, "state": "", "configuration_statuses": []} == {
            "request": 2722445,
            "site": "sim",
            "enclosure": "doma",
            "telescope": "0m4a",
            "start": NIGHT.isoformat(),
            "end": (NIGHT + timedelta(minutes=20)).isoformat(),
            "id": 0,
            "state": "",
            "configuration_statuses": [],
        }
        assert [s["configuration"] for s in replay.observations[0]["configuration_statuses"]] == [
            7011091,
            7011092,
        ]
        # Page size 1: reading back follows "next".
        assert await archive.read_schedule() == [entry, later]

        await archive.mark_started(task.id)
        assert replay.patches == [(900, {"state": "ATTEMPTED"})]
        clock.advance(600)
        half = TaskProgress(exposures_done=((2,), (0,)))
        failed = await archive.mark_failed(task.id, "clouds", half)
        assert failed.state is TaskState.FAILED and failed.status.progress == half
        (first_id, first), (second_id, second) = replay.patches[1:]
        assert (first_id, first["state"], second_id, second["state"]) == (900, "FAILED", 901, "NOT_ATTEMPTED")
        assert first["summary"]["time_completed"] == 240 and first["summary"]["reason"] == "clouds"
        assert first["summary"]["start"] == NIGHT.isoformat()
        assert first["summary"]["end"] == (NIGHT + timedelta(seconds=600)).isoformat()
        assert heard[-1] == TaskChange(frozenset({task.id}))

        # A new plan from now on cancels the rest and uploads nothing.
        await archive.write_schedule([], replace_from=NIGHT + timedelta(hours=1))
        assert await archive.read_schedule() == [entry]


async def test_a_retry_keeps_the_progress_and_reports_only_its_own_time(
    portal: tuple[ReplayPortal, str],
) -> None:
    replay, url = portal
    clock = ManualClock(NIGHT)
    async with _archive(url, clock) as archive:
        task = (await archive.get_schedulable_tasks())[0]
        first = PlannedSlot(task.id, NIGHT, NIGHT + timedelta(minutes=20))
        await archive.write_schedule([first], replace_from=NIGHT)
        await archive.mark_started(task.id)
        clock.advance(300)
        half = TaskProgress(exposures_done=((2,), (0,)))
        await archive.mark_failed(task.id, "interrupted by bad weather", half)

        # Planned again later: the task still knows what was done, so the runner resumes from it.
        retry = PlannedSlot(task.id, NIGHT + timedelta(hours=2), NIGHT + timedelta(hours=2, minutes=20))
        await archive.write_schedule([retry], replace_from=NIGHT + timedelta(hours=1))
        clock.advance(7200)
        again = await archive.mark_started((await archive.get_schedulable_tasks())[0].id)
        assert again.status.progress.exposures_done == ((2,), (0,))
        clock.advance(300)
        await archive.mark_finished(task.id, TaskProgress(exposures_done=((3,), (2,))))

        # The second observation completed both configurations, having exposed one 120-s frame.
        retry_statuses = [s["id"] for s in replay.observations[-1]["configuration_statuses"]]
        patches = dict(replay.patches[-2:])
        assert list(patches) == retry_statuses
        assert [p["state"] for p in patches.values()] == ["COMPLETED", "COMPLETED"]
        assert [p["summary"]["time_completed"] for p in patches.values()] == [120, 0]


async def test_changes_are_polled_and_errors_named(portal: tuple[ReplayPortal, str]) -> None:
    replay, url = portal
    async with _archive(url, ManualClock(NIGHT)) as archive:
        assert await archive.check_for_changes()  # the first answer is news
        assert not await archive.check_for_changes()
        replay.last_change = "2026-11-10T20:00:00Z"
        assert await archive.check_for_changes()
    async with LcoPortalClient(url, "wrong-token") as client:
        with pytest.raises(PortalError, match=r"HTTP 401 \(check the API token\).*Invalid token") as caught:
            await client.last_changed()
        assert caught.value.status == 401
    async with LcoPortalClient("http://127.0.0.1:9", TOKEN, timeout=5) as client:
        with pytest.raises(PortalError, match=re.escape("GET http://127.0.0.1:9/api/last_changed/")):
            await client.last_changed()
    with pytest.raises(PortalError, match="not open"):
        await LcoPortalClient(url, TOKEN).last_changed()


async def test_window_over_means_not_schedulable(portal: tuple[ReplayPortal, str]) -> None:
    _, url = portal
    async with _archive(url, ManualClock(datetime(2026, 11, 11, 6, tzinfo=UTC))) as archive:
        assert await archive.get_schedulable_tasks() == []
