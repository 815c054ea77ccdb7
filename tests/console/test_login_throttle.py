"""The brake on guessing locks out the guesser, not the others behind the same reverse proxy.

Failures count per user name and client address; the client address comes from X-Forwarded-For
only when the connection is from a configured trusted proxy. The console here is reached from
127.0.0.1, which plays the proxy: the test sends the header such a proxy would add.
"""

from __future__ import annotations

from collections.abc import Callable

import pytest

from nightcrew.errors import ConfigError
from nightcrew.modules.console import WebConsole
from nightcrew.modules.console._auth import LoginThrottle

from .conftest import OPERATOR, OPERATOR_PASSWORD, ApiClient, Observatory

GUESSER, COLLEAGUE = "203.0.113.5", "198.51.100.7"


async def _login(client: ApiClient, user: str, password: str, forwarded_for: str) -> int:
    headers = {"X-Forwarded-For": forwarded_for}
    body = {"user": user, "password": password}
    async with client.http.post(client.base + "/api/login", json=body, headers=headers) as response:
        return response.status


def test_the_client_address_is_the_proxies_word_only_from_trusted_proxies() -> None:
    throttle = LoginThrottle(5, 300.0, ["10.0.0.0/8", "::1"])
    # Not from a proxy: the header is whatever the client wrote, never believed.
    assert throttle.client_address("203.0.113.5", ["198.51.100.7"]) == "203.0.113.5"
    # From a proxy: the right-most hop that is not a proxy; a client's own entry is further left.
    assert throttle.client_address("10.0.0.2", ["1.2.3.4, 203.0.113.5"]) == "203.0.113.5"
    assert throttle.client_address("10.0.0.2", ["1.2.3.4, 203.0.113.5, 10.0.0.9"]) == "203.0.113.5"
    assert throttle.client_address("::1", ["2001:db8::7"]) == "2001:db8::7"
    # Nothing usable from the proxy: the failures count on the proxy itself.
    assert throttle.client_address("10.0.0.2", []) == "10.0.0.2"
    assert throttle.client_address("10.0.0.2", ["1.2.3.4, not-an-address"]) == "10.0.0.2"


async def test_guessing_behind_a_trusted_proxy_locks_out_only_the_guesser(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console(login_attempts=3, trusted_proxies=["127.0.0.1"])
    client = clients(console.url)
    for _ in range(20):  # the 20 bad logins, each counted on the guesser
        assert await _login(client, OPERATOR, "guess", GUESSER) in (401, 429)
    assert await _login(client, OPERATOR, OPERATOR_PASSWORD, GUESSER) == 429
    assert await _login(client, OPERATOR, OPERATOR_PASSWORD, COLLEAGUE) == 200


async def test_without_trusted_proxies_the_header_does_not_let_a_guesser_go_on(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console(login_attempts=3)
    client = clients(console.url)
    for number in range(3):  # a new made-up address each time: all the same to the console
        assert await _login(client, OPERATOR, "guess", f"192.0.2.{number}") == 401
    assert await _login(client, OPERATOR, OPERATOR_PASSWORD, "192.0.2.99") == 429


@pytest.mark.parametrize(
    ("value", "key"), [("10.0.0.0/8", "trusted_proxies"), (["proxy.local"], "trusted_proxies[0]")]
)
def test_a_bad_trusted_proxy_is_named(value: object, key: str) -> None:
    with pytest.raises(ConfigError, match="address") as raised:
        WebConsole(name="console", trusted_proxies=value)  # type: ignore[arg-type]
    assert raised.value.key == key
