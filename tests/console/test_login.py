"""Logging in and out, roles, CSRF, the brake on guessing, and accounts in the config."""

from __future__ import annotations

import io
import logging
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import aiohttp
import pytest

from nightcrew.cli.main import main
from nightcrew.config import build_object, load_config, validate_config
from nightcrew.errors import ConfigError
from nightcrew.modules import Module
from nightcrew.modules.console import WebConsole, hash_password, verify_password
from nightcrew.modules.sim import SimTelescope
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.security import LoginLimiter

from .conftest import OPERATOR, OPERATOR_PASSWORD, VIEWER, VIEWER_PASSWORD, ApiClient, Observatory


def test_a_password_hash_verifies_only_its_password() -> None:
    stored = hash_password("correct horse")
    assert stored.startswith("scrypt$16384$8$1$")
    assert verify_password("correct horse", stored)
    assert not verify_password("correct hors", stored)
    assert hash_password("correct horse") != stored  # a fresh salt every time


async def test_a_wrong_user_and_a_wrong_password_get_the_same_answer(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    client = clients(console.url)
    wrong_password = await client.login(OPERATOR, "guess")
    wrong_user = await client.login("mallory", OPERATOR_PASSWORD)
    assert (
        wrong_password
        == wrong_user
        == (
            401,
            {"error": {"class": "LoginError", "message": "wrong user name or password", "module": None}},
        )
    )
    assert (await client.get("/api/modules"))[0] == 401


async def test_logging_in_sets_a_strict_http_only_cookie_and_logging_out_ends_the_session(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    client = clients(console.url)
    async with client.http.post(
        client.base + "/api/login", json={"user": OPERATOR, "password": OPERATOR_PASSWORD}
    ) as response:
        assert response.status == 200
        cookie = response.cookies["nightcrew_session"]
        body = await response.json()
    assert cookie["httponly"] and cookie["samesite"] == "Strict" and cookie["path"] == "/"
    assert not cookie["secure"]  # plain HTTP on loopback; cookie_secure behind a TLS proxy
    assert body["user"] == OPERATOR and body["role"] == "operator" and len(body["csrf_token"]) > 20
    client.csrf = body["csrf_token"]
    assert (await client.get("/api/session"))[1]["csrf_token"] == client.csrf
    assert (await client.post("/api/logout", {}))[0] == 200
    status, answer = await client.get("/api/modules")
    assert status == 401 and answer["error"]["class"] == "NotLoggedInError"


async def test_a_post_without_the_csrf_token_is_refused(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    telescope = await observatory.start(SimTelescope, "telescope")
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    for token in ("", "not-the-token"):
        status, body = await client.post(
            "/api/call", {"module": "telescope", "method": "init", "args": []}, csrf=token
        )
        assert status == 403 and body["error"]["class"] == "CsrfError"
    assert await telescope.get_motion_status() == "parked"  # nothing was called


async def test_a_viewer_reads_but_calls_nothing_that_changes_anything(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    telescope = await observatory.start(SimTelescope, "telescope")
    client = clients(console.url)
    assert (await client.login(VIEWER, VIEWER_PASSWORD))[1]["role"] == "viewer"
    assert await client.call("telescope", "get_motion_status") == (200, {"result": "parked"})
    status, body = await client.call("telescope", "init")
    assert status == 403
    assert body["error"] == {
        "class": "ForbiddenError",
        "message": "a viewer may only call read methods, not init()",
        "module": None,
    }
    status, body = await client.post("/api/shell", {"line": "telescope.init()"})
    assert status == 403
    status, body = await client.post("/api/events", {"type": "TestEvent", "fields": {}})
    assert status == 403 and body["error"]["class"] == "ForbiddenError"
    assert await telescope.get_motion_status() == "parked"


async def test_guessing_is_stopped_for_the_user_name_even_with_the_right_password(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console(login_attempts=3)
    client = clients(console.url)
    for _ in range(3):
        assert (await client.login(OPERATOR, "guess"))[0] == 401
    status, body = await client.login(OPERATOR, OPERATOR_PASSWORD)
    assert status == 429 and body["error"]["class"] == "RateLimitedError"
    async with client.http.post(
        client.base + "/api/login", json={"user": OPERATOR, "password": OPERATOR_PASSWORD}
    ) as response:
        assert 0 < int(response.headers["Retry-After"]) <= 301
    assert (await client.login(VIEWER, VIEWER_PASSWORD))[0] == 200  # others on this address still may


async def test_guessing_across_many_names_is_stopped_for_the_address(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console(login_attempts=2)
    client = clients(console.url)
    for number in range(8):  # four times the per-name limit, each name below it
        assert (await client.login(f"user{number}", "guess"))[0] == 401
    status, body = await client.login(VIEWER, VIEWER_PASSWORD)
    assert status == 429 and body["error"]["class"] == "RateLimitedError"


def test_the_limiter_forgets_failures_after_its_window() -> None:
    now = [1000.0]
    limiter = LoginLimiter(2, 60.0, now=lambda: now[0])
    limiter.failed(["user:a"])
    limiter.failed(["user:a"])
    assert limiter.retry_after(["user:a", "address:x"]) == pytest.approx(60.0)
    assert limiter.retry_after(["user:b"]) == 0.0
    now[0] += 59.0
    assert limiter.retry_after(["user:a"]) == pytest.approx(1.0)
    now[0] += 1.0
    assert limiter.retry_after(["user:a"]) == 0.0


async def test_passwords_never_reach_the_log(
    observatory: Observatory, clients: Callable[[str], ApiClient], caplog: pytest.LogCaptureFixture
) -> None:
    console = await observatory.start_console()
    client = clients(console.url)
    with caplog.at_level(logging.DEBUG):
        await client.login(OPERATOR, "a-wrong-secret")
        await client.login(OPERATOR, OPERATOR_PASSWORD)
    assert "a-wrong-secret" not in caplog.text and OPERATOR_PASSWORD not in caplog.text
    assert "scrypt$" not in repr(console.accounts)


@pytest.mark.parametrize(
    ("accounts", "key", "message"),
    [
        ({"ann": {"password_hash": "plain", "role": "operator"}}, "accounts.ann.password_hash", "scrypt"),
        ({"ann": {"password_hash": hash_password("x"), "role": "admin"}}, "accounts.ann.role", "viewer"),
        ({"ann": {"password": "x"}}, "accounts.ann", "unknown keys password"),
    ],
)
def test_a_bad_account_is_named_when_the_console_is_built(
    accounts: dict[str, Any], key: str, message: str
) -> None:
    with pytest.raises(ConfigError, match=message) as raised:
        WebConsole(name="console", accounts=accounts)
    assert raised.value.key == key


async def test_the_page_options_are_public_and_widgets_need_a_session(
    observatory: Observatory, clients: Callable[[str], ApiClient], tmp_path: Path
) -> None:
    page = tmp_path / "dewar.html"
    page.write_text("<p>dewar pressure</p>")
    console = await observatory.start_console(
        title="Hill top",
        show_shell=False,
        show_modules=["camera"],
        widgets={"camera": {"title": "Dewar", "file": str(page)}},
    )
    client = clients(console.url)
    assert await client.get("/api/config") == (
        200,
        {
            "title": "Hill top",
            "show_shell": False,
            "show_events": True,
            "show_status": True,
            "show_modules": ["camera"],
            "show_tasks": False,
            "widgets": {"camera": {"title": "Dewar", "url": "/api/widgets/camera"}},
        },
    )
    assert (await client.get_bytes("/api/widgets/camera"))[0] == 401
    await client.login(VIEWER, VIEWER_PASSWORD)
    status, body, headers = await client.get_bytes("/api/widgets/camera")
    assert (
        status == 200 and body == b"<p>dewar pressure</p>" and headers["Content-Type"].startswith("text/html")
    )
    assert (await client.get_bytes("/api/widgets/roof"))[0] == 404
    status, index, _ = await client.get_bytes("/")
    assert status == 200 and b"<html" in index.lower()


def test_a_widget_file_that_does_not_exist_is_named(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="no such file") as raised:
        WebConsole(
            name="console", widgets={"camera": {"title": "Dewar", "file": str(tmp_path / "none.html")}}
        )
    assert raised.value.key == "widgets.camera.file"


async def test_a_page_of_another_site_can_neither_log_in_nor_open_the_socket(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    client = clients(console.url)
    evil = {"Origin": "http://evil.example"}
    login = {"user": OPERATOR, "password": OPERATOR_PASSWORD}
    async with client.http.post(client.base + "/api/login", json=login, headers=evil) as response:
        assert response.status == 403
        assert (await response.json())["error"]["class"] == "CsrfError"
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
        await client.http.ws_connect(client.base + "/api/ws", headers=evil)
    assert refused.value.status == 403
    same_site = {"Origin": client.base}
    async with client.http.ws_connect(client.base + "/api/ws", headers=same_site) as socket:
        assert (await socket.receive_json())["type"] == "hello"


def test_the_example_configuration_builds_a_console() -> None:
    path = Path(__file__).resolve().parents[2] / "examples" / "console.yaml"
    config = load_config(path)
    validate_config(config, Module)
    console = build_object({**config, "name": "console"}, Module)
    assert isinstance(console, WebConsole) and console.port == 37180
    assert {a.role.value for a in console.accounts.values()} == {"operator", "viewer"}
    assert isinstance(console.task_archive, SqliteTaskArchive)  # built, opened only with the console


async def test_behind_a_tls_proxy_the_cookie_is_secure(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console(cookie_secure=True)
    client = clients(console.url)
    async with client.http.post(
        client.base + "/api/login", json={"user": VIEWER, "password": VIEWER_PASSWORD}
    ) as response:
        assert response.status == 200 and response.cookies["nightcrew_session"]["secure"]


def test_nightcrew_console_hashes_a_password_from_a_pipe(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(sys, "stdin", io.StringIO("a long pass phrase\n"))
    assert main(["console", "--hash-password"]) == 0
    stored = capsys.readouterr().out.strip()
    assert verify_password("a long pass phrase", stored) and not verify_password(
        "a long pass phrase\n", stored
    )
    monkeypatch.setattr(sys, "stdin", io.StringIO("\n"))
    assert main(["console", "--hash-password"]) == 2  # an empty password is a configuration error
    assert "an empty password" in capsys.readouterr().err
