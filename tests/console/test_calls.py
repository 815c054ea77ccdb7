"""Calling methods from the browser: results, the shell's syntax, and every kind of failure."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

from nightcrew.modules.sim import SimRoof, SimTelescope

from .conftest import OPERATOR, OPERATOR_PASSWORD, VIEWER, VIEWER_PASSWORD, ApiClient, Observatory

PLEIADES = (56.75, 24.12)  # high at the epoch


@pytest.fixture
async def operator(observatory: Observatory, clients: Callable[[str], ApiClient]) -> ApiClient:
    await observatory.start(SimTelescope, "telescope", init_time=1.0, seed=1)
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    return client


async def test_the_operator_moves_the_telescope(operator: ApiClient) -> None:
    assert await operator.call("telescope", "init") == (200, {"result": None})
    status, body = await operator.post(
        "/api/call",
        {"module": "telescope", "method": "move_radec", "args": {"ra": PLEIADES[0], "dec": PLEIADES[1]}},
    )
    assert (status, body) == (200, {"result": None})
    status, body = await operator.call("telescope", "get_radec")
    assert status == 200
    assert body["result"] == [pytest.approx(PLEIADES[0], abs=0.01), pytest.approx(PLEIADES[1], abs=0.01)]
    assert (await operator.call("telescope", "get_motion_status"))[1] == {"result": "tracking"}


async def test_a_remote_error_keeps_its_class_and_module(operator: ApiClient) -> None:
    status, body = await operator.call("telescope", "move_radec", *PLEIADES)  # not initialised
    assert status == 502
    assert body["error"]["class"] == "MoveError" and body["error"]["module"] == "telescope"
    assert "init() first" in body["error"]["message"]


async def test_the_shell_runs_a_line_and_names_what_does_not_parse(operator: ApiClient) -> None:
    status, body = await operator.post("/api/shell", {"line": "telescope.get_motion_status()"})
    assert (status, body) == (
        200,
        {"module": "telescope", "method": "get_motion_status", "args": [], "result": "parked"},
    )
    for line, message in [
        ("telescope.", "not a call: 'telescope.'"),
        ("telescope.move_radec(ra=1, dec=2)", "keyword arguments are not supported"),
        ("telescope.move_radec(__import__('os'), 1)", "arguments must be literals"),
        ("move_radec(1, 2)", "expected module.method(arguments)"),
        ("telescope.move_radec(" + "[" * 200_000, "longer than 10000 characters"),
    ]:
        status, body = await operator.post("/api/shell", {"line": line})
        assert status == 400, line
        assert body["error"]["class"] == "InvalidArgumentError" and message in body["error"]["message"]


@pytest.mark.parametrize(
    ("call", "status", "error_class", "message"),
    [
        ({"module": "dome", "method": "init", "args": []}, 404, "RemoteError", "module 'dome' is not online"),
        ({"module": "telescope", "method": "fly", "args": []}, 404, "InterfaceError", "has no method 'fly'"),
        (
            {"module": "telescope", "method": "move_radec", "args": [1.0]},
            400,
            "InvalidArgumentError",
            "'dec'",
        ),
        ({"module": "telescope", "method": "move_radec", "args": ["far", 2]}, 400, "CodecError", "'ra'"),
        (
            {"module": "telescope", "method": "move_radec", "args": {"az": 1}},
            400,
            "InvalidArgumentError",
            "az",
        ),
        ({"module": "telescope", "method": "move_radec", "args": 3}, 400, "InvalidArgumentError", "'args'"),
        ({"method": "init"}, 400, "InvalidArgumentError", "missing field 'module'"),
    ],
)
async def test_bad_calls_get_one_clear_error(
    operator: ApiClient, call: dict[str, Any], status: int, error_class: str, message: str
) -> None:
    answer = await operator.post("/api/call", call)
    assert answer[0] == status
    assert answer[1]["error"]["class"] == error_class and message in answer[1]["error"]["message"]


async def test_malformed_requests_are_refused_and_the_console_stays_up(operator: ApiClient) -> None:
    async with operator.http.post(
        operator.base + "/api/call",
        data=b"{not json",
        headers={"X-CSRF-Token": operator.csrf, "Content-Type": "application/json"},
    ) as response:
        assert response.status == 400
        assert "not JSON" in (await response.json())["error"]["message"]
    status, body = await operator.get("/api/nothing-here")
    assert status == 404 and body["error"]["class"] == "HTTPError"
    status, body = await operator.post("/api/modules", {})
    assert status == 405 and body["error"]["class"] == "HTTPError"
    assert (await operator.call("telescope", "get_motion_status"))[0] == 200


async def test_a_module_that_vanished_is_reported_as_not_online(
    observatory: Observatory, operator: ApiClient
) -> None:
    roof = await observatory.start(SimRoof, "roof")
    assert (await operator.call("roof", "get_motion_status"))[0] == 200
    await roof.close()
    status, body = await operator.call("roof", "open_roof")
    assert status == 404 and body["error"]["message"] == "module 'roof' is not online"


async def test_a_page_reads_several_values_at_once(
    observatory: Observatory, clients: Callable[[str], ApiClient], operator: ApiClient
) -> None:
    viewer = clients(operator.base)
    await viewer.login(VIEWER, VIEWER_PASSWORD)
    calls = [
        {"module": "telescope", "method": "get_motion_status"},
        {"module": "telescope", "method": "get_radec", "args": []},
        {"module": "gone", "method": "get_state"},
    ]
    status, body = await viewer.post("/api/read", {"calls": calls})
    assert status == 200
    first, second, third = body["results"]
    assert first == {"result": "parked"}
    assert "result" in second or second["error"]["module"] == "telescope"
    assert third["error"]["class"] == "RemoteError"
    status, body = await viewer.post("/api/read", {"calls": [{"module": "telescope", "method": "init"}]})
    assert status == 403 and "read methods only" in body["error"]["message"]
