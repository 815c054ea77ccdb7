"""Benchmark of the Alpaca client against alpaca-simulators, with baselines timed in the same run.

Run: ``.venv/bin/python bench/alpaca.py [runs]``. Starts alpaca-simulators on 127.0.0.1 with a
4096 x 4096 camera, takes one frame, then times:

* downloading that 16-bit frame through AlpacaCamera (ImageBytes, decoded to the uint16 array the
  camera writes) against alpyca's own ``Camera.ImageArray`` of the same frame
  (goal: >= 2 x alpyca's throughput);
* the floor: the same bytes fetched by a bare aiohttp GET, not decoded (the server's own time to
  serialise and send 32 MB bounds every client);
* one property read through the module (``GET camerastate``, ids, JSON, error check) against a
  bare aiohttp GET of the same URL on a reused session (goal: <= 1.2 x its latency).

Prints one table: median and best time per case, throughput, and the ratio to the baseline.
"""

from __future__ import annotations

import asyncio
import statistics
import sys
import tempfile
import time
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

# Run as a script, this file's directory comes first on sys.path and this file, alpaca.py, would
# shadow alpyca's package of the same name.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

import aiohttp  # noqa: E402
import numpy as np  # noqa: E402

from nightcrew.clock import RealClock  # noqa: E402
from nightcrew.modules.alpaca import AlpacaCamera  # noqa: E402
from nightcrew.modules.alpaca.camera import _as_uint16  # noqa: E402
from nightcrew.testing import Observatory  # noqa: E402
from nightcrew.testing.alpaca import SIMULATOR_SITE, TEST_OVERRIDES, merge_config, start_simulator  # noqa: E402

SIZE = 4096
_BIG_CAMERA = {
    "devices": {"camera": {0: {"cameraxsize": SIZE, "cameraysize": SIZE, "numx": SIZE, "numy": SIZE}}}
}


async def timed(run: Callable[[], Awaitable[Any]], repeats: int) -> list[float]:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        await run()
        times.append(time.perf_counter() - start)
    return times


def row(name: str, times: list[float], baseline: list[float] | None, unit: str, nbytes: int = 0) -> str:
    median, best = statistics.median(times), min(times)
    scale = 1e3 if unit == "ms" else 1e6
    rate = f"{nbytes / median / 1e6:8.1f}" if nbytes else " " * 8
    ratio = f"{statistics.median(baseline) / median:6.2f} x faster" if baseline and nbytes else ""
    if baseline and not nbytes:
        ratio = f"{median / statistics.median(baseline):6.2f} x its time"
    return f"{name:<44} {median * scale:10.2f} {best * scale:10.2f} {unit:>3} {rate} {ratio}"


async def main(runs: int) -> None:
    from alpaca.camera import Camera  # type: ignore[import-untyped]

    with tempfile.TemporaryDirectory() as tmp:
        simulator = start_simulator(Path(tmp), overrides=merge_config(TEST_OVERRIDES, _BIG_CAMERA))
        try:
            async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
                camera = await obs.start(AlpacaCamera, "camera", server=simulator.url, readout_timeout=300.0)
                await camera.set_exposure_time(0.1)
                await camera.grab_data(broadcast=False)  # the frame both clients then download
                shape = (SIZE, SIZE)

                async def module_download() -> None:
                    _as_uint16(await camera.device.image_array(time_limit=120.0), shape, "bench")

                alpyca = Camera(f"127.0.0.1:{simulator.port}", 0)

                async def alpyca_download() -> None:
                    image = alpyca.ImageArray
                    assert len(image) == SIZE and len(image[0]) == SIZE

                image_url = f"{simulator.url}/api/v1/camera/0/imagearray"

                async def bare_download() -> None:
                    async with (
                        aiohttp.ClientSession() as session,
                        session.get(image_url, headers={"Accept": "application/imagebytes"}) as reply,
                    ):
                        assert len(await reply.read()) == 44 + SIZE * SIZE * 2

                check = await camera.device.image_array()
                assert check.shape == shape and check.dtype == np.uint16
                module_times, alpyca_times, floor_times = [], [], []
                for _ in range(runs):  # interleaved: all three see the same machine load
                    module_times += await timed(module_download, 1)
                    alpyca_times += await timed(alpyca_download, 1)
                    floor_times += await timed(bare_download, 1)

                url = f"{simulator.url}/api/v1/camera/0/camerastate"
                async with aiohttp.ClientSession() as session:

                    async def bare_get() -> None:
                        async with session.get(url, params={"ClientTransactionID": "1"}) as reply:
                            await reply.json()

                    async def module_get() -> None:
                        await camera._get("camerastate")

                    reads = 50 * runs
                    bare, through = [], []
                    for _ in range(reads):  # interleaved: both see the same machine load
                        bare += await timed(bare_get, 1)
                        through += await timed(module_get, 1)
        finally:
            simulator.stop()

    nbytes = SIZE * SIZE * 2
    print(f"Alpaca client vs baselines (alpaca-simulators on 127.0.0.1, {runs} runs)")
    print(f"{'case':<44} {'median':>10} {'best':>10}     {'MB/s':>8} ratio")
    print(row("alpyca Camera.ImageArray 4096x4096 u16", alpyca_times, None, "ms", nbytes))
    print(row("AlpacaCamera ImageBytes 4096x4096 u16", module_times, alpyca_times, "ms", nbytes))
    print("  goal: >= 2 x alpyca's throughput")
    print(row("floor: bare aiohttp GET of the bytes only", floor_times, None, "ms", nbytes))
    over_floor = statistics.median(module_times) / statistics.median(floor_times)
    print(f"  the module's download takes {over_floor:.2f} x the floor")
    print(row("bare aiohttp GET camerastate", bare, None, "us"))
    print(row("AlpacaCamera GET camerastate", through, bare, "us"))
    print("  goal: <= 1.2 x the bare GET's latency")


if __name__ == "__main__":
    asyncio.run(main(int(sys.argv[1]) if len(sys.argv) > 1 else 6))
