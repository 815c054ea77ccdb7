"""Trigger: an event makes it call another module's method with the event's fields."""

from __future__ import annotations

import logging
from abc import abstractmethod
from typing import Any

import pytest

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module
from nightcrew.modules.utils import Trigger
from nightcrew.testing import Observatory
from tests.modules.devices import GradientCamera


class ITestImageArchive(Interface):
    """What the paper's trigger example calls: an archive told about new images."""

    @abstractmethod
    async def add_image(self, filename: str, kind: str | None = None) -> None: ...


class Archive(Module, ITestImageArchive):
    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.added: list[tuple[str, str | None]] = []

    async def add_image(self, filename: str, kind: str | None = None) -> None:
        self.added.append((filename, kind))


async def test_new_image_calls_archive_add_image(fast_observatory: Observatory) -> None:
    obs = fast_observatory
    archive = await obs.start(Archive, "archive")
    await obs.start(
        Trigger,
        "trigger",
        triggers=[
            {"event": "NewImageEvent", "module": "archive", "method": "add_image", "args": ["filename"]},
            {
                "event": "NewImageEvent",
                "module": "archive",
                "method": "add_image",
                "args": ["filename"],
                "kwargs": {"kind": "image_type"},
                "sender": "other-camera",
            },
        ],
    )
    camera = await obs.start(GradientCamera, "camera")
    filename = await camera.grab_data()
    await obs.wait_for(lambda: bool(archive.added), 2000.0, interval=1.0)
    assert archive.added == [(filename, None)]  # the second trigger waits for another sender


async def test_kwargs_from_event_fields_and_a_failing_call_is_logged(
    fast_observatory: Observatory, caplog: pytest.LogCaptureFixture
) -> None:
    obs = fast_observatory
    archive = await obs.start(Archive, "archive")
    await obs.start(
        Trigger,
        "trigger",
        triggers=[
            {"event": "NewImageEvent", "module": "archive", "method": "no_such_method", "args": ["filename"]},
            {
                "event": "NewImageEvent",
                "module": "archive",
                "method": "add_image",
                "kwargs": {"filename": "filename", "kind": "image_type"},
            },
        ],
    )
    camera = await obs.start(GradientCamera, "camera")
    with caplog.at_level(logging.ERROR):
        filename = await camera.grab_data()
        await obs.wait_for(lambda: bool(archive.added), 2000.0, interval=1.0)
    assert archive.added == [(filename, "object")]
    assert "module 'archive' offers no method no_such_method()" in caplog.text


@pytest.mark.parametrize(
    ("entry", "key", "message"),
    [
        ({"event": "NoEvent", "module": "a", "method": "m"}, "triggers[0].event", "unknown event 'NoEvent'"),
        ({"event": "NewImageEvent", "module": "a"}, "triggers[0].method", "'method' must be"),
        (
            {"event": "NewImageEvent", "module": "a", "method": "m", "args": ["nope"]},
            "triggers[0].args",
            "NewImageEvent has no field 'nope'; it has: filename, image_type",
        ),
        ({"event": "NewImageEvent", "module": "a", "method": "m", "when": 1}, "triggers[0]", "unknown keys"),
    ],
)
def test_config_errors_name_the_key(entry: dict[str, Any], key: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message) as info:
        build_object({"class": "nightcrew.modules.utils.Trigger", "name": "t", "triggers": [entry]})
    assert info.value.key == key
