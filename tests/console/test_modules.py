"""The module list: built from the interfaces, following modules as they come, go and change state."""

from __future__ import annotations

from collections.abc import Callable

from nightcrew.events import ModuleStateChangedEvent
from nightcrew.interfaces import ModuleState
from nightcrew.modules.sim import SimCamera, SimRoof, SimTelescope

from .conftest import (
    OPERATOR,
    OPERATOR_PASSWORD,
    VIEWER,
    VIEWER_PASSWORD,
    ApiClient,
    Observatory,
    open_socket,
)


async def test_the_list_describes_each_module_by_what_its_interfaces_offer(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    await observatory.start(SimTelescope, "telescope")
    await observatory.start(SimRoof, "roof")
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(VIEWER, VIEWER_PASSWORD)
    status, body = await client.get("/api/modules")
    assert status == 200
    modules = {m["name"]: m for m in body["modules"]}
    assert sorted(modules) == ["roof", "telescope"]  # not the console itself
    telescope = modules["telescope"]
    assert telescope["state"] == "ready" and telescope["error"] == "" and telescope["version"]
    assert {"ITelescope", "IPointingRaDec", "IMotion", "IModule"} <= set(telescope["interfaces"])
    assert "IWindow" not in telescope["interfaces"] and "set_window" not in telescope["methods"]
    move = telescope["methods"]["move_radec"]
    assert move["interface"] == "IPointingRaDec" and move["read"] is False
    assert [(p["name"], p["type"], p["required"]) for p in move["params"]] == [
        ("ra", "float", True),
        ("dec", "float", True),
    ]
    assert telescope["methods"]["get_motion_status"]["returns"] == "MotionStatus"
    assert telescope["methods"]["get_motion_status"]["read"] is True
    assert "open_roof" in modules["roof"]["methods"] and "move_radec" not in modules["roof"]["methods"]
    assert telescope["uptime_s"] >= 0


async def test_enum_parameters_list_their_choices(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    await observatory.start(SimCamera, "camera", detector={"chip_width": 64, "chip_height": 64})
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(VIEWER, VIEWER_PASSWORD)
    status, camera = await client.get("/api/modules/camera")
    assert status == 200
    image_type = camera["methods"]["grab_data"]["params"][1]
    assert image_type["name"] == "image_type" and image_type["type"] == "ImageType | None"
    assert image_type["required"] is False and image_type["default"] is None
    assert "skyflat" in image_type["choices"]
    status, body = await client.get("/api/modules/nothing")
    assert status == 404 and body["error"]["message"] == "module 'nothing' is not online"


async def test_modules_that_start_and_stop_join_and_leave_the_live_list(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(VIEWER, VIEWER_PASSWORD)
    socket = await open_socket(client)
    assert socket.messages[0]["modules"] == []
    roof = await observatory.start(SimRoof, "roof")
    joined = await socket.wait_for(lambda m: m["type"] == "module_joined", "roof joining")
    assert joined["module"]["name"] == "roof" and "IRoof" in joined["module"]["interfaces"]
    if joined["module"]["state"] != "ready":  # it joins the network before it is ready
        await socket.wait_for(
            lambda m: m["type"] == "module_state" and m["name"] == "roof" and m["state"] == "ready", "ready"
        )
    await roof.close()
    left = await socket.wait_for(lambda m: m["type"] == "module_left", "roof leaving")
    assert left == {"type": "module_left", "name": "roof"}
    assert (await client.get("/api/modules"))[1]["modules"] == []


async def test_an_error_state_shows_and_the_operator_resets_it(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    roof = await observatory.start(SimRoof, "roof")
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    socket = await open_socket(client)
    roof.set_error("motor stalled")
    changed = await socket.wait_for(lambda m: m["type"] == "module_state", "the roof's error")
    assert changed == {"type": "module_state", "name": "roof", "state": "error", "error": "motor stalled"}
    status, body = await client.call("roof", "open_roof")
    assert status == 502
    assert body["error"]["class"] == "ModuleError" and body["error"]["module"] == "roof"
    assert await client.call("roof", "reset_error") == (200, {"result": True})
    await socket.wait_for(
        lambda m: m["type"] == "module_state" and m["state"] == "ready" and m["error"] == "", "ready again"
    )
    modules = (await client.get("/api/modules"))[1]["modules"]
    assert [(m["name"], m["state"], m["error"]) for m in modules] == [("roof", "ready", "")]


async def test_a_module_announcing_its_state_is_shown_at_once(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    roof = await observatory.start(SimRoof, "roof")
    console = await observatory.start_console(status_interval=3600.0)  # no poll would find it
    client = clients(console.url)
    await client.login(VIEWER, VIEWER_PASSWORD)
    socket = await open_socket(client)
    event = ModuleStateChangedEvent(
        last=ModuleState.READY, current=ModuleState.ERROR, error="rain sensor wet"
    )
    await roof.comm.send_event(event)
    changed = await socket.wait_for(lambda m: m["type"] == "module_state", "the announced state")
    assert changed == {"type": "module_state", "name": "roof", "state": "error", "error": "rain sensor wet"}
