"""``nightcrew sim --archive``: a night's raw frames, the masters built from them and the reduced
frames end in the image archive, linked, and the archive's web frontend (real Chromium) finds them.

One short night (``--quick``: biases and darks, a focus series, two fields in V and R) runs once
for the module; the archive it leaves in ``OUT/archive`` is opened again, as a user would with
``nightcrew archive --config OUT/archive/archive.yaml``.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

import aiohttp
import pytest
from astropy.io import fits  # type: ignore[import-untyped]
from playwright.async_api import Page, expect

from nightcrew.cli.main import main
from nightcrew.config import load_config
from nightcrew.testing.archive import running_archive
from nightcrew.testing.browser import browser, page  # noqa: F401 - the shared browser fixtures

expect.set_options(timeout=20_000)


@pytest.fixture(scope="module")
def night(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("night")
    arguments = ["--targets", "2", "--filters", "V,R", "--calibration-frames", "2"]
    assert main(["sim", "--quick", "--archive", "--out", str(out), *arguments]) == 0
    return out


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


async def _get(session: aiohttp.ClientSession, url: str) -> Any:
    async with session.get(url) as response:
        assert response.status == 200, await response.text()
        return await response.json()


async def test_every_frame_is_archived_and_every_science_frame_linked_to_its_calibrated_frame(
    night: Path,
) -> None:
    raw = sorted((night / "frames").glob("*.fits"))
    masters = sorted((night / "masters").glob("*.fits"))
    reduced = sorted((night / "reduced").glob("*.fits"))
    # Built during the night from its 2 biases and 2 darks, before the first object frame.
    assert [p.name for p in masters] == ["master_bias_1x1.fits", "master_dark_1x1_30s.fits"]
    science = [p for p in raw if fits.getheader(p)["IMAGETYP"] == "object"]
    assert len(science) == 4  # two fields in V and R
    assert {p.name for p in reduced} == {p.stem + "_red.fits" for p in science}
    config = load_config(night / "archive" / "archive.yaml")
    assert Path(config["database"].removeprefix("sqlite:///")) == (night / "archive" / "archive.db").resolve()

    async with running_archive(night / "archive") as archive, aiohttp.ClientSession() as session:
        page = await _get(session, f"{archive.url}/frames/?limit=1000")
        assert page["count"] == len(raw) + len(masters) + len(reduced)
        frames = {frame["basename"]: frame for frame in page["results"]}
        for path in [*raw, *masters, *reduced]:
            assert frames[path.name]["sha256"] == _sha256(path), path.name
        assert {frames[p.name]["RLEVEL"] for p in raw} == {0}
        assert {frames[p.name]["RLEVEL"] for p in reduced} == {91}
        for path in science:
            related = await _get(session, frames[path.name]["related_url"])
            assert [(f["relation"], f["basename"]) for f in related] == [("reduced", path.stem + "_red.fits")]
            back = await _get(session, frames[path.stem + "_red.fits"]["related_url"])
            assert sorted((f["relation"], f["basename"]) for f in back) == [
                ("bias", "master_bias_1x1.fits"),
                ("dark", "master_dark_1x1_30s.fits"),
                ("raw", path.name),
            ]


#: Every thumbnail in the table loaded and decoded as an image.
_THUMBNAILS_LOADED = (
    "[...document.querySelectorAll('#rows img')].every(i => i.complete && i.naturalWidth > 0)"
)


async def test_the_frontend_finds_the_night_s_reduced_frames_with_thumbnails(
    night: Path,
    page: Page,  # noqa: F811 - the fixture
) -> None:
    reduced = sorted((night / "reduced").glob("*.fits"))
    in_v = [p for p in reduced if fits.getheader(p)["FILTER"] == "V"]
    assert in_v
    async with running_archive(night / "archive") as archive:
        await page.goto(archive.url)
        total = sum(len(list((night / d).glob("*.fits"))) for d in ("frames", "masters", "reduced"))
        await expect(page.locator("#count")).to_have_text(f"{total} frames")
        # The first page's thumbnails are made on first request; a browser sends at most six
        # requests to a host at once, so a search sent meanwhile queues behind them.
        await page.wait_for_function(_THUMBNAILS_LOADED, timeout=120_000)
        await page.get_by_label("Level").select_option("91")
        await page.get_by_label("Filter", exact=True).fill("V")
        await page.get_by_role("button", name="Search").click()
        await expect(page.locator("#count")).to_have_text(f"{len(in_v)} frames")
        rows = page.locator("#rows tr")
        await expect(rows).to_have_count(len(in_v))
        for path in in_v:
            await expect(rows.filter(has_text=path.name)).to_have_count(1)
        await page.wait_for_function(_THUMBNAILS_LOADED)
        await expect(page.locator("#rows img")).to_have_count(len(in_v))


def test_archive_with_a_season_is_refused_before_the_night(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["sim", "--quick", "--archive", "--nights", "2", "--out", str(tmp_path)])
    assert code == 2
    assert "--archive archives one night; leave out --nights" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())
