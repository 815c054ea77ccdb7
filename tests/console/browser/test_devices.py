"""Device pages driving the simulated devices: the camera takes and shows a frame, the telescope moves."""

from __future__ import annotations

from playwright.async_api import Page, expect

from nightcrew.interfaces import MotionStatus
from nightcrew.modules.sim import SimCamera, SimTelescope

from .observatory import PLEIADES, Observatory, login


async def test_camera_page_takes_an_exposure_and_shows_it(page: Page, observatory: Observatory) -> None:
    await login(page, observatory.url)
    await page.click("#module-list li[data-module='camera'] a")
    await expect(page.locator("#image-info")).to_have_text("no frame yet")
    await page.fill("#cam-exptime", "2.5")
    await page.select_option("#cam-imagetype", "dark")
    await page.click("#cam-expose")
    image = page.locator("#last-image")
    await expect(image).to_have_attribute("data-image-id", "1")
    # The PNG decoded in the browser at the frame's shape (256 x 256 fits max_size unbinned).
    assert await image.evaluate("(img) => [img.naturalWidth, img.naturalHeight]") == [256, 256]
    await expect(page.locator("#image-info")).to_contain_text("256 \u00d7 256 px")
    await page.click(".header-box summary")
    header = page.locator("#image-header")
    await expect(header.locator("tr:has(th:text-is('EXPTIME')) td").first).to_have_text("2.5")
    await expect(header.locator("tr:has(th:text-is('IMAGETYP')) td").first).to_have_text("dark")
    camera = observatory.modules["camera"]
    assert await camera.get_exposure_time() == 2.5  # type: ignore[attr-defined]

    # Another stretch renders the same frame again.
    src = await image.get_attribute("src")
    await page.select_option("#image-stretch", "asinh")
    await expect(image).not_to_have_attribute("src", src or "")
    assert "stretch=asinh" in (await image.get_attribute("src") or "")


async def test_telescope_page_moves_the_telescope(page: Page, observatory: Observatory) -> None:
    telescope = observatory.modules["telescope"]
    assert isinstance(telescope, SimTelescope)
    await login(page, observatory.url)
    await page.click("#module-list li[data-module='telescope'] a")
    await expect(page.locator("#motion-status")).to_have_text("idle")
    await page.fill("#tel-move-ra", str(PLEIADES[0]))
    await page.fill("#tel-move-dec", str(PLEIADES[1]))
    await page.click("#tel-move-radec")
    await expect(page.locator("#motion-status")).to_have_text("tracking")
    await expect(page.locator("#tel-ra")).to_have_text("03h47m00.00s")
    # +24 degrees 07 minutes 12.0 seconds, written with the degree, prime and double prime signs
    await expect(page.locator("#tel-dec")).to_have_text("+24\u00b007\u203212.0\u2033")
    assert await telescope.get_motion_status() is MotionStatus.TRACKING
    ra, dec = await telescope.get_radec()
    assert (ra, dec) == PLEIADES
    # The all-sky plot marks where it points, at its altitude above the horizon.
    alt, _ = await telescope.get_altaz()
    marker = page.locator("#sky-telescope")
    await expect(marker).to_have_attribute("visibility", "visible")
    assert abs(float(await marker.get_attribute("data-alt") or "nan") - alt) < 1.0

    # A move the mount refuses shows its error; then park.
    await page.fill("#tel-move-alt", "5")
    await page.fill("#tel-move-az", "180")
    await page.click("#tel-move-altaz")
    await expect(page.locator(".card[data-widget='telescope'] .message")).to_contain_text(
        "MoveError from telescope"
    )
    await page.click("#motion-park")
    await expect(page.locator("#motion-status")).to_have_text("parked")


async def test_zooming_into_a_large_frame_shows_its_full_resolution(
    page: Page, observatory: Observatory
) -> None:
    big = await observatory.start(
        SimCamera,
        "bigcam",
        detector={"chip_width": 2048, "chip_height": 2048, "cosmic_rays_per_s": 0.0},
        catalog_depth=10.0,
        seed=4,
        readout_time=0.5,
    )
    await big.set_exposure_time(1.0)
    await login(page, observatory.url)
    await page.click("#module-list li[data-module='bigcam'] a")
    await page.click("#cam-expose")
    overview = page.locator("#last-image")
    await expect(overview).to_have_attribute("data-image-id", "1", timeout=60_000)
    assert await overview.evaluate("(img) => img.naturalWidth") == 1024  # the whole frame, binned 2x2
    detail = page.locator("#image-detail")
    await expect(detail).to_be_hidden()
    await page.locator(".image-stage").scroll_into_view_if_needed()
    box = await page.locator(".image-stage").bounding_box()
    assert box is not None
    await page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    for _ in range(15):  # zoom in around the middle, past the overview's own resolution
        await page.mouse.wheel(0, -300)
    await expect(detail).to_be_visible()
    region = [int(v) for v in (await detail.get_attribute("data-region") or "").split(",")]
    assert 0 < region[2] < 2048 and 0 < region[3] < 2048  # a part of the frame ...
    natural = await detail.evaluate("(img) => [img.naturalWidth, img.naturalHeight]")
    assert natural == [region[2], region[3]]  # ... at one PNG pixel per frame pixel
