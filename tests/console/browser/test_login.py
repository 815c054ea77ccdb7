"""Logging in and out of the console in a real browser, and what a viewer may not do."""

from __future__ import annotations

from playwright.async_api import Page, expect

from .observatory import OPERATOR, VIEWER, Observatory, login


async def test_wrong_password_is_refused_without_saying_which_part(
    page: Page, observatory: Observatory
) -> None:
    await page.goto(observatory.url)
    await page.fill("#login-user", OPERATOR[0])
    await page.fill("#login-password", "not-the-password")
    await page.click("#login-submit")
    await expect(page.locator("#login-error")).to_have_text("wrong user name or password")
    await page.fill("#login-user", "nobody")
    await page.fill("#login-password", OPERATOR[1])
    await page.click("#login-submit")
    await expect(page.locator("#login-error")).to_have_text("wrong user name or password")
    await expect(page.locator("#whoami")).to_have_count(0)


async def test_repeated_wrong_passwords_are_slowed_down(page: Page, observatory: Observatory) -> None:
    await page.goto(observatory.url)
    error = page.locator("#login-error")
    for attempt in range(5):  # the console's default: 5 failures per user name within 5 minutes
        await page.fill("#login-user", OPERATOR[0])
        await page.fill("#login-password", f"guess-{attempt}")
        await page.click("#login-submit")
        await expect(error).to_have_text("wrong user name or password")
        await page.evaluate("document.getElementById('login-error').textContent = ''")
    await page.fill("#login-user", OPERATOR[0])
    await page.fill("#login-password", OPERATOR[1])  # even the right one waits now
    await page.click("#login-submit")
    await expect(error).to_contain_text("too many failed logins; try again in")
    await expect(page.locator("#whoami")).to_have_count(0)


async def test_operator_logs_in_sees_the_modules_and_logs_out(page: Page, observatory: Observatory) -> None:
    await login(page, observatory.url, OPERATOR)
    await expect(page.locator("#whoami")).to_have_text(f"{OPERATOR[0]} (operator)")
    await expect(page.locator("#module-list li")).to_have_count(5)
    await expect(page.locator("#live-dot")).to_be_visible()
    await page.click("#logout")
    await expect(page.locator("#login-submit")).to_be_visible()
    # The session is gone on the server too: a reload asks for the password again.
    await page.reload()
    await expect(page.locator("#login-submit")).to_be_visible()


async def test_viewer_sees_everything_and_calls_nothing(page: Page, observatory: Observatory) -> None:
    await login(page, observatory.url, VIEWER)
    await expect(page.locator("#whoami")).to_have_text(f"{VIEWER[0]} (viewer)")
    await page.click("#module-list a:has-text('telescope')")
    await expect(page.locator("#tel-ra")).not_to_have_text("—")  # reading is allowed
    await expect(page.locator("#tel-move-radec")).to_be_disabled()
    await expect(page.locator("#motion-park")).to_be_disabled()
    await expect(page.locator("form.method[data-method='park'] button")).to_be_disabled()

    # The shell lets the viewer try, and the server refuses: the refusal is shown, nothing moves.
    await page.click("#nav-shell")
    await page.fill("#shell-input", "telescope.park()")
    await page.press("#shell-input", "Enter")
    error = page.locator("#shell-output li").last.locator(".result.error")
    await expect(error).to_contain_text("ForbiddenError")
    await page.fill("#shell-input", "filters.get_filter()")
    await page.press("#shell-input", "Enter")
    await expect(page.locator("#shell-output li").last.locator(".result.ok")).to_have_text("V")
    assert await observatory.modules["telescope"].get_motion_status() != "parked"  # type: ignore[attr-defined]

    await page.click("#nav-events")
    await expect(page.locator("#send-event")).to_be_disabled()
