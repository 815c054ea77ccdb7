"""The archive's web frontend in a real browser (Debian's Chromium through Playwright): filter,
result table with thumbnails, header view with related frames, zip and single downloads."""

from __future__ import annotations

import zipfile
from pathlib import Path

from playwright.async_api import Page, expect

from nightcrew.testing.archive import RunningArchive, fits_frame
from nightcrew.testing.browser import browser, page  # noqa: F401 - the shared browser fixtures

from .conftest import Client

expect.set_options(timeout=20_000)


async def test_filter_preview_header_related_and_download(
    page: Page,  # noqa: F811 - the fixture
    archive: RunningArchive,
    client: Client,
    tmp_path: Path,
) -> None:
    uploads = [
        ("m13.fits", fits_frame(seed=1, OBJECT="M 13", FILTER="V", date_obs="2026-11-24T20:00:00")),
        (
            "m13-red.fits",
            fits_frame(seed=2, OBJECT="M 13", FILTER="V", RAWFILE="m13.fits", date_obs="2026-11-24T20:00:00"),
        ),
        ("m57.fits", fits_frame(seed=3, OBJECT="M 57", FILTER="R", date_obs="2026-11-24T22:00:00")),
    ]
    for name, data in uploads:
        assert (await client.upload(data, name))[0] == 201

    await page.goto(archive.url)
    await expect(page.locator("#count")).to_have_text("3 frames")
    await page.get_by_label("Object").fill("M 13")
    await page.get_by_role("button", name="Search").click()
    await expect(page.locator("#count")).to_have_text("2 frames")
    await expect(page.locator("#rows tr")).to_have_count(2)
    assert "OBJECT=M+13" in page.url  # a link that repeats the search
    await page.wait_for_function(  # every thumbnail loaded and decoded as an image
        "[...document.querySelectorAll('#rows img')].every(i => i.complete && i.naturalWidth > 0)"
    )

    await page.get_by_role("button", name="m13-red.fits").click()
    details = page.locator("#details")
    await expect(details.locator("#details-title")).to_have_text("m13-red.fits")
    await expect(details.locator("#header tr", has_text="RAWFILE")).to_contain_text('"m13.fits"')
    await expect(details.locator("#related li")).to_have_text(["raw: m13.fits"])
    await details.get_by_role("button", name="m13.fits").click()
    await expect(details.locator("#details-title")).to_have_text("m13.fits")
    await expect(details.locator("#related li")).to_have_text(["reduced: m13-red.fits"])

    await page.get_by_label("Select all").check()
    async with page.expect_download() as download_info:
        await page.get_by_role("button", name="Download selected (zip, 2)").click()
    saved = tmp_path / "frames.zip"
    await (await download_info.value).save_as(saved)
    with zipfile.ZipFile(saved) as bundle:
        assert sorted(bundle.namelist()) == ["20261124/m13-red.fits", "20261124/m13.fits"]
        assert bundle.read("20261124/m13.fits") == uploads[0][1]
    async with page.expect_download() as download_info:
        await page.locator("#rows tr", has_text="m13-red.fits").get_by_role("link", name="FITS").click()
    assert (await download_info.value).suggested_filename == "m13-red.fits"


async def test_a_bad_filter_shows_the_archive_s_message(
    page: Page,  # noqa: F811 - the fixture
    archive: RunningArchive,
) -> None:
    await page.goto(archive.url)
    await expect(page.locator("#count")).to_have_text("0 frames")
    await page.get_by_label("RA", exact=True).fill("10")
    await page.get_by_label("Dec", exact=True).fill("95")
    await page.get_by_label("Radius", exact=True).fill("1")
    await page.get_by_role("button", name="Search").click()
    await expect(page.get_by_role("alert")).to_have_text("dec must be within -90..90, got '95'")
