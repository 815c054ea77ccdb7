"""ConformU's Alpaca protocol checks against nightcrew's AlpacaServer and against alpaca-simulators.

Each served device type gets the same checks on both servers (:mod:`tests.alpaca.conformance`):
nightcrew must pass every one (so everywhere the reference passes, and also where it does not).
One server of each for the module; the reference's results are printed (``-s``) for comparison.
"""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import AsyncIterator
from pathlib import Path

import aiohttp
import pytest
import pytest_asyncio

from nightcrew.testing.alpaca import AlpacaSimulator, start_simulator

from .conformance import Outcome
from .conformance_run import run_device_checks
from .served import DEVICES, MORE_DEVICES, served_observatory

pytestmark = pytest.mark.asyncio(loop_scope="module")

#: The device types nightcrew's server serves here: all ten (nightcrew sim --alpaca serves seven).
SERVED = {**DEVICES, **MORE_DEVICES, "observingconditions": "weather"}


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def servers(
    tmp_path_factory: pytest.TempPathFactory, alpaca_star_table: Path
) -> AsyncIterator[tuple[str, str]]:
    """The URLs of nightcrew's server and of a private alpaca-simulators (the first-use checks need
    devices nobody has used yet), started side by side."""
    directory = tmp_path_factory.mktemp("conformance-reference")
    starting = asyncio.ensure_future(
        asyncio.to_thread(start_simulator, directory, star_table=alpaca_star_table)
    )
    simulator: AlpacaSimulator | None = None
    try:
        async with served_observatory(devices=SERVED, more_devices=True) as served:
            simulator = await starting
            yield served.url, simulator.url
    finally:
        if simulator is None:
            with contextlib.suppress(Exception):
                simulator = await starting
        if simulator is not None:
            await asyncio.to_thread(simulator.stop, grace=1.0)


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def session() -> AsyncIterator[aiohttp.ClientSession]:
    async with aiohttp.ClientSession() as session:
        yield session


def _summary(server: str, outcomes: list[Outcome]) -> str:
    failed = [o for o in outcomes if o.problem]
    lines = [f"{server}: {len(outcomes)} checks, {len(outcomes) - len(failed)} conformant, {len(failed)} not"]
    lines += [f"  {o.check.name}: {o.problem}  [{o.detail.get('body', '')[:120]}]" for o in failed]
    return "\n".join(lines)


@pytest.mark.parametrize("device_type", sorted(SERVED))
async def test_nightcrew_passes_every_check(
    device_type: str, servers: tuple[str, str], session: aiohttp.ClientSession
) -> None:
    nightcrew_url, reference_url = servers
    reference = await run_device_checks(session, reference_url, device_type, 0)
    ours = await run_device_checks(session, nightcrew_url, device_type, 0)
    print(f"\n{device_type}\n{_summary('alpaca-simulators', reference)}\n{_summary('nightcrew', ours)}")
    assert [o for o in ours if o.problem] == [], _summary("nightcrew", ours)
