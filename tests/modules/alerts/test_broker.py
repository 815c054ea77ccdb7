"""The alerts module against a real VOEvent broker (Comet): notices published by the tests become
rapid-response requests; updates move them (also after a restart of the listener), retractions
cancel them, bad notices change nothing."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import pytest

from nightcrew.config import load_config
from nightcrew.events import RapidResponseEvent, TasksChangedEvent
from nightcrew.modules import Module
from nightcrew.modules.alerts import AlertListener
from nightcrew.night.build import files_environ
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.tasks import ObservationType, TaskState
from nightcrew.testing import Observatory, wait_for
from nightcrew.testing.comet import CometBroker

from .voevents import STREAM, notice

#: The example a user copies (its broker and data folder from the environment, as documented).
EXAMPLE = Path(__file__).parents[3] / "examples/observatory/options/alerts.yaml"


class Heard(Module):
    """Notes the task events the listener sends."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.rapid: list[tuple[str, ...]] = []
        self.changes: list[tuple[str, tuple[str, ...]]] = []

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(RapidResponseEvent, self.on_rapid)
        await self.comm.register_event(TasksChangedEvent, self.on_change)

    async def on_rapid(self, event: RapidResponseEvent, sender: str) -> None:
        self.rapid.append(event.ids)

    async def on_change(self, event: TasksChangedEvent, sender: str) -> None:
        self.changes.append((event.change, event.ids))


async def test_notices_become_requests_updates_move_them_and_retractions_cancel(
    comet: CometBroker, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    environ = {**files_environ(), "ALERTS_BROKER": comet.address, "OBSERVATORY_DATA": str(tmp_path)}
    config = load_config(EXAMPLE, environ=environ)
    assert config["class"] == "nightcrew.modules.alerts.AlertListener"
    async with Observatory(speed=1.0) as obs:  # the broker runs in wall time
        archive = SqliteTaskArchive(tmp_path / "tasks.sqlite", clock=obs.clock, poll_interval=0)  # to look
        heard = await obs.start(Heard, "heard")
        options = {key: value for key, value in config.items() if key != "class"}
        listener = await obs.start(AlertListener, "alerts", **options)
        await wait_for(lambda: listener.connected, 20, message="the listener did not connect")
        await archive.open()  # the one the listener's file names, made by the listener

        async def tasks() -> list[Any]:
            return sorted(await archive.list_tasks(), key=lambda t: int(t.id))

        with caplog.at_level(logging.INFO, logger="nightcrew.modules.alerts"):
            # Bad input first: one line each, nothing stored, and the listener keeps listening.
            assert await comet.publish(b"<VOEvent>not closed") == "closed"  # refused by the broker
            assert await comet.publish(notice("bad", dec=120.0)) == "ack"
            assert await comet.publish(notice("drill", role="test")) == "ack"
            assert await comet.publish(notice("pos1", error=0.2)) == "ack"
            await wait_for(lambda: bool(heard.rapid), 20, message="no request from the GRB notice")
            (first,) = await tasks()
            assert first.observation_type is ObservationType.RAPID_RESPONSE and first.priority == 100
            assert heard.rapid == [(first.id,)]
            out_of_range = [r for r in caplog.records if "#bad" in r.getMessage()]
            assert [r.getMessage() for r in out_of_range] == [
                f"alerts: ignored a notice: {STREAM}#bad: coordinates out of range (ra 56.75, dec 120)"
            ]
            assert f"{STREAM}#drill: not observed: role 'test' is not one of observation" in caplog.text

            # An update with a smaller error box and a refined position moves the request.
            update = notice("pos2", ra=56.80, error=0.01, cites=(("supersedes", f"{STREAM}#pos1"),))
            assert await comet.publish(update) == "ack"
            await wait_for(lambda: len(heard.rapid) == 2, 20, message="no request from the update")
            old, new = await tasks()
            assert old.state is TaskState.CANCELED and f"superseded by {STREAM}#pos2" in (
                old.status.reason or ""
            )
            target = new.request.configurations[0].target
            assert target is not None and target.ra == 56.80 and new.state is TaskState.PENDING

            # Restarted, the listener reads its events back from the archive (Comet itself refuses
            # a notice it has seen, so no repeat is sent): a follow-up with a larger error box keeps
            # the request, one with a smaller box moves it, a retraction of the first cancels it.
            await listener.close()
            listener = await obs.start(AlertListener, "alerts", **options)
            await wait_for(lambda: listener.connected, 20, message="the listener did not reconnect")
            assert "alerts: 2 earlier alert requests read back from the archive" in caplog.text
            wider = notice("xrt1", error=0.05, cites=(("followup", f"{STREAM}#pos2"),))
            assert await comet.publish(wider) == "ack"
            await wait_for(lambda: "#xrt1: request" in caplog.text, 20, message="no word on the follow-up")
            assert f"request {new.id} kept: error radius 0.05° is not smaller than its 0.01°" in caplog.text
            narrower = notice("xrt2", ra=56.81, error=0.002, cites=(("followup", f"{STREAM}#pos2"),))
            assert await comet.publish(narrower) == "ack"
            await wait_for(lambda: len(heard.rapid) == 3, 20, message="the follow-up did not move it")
            moved = (await tasks())[-1]
            assert (await archive.get_task(new.id)).state is TaskState.CANCELED
            assert moved.state is TaskState.PENDING
            assert (
                await comet.publish(
                    notice("retr", ra=None, retraction=True, cites=(("retraction", f"{STREAM}#pos1"),))
                )
                == "ack"
            )
            await wait_for(lambda: ("cancelled", (moved.id,)) in heard.changes, 20, message="not cancelled")
            assert (await archive.get_task(moved.id)).state is TaskState.CANCELED
            assert len(await tasks()) == 3 and len(heard.rapid) == 3
        await archive.close()
