"""The module list follows modules that start and stop; the show_* options shape the console."""

from __future__ import annotations

from pathlib import Path

from playwright.async_api import Page, expect

from nightcrew.interfaces import IWindow
from nightcrew.modules.sim import SimFocuser

from .observatory import Observatory, login


async def test_module_list_follows_modules_that_start_and_stop(page: Page, observatory: Observatory) -> None:
    await login(page, observatory.url)
    entries = page.locator("#module-list li")
    await expect(entries).to_have_count(5)
    await observatory.start(SimFocuser, "focuser2", focus=20.0, best_focus=21.0)
    await expect(page.locator("#module-list li[data-module='focuser2']")).to_be_visible()
    await expect(entries).to_have_count(6)

    # A module vanishing while its page is open: the page says so, the console goes on.
    await page.click("#module-list li[data-module='focuser2'] a")
    await expect(page.locator("#focus-value")).to_have_text("20")
    await observatory.stop("focuser2")
    await expect(page.locator("#module-list li[data-module='focuser2']")).to_have_count(0)
    await expect(page.locator("#module-gone")).to_contain_text("focuser2 is not online")

    # ... and comes back when the module returns.
    await observatory.start(SimFocuser, "focuser2", focus=22.0, best_focus=21.0)
    await expect(page.locator("#focus-value")).to_have_text("22")


async def test_pages_show_only_what_the_interfaces_offer(page: Page, observatory: Observatory) -> None:
    await login(page, observatory.url)
    await page.click("#module-list li[data-module='filters'] a")
    await expect(page.locator(".card[data-widget='filter wheel']")).to_be_visible()
    await expect(page.locator(".card[data-widget='camera']")).to_have_count(0)
    await expect(page.locator(".card[data-widget='telescope']")).to_have_count(0)
    await page.select_option("#filter-select", "R")
    await page.click("#filter-set")
    await expect(page.locator("#filter-current")).to_have_text("R")

    await page.click("#module-list li[data-module='camera'] a")
    methods = page.locator("form.method")
    await expect(methods.first).to_be_attached()
    offered = set(await methods.evaluate_all("(forms) => forms.map((f) => f.dataset.method)"))
    has_window = isinstance(observatory.modules["camera"], IWindow)
    assert ("set_window" in offered) == has_window
    assert (await page.locator("#cam-window-left").count() == 1) == has_window
    assert "grab_data" in offered and "move_radec" not in offered


async def test_show_options_hide_pages_and_modules(page: Page) -> None:
    obs = Observatory()
    try:
        await obs.start_devices()
        await obs.start_console(show_shell=False, show_events=False, show_modules=["camera", "roof"])
        await login(page, obs.url)
        await expect(page.locator("#module-list li")).to_have_count(2)
        await expect(page.locator("#nav-status")).to_be_visible()
        await expect(page.locator("#nav-shell")).to_have_count(0)
        await expect(page.locator("#nav-events")).to_have_count(0)
        await page.goto(obs.url + "#/modules/telescope")
        await expect(page.locator("section.welcome")).to_be_visible()
        await page.goto(obs.url + "#/shell")
        await expect(page.locator("#shell-input")).to_have_count(0)
    finally:
        await obs.close()


async def test_no_module_pages_and_no_status(page: Page) -> None:
    obs = Observatory()
    try:
        await obs.start_devices()
        await obs.start_console(show_status=False, show_modules=False)
        await login(page, obs.url)
        await expect(page.locator("#nav-shell")).to_be_visible()
        await expect(page.locator("#module-list li")).to_have_count(0)
        await expect(page.locator("#nav-status")).to_have_count(0)
    finally:
        await obs.close()


async def test_custom_widget_shows_on_its_module_page(page: Page, tmp_path: Path) -> None:
    widget = tmp_path / "roof-widget.html"
    # The observatory's own page uses the API with the session cookie, like the console's pages.
    widget.write_text(
        "<!doctype html><p id=hello>Roof camera</p><p id=roof-state></p><script>"
        "fetch('/api/modules/roof').then((r) => r.json())"
        ".then((m) => { document.getElementById('roof-state').textContent = 'roof is ' + m.state; });"
        "</script>"
    )
    obs = Observatory()
    try:
        await obs.start_devices()
        await obs.start_console(widgets={"roof": {"title": "Roof camera", "file": str(widget)}})
        await login(page, obs.url)
        await page.click("#module-list li[data-module='roof'] a")
        card = page.locator(".custom-widget")
        await expect(card.locator("h3")).to_have_text("Roof camera")
        frame = page.frame_locator(".custom-widget iframe")
        await expect(frame.locator("#roof-state")).to_have_text("roof is ready")
        await page.click("#module-list li[data-module='camera'] a")
        await expect(page.locator(".custom-widget")).to_have_count(0)
    finally:
        await obs.close()
