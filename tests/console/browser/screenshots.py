"""Screenshots of the console's main pages for docs/console.md, taken during a simulated night.

    .venv/bin/python -m tests.console.browser.screenshots [--out docs/img]

Starts ``nightcrew sim --console`` (as the test does), waits until the mastermind runs a science
task, then visits the pages in headless Chromium and saves docs/img/console-*.png. The Tasks page
is taken on the tests' small observatory with the sample tasks, a scheduler and a console with
the task archive (``nightcrew sim --console`` has no task archive of its own).
"""

from __future__ import annotations

import argparse
import asyncio
import re
from pathlib import Path

from playwright.async_api import Page, expect

from nightcrew.clock import AcceleratedClock
from nightcrew.modules.robotic import SchedulerModule
from nightcrew.robotic import samples
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.tasks import load_request_group_file
from nightcrew.testing.browser import launch_chromium

from .observatory import Observatory, login
from .test_sim_console import PASSWORD, sim_night

WIDTH, HEIGHT = 1400, 900
expect.set_options(timeout=120_000)  # the night has to get there first


async def shoot(page: Page, out: Path, name: str) -> None:
    await page.mouse.move(WIDTH - 2, 2)  # no hover highlight in the picture
    await page.evaluate("document.getElementById('page')?.scrollTo(0, 0)")
    await page.wait_for_timeout(1500)  # let plots and the poll settle: a picture, not a test
    await page.screenshot(path=out / f"console-{name}.png")
    print(f"wrote {out / f'console-{name}.png'}")


async def main(out: Path, tmp: Path) -> None:
    async with sim_night(tmp, start="17:30", hours=8, speed=30) as url, launch_chromium() as browser:
        page = await browser.new_page(viewport={"width": WIDTH, "height": HEIGHT})
        errors: list[str] = []
        page.on("pageerror", lambda error: errors.append(str(error)))
        await page.goto(url)
        await page.fill("#login-user", "operator")
        await shoot(page, out, "login")
        await login(page, url, ("operator", PASSWORD))

        await page.click("#module-list li[data-module='mastermind'] a")
        await expect(page.locator("#mm-action")).to_have_text("run_task", timeout=240_000)
        await shoot(page, out, "mastermind")

        await page.click("#module-list li[data-module='scheduler'] a")
        await expect(page.locator("#plan-summary")).to_contain_text("objective")
        await shoot(page, out, "scheduler")

        await page.click("#module-list li[data-module='camera'] a")
        await expect(page.locator("#last-image")).to_have_attribute("data-image-id", re.compile(r"\d+"))
        await page.select_option("#image-stretch", "asinh")
        await shoot(page, out, "camera")
        stage = page.locator(".image-stage")
        await stage.scroll_into_view_if_needed()
        box = await stage.bounding_box()
        assert box is not None
        await page.mouse.move(box["x"] + box["width"] * 0.4, box["y"] + box["height"] * 0.45)
        for _ in range(14):
            await page.mouse.wheel(0, -300)
        await page.wait_for_timeout(1500)  # a frame larger than 1024 px gets its full-resolution detail
        await stage.screenshot(path=out / "console-camera-zoom.png")

        await page.click("#module-list li[data-module='telescope'] a")
        await expect(page.locator("#tel-ra")).not_to_have_text("—")
        await shoot(page, out, "telescope")

        await page.click("#module-list li[data-module='weather'] a")
        await shoot(page, out, "weather")

        await page.click("#module-list li[data-module='focus'] a")
        await shoot(page, out, "focus")

        await page.click("#nav-shell")
        for line in ["telescope.get_altaz()", "filters.set_filter('H-alpha')"]:
            await page.fill("#shell-input", line)
            await page.press("#shell-input", "Enter")
        await page.fill("#shell-input", "camera.set_")
        await page.press("#shell-input", "Tab")
        await expect(page.locator("#shell-output li .result.error")).to_be_visible()
        await shoot(page, out, "shell")

        await page.click("#nav-events")
        await expect(page.locator("#events-list li").first).to_be_visible()
        await shoot(page, out, "events")

        await page.click("#nav-status")
        await shoot(page, out, "status")

        # Every other module page once, for script errors (the tests' observatory lacks some).
        names = await page.locator("#module-list li").evaluate_all("(li) => li.map((l) => l.dataset.module)")
        for name in names:
            await page.goto(f"{url}#/modules/{name}")
            await expect(page.locator(".module-head h2")).to_contain_text(name)
            await page.wait_for_timeout(1200)
        await page.goto(f"{url}#/modules/guiding")
        await shoot(page, out, "guiding")

        await page.set_viewport_size({"width": 390, "height": 844})  # a phone
        await page.goto(url + "#/modules/camera")
        await expect(page.locator("#last-image")).to_have_attribute("data-image-id", re.compile(r"\d+"))
        await shoot(page, out, "phone")
        assert not errors, f"script errors in the console: {errors}"


async def tasks_page(out: Path, tmp: Path) -> None:
    """The Tasks page with the sample tasks at 18:00 UTC on their night, one "why not" unfolded."""
    database = tmp / "tasks.sqlite"
    obs = Observatory()
    obs.clock = AcceleratedClock("2026-11-10T18:00:00+00:00", speed=30)
    async with SqliteTaskArchive(database, clock=obs.clock, poll_interval=0) as archive:
        for path in sorted(Path(samples.__file__).parent.glob("*.yaml")):
            await archive.add_request_group(load_request_group_file(path))
        try:
            await obs.start(SchedulerModule, "scheduler", archive=archive, store=archive, time_limit_s=5.0)
            description = {"class": "nightcrew.robotic.archives.SqliteTaskArchive", "path": str(database)}
            await obs.start_console(tasks=description)
            async with launch_chromium() as browser:
                page = await browser.new_page(viewport={"width": WIDTH, "height": HEIGHT})
                await login(page, obs.url)
                await page.click("#nav-tasks")
                await expect(page.locator("#tasks-table td.tonight time").first).to_be_visible()
                await page.locator("#tasks-table details.why summary").first.click()
                await shoot(page, out, "tasks")
        finally:
            await obs.close()


if __name__ == "__main__":
    import tempfile

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("docs/img"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        asyncio.run(main(args.out, Path(tmp)))
        asyncio.run(tasks_page(args.out, Path(tmp)))
