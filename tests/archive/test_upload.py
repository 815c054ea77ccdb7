"""Uploads: accepted frames land on disk by date and instrument and in the index; every bad upload
gets one clear error and leaves nothing behind."""

from __future__ import annotations

import hashlib
from pathlib import Path

from nightcrew.testing.archive import RunningArchive, fits_frame, running_archive

from .conftest import Client


def stored_files(archive: RunningArchive) -> list[str]:
    return sorted(
        str(p.relative_to(archive.storage))
        for p in archive.storage.rglob("*")
        if p.is_file() and ".thumbnails" not in p.parts
    )


async def test_an_upload_is_stored_by_day_and_instrument_and_indexed(
    client: Client, archive: RunningArchive
) -> None:
    data = fits_frame(date_obs="2026-11-24T21:30:00.5", instrument="sbig 6303", OBJECT="M 13", FILTER="V")
    status, body = await client.upload(data, "m13-0001.fits")
    assert status == 201, body
    assert body["duplicate"] is False
    assert body["sha256"] == hashlib.sha256(data).hexdigest() and body["size"] == len(data)
    assert (body["path"], body["DATE_OBS"], body["OBJECT"], body["FILTER"], body["RLEVEL"]) == (
        "20261124/sbig_6303/m13-0001.fits",
        "2026-11-24T21:30:00.500",
        "M 13",
        "V",
        0,
    )
    assert stored_files(archive) == ["20261124/sbig_6303/m13-0001.fits"]
    assert (archive.storage / body["path"]).read_bytes() == data
    status, found = await client.get(f"/frames/{body['id']}/")
    assert status == 200 and found["basename"] == "m13-0001.fits"


async def test_the_same_file_twice_is_a_409_naming_the_stored_frame(
    client: Client, archive: RunningArchive
) -> None:
    data = fits_frame(seed=1)
    _, first = await client.upload(data, "a.fits")
    status, body = await client.upload(data, "b.fits")
    assert status == 409
    assert body["duplicate"] is True and body["frame"]["id"] == first["id"]
    assert f"duplicate of frame {first['id']} (a.fits, same sha256)" in body["detail"]
    status, body = await client.upload(fits_frame(seed=2), "a.fits")
    assert status == 409 and body["duplicate"] is False
    assert "a different frame is stored as a.fits" in body["detail"]
    assert stored_files(archive) == ["20261124/sbig6303/a.fits"]


async def test_uploads_need_the_token(client: Client, archive: RunningArchive) -> None:
    for token, why in ((None, "no bearer token"), ("not-the-token-at-all", "a wrong bearer token")):
        status, body = await client.upload(fits_frame(), "a.fits", token=token)
        assert status == 401 and body["error"] == "Unauthorized"
        assert why in body["detail"]
    assert stored_files(archive) == []


async def test_bad_files_are_refused_with_one_clear_error_each(
    client: Client, archive: RunningArchive
) -> None:
    good = fits_frame()
    without_filter = fits_frame().replace(b"IMAGETYP= 'object  '", b"COMMENT   'object  '")
    cases = [
        (b"PNG not a fits file" * 200, "a.fits", 415, "not a FITS file"),
        (good[:-2880], "a.fits", 400, "truncated FITS file: File may have been truncated"),
        (good[:-100], "a.fits", 400, "truncated FITS file: 5660 bytes is not a whole number"),
        (without_filter, "a.fits", 422, "missing FITS keywords IMAGETYP"),
        (fits_frame(exptime=-1.0), "a.fits", 422, "EXPTIME must be a number of seconds >= 0, got -1.0"),
        (fits_frame(date_obs="yesterday"), "a.fits", 422, "DATE-OBS must be an ISO date"),
        (good, "../etc/a.fits", 400, "must be a plain file name"),
        (good, "a.txt", 400, "ending in one of .fits"),
        (b"", "a.fits", 400, "empty upload"),
    ]
    for data, name, status, message in cases:
        got, body = await client.upload(data, name)
        assert (got, message in body.get("detail", "")) == (status, True), (name, message, body)
    assert stored_files(archive) == []
    assert (await client.get("/frames/"))[1]["count"] == 0


async def test_an_upload_over_the_size_cap_is_a_413(tmp_path: Path, database: str | None) -> None:
    async with running_archive(tmp_path, database=database, max_upload_bytes=8 * 2880) as archive:
        client = Client(archive)
        try:
            status, body = await client.upload(fits_frame(shape=(200, 200)), "big.fits")
            assert status == 413 and "exceeds the limit of 23040 bytes" in body["detail"]
            assert (await client.upload(fits_frame(), "small.fits"))[0] == 201
        finally:
            await client.close()
        assert stored_files(archive) == ["20261124/sbig6303/small.fits"]


async def test_a_start_removes_what_uploads_cut_off_by_a_crash_left(
    tmp_path: Path, database: str | None
) -> None:
    left = tmp_path / "frames/20261124/sbig6303/.upload-0123456789abcdef"
    left.parent.mkdir(parents=True)
    left.write_bytes(fits_frame()[:2880])
    async with running_archive(tmp_path, database=database) as archive:
        assert not left.exists()
        assert stored_files(archive) == []


async def test_a_night_keeps_one_day_obs_across_midnight(client: Client) -> None:
    """Without DAY-OBS: the date of the local noon before DATE-OBS (SITELONG, east positive)."""
    cases = [
        ({"date_obs": "2026-11-25T04:00:00", "SITELONG": 9.9}, "20261124"),  # after midnight in Europe
        ({"date_obs": "2026-11-25T03:00:00", "SITELONG": -70.7}, "20261124"),  # evening in Chile
        ({"date_obs": "2026-11-25T13:00:00", "SITELONG": -155.5}, "20261124"),  # Hawaii, 3 am
        ({"date_obs": "2026-11-25T11:00:00"}, "20261124"),  # no longitude: Greenwich
        ({"date_obs": "2026-11-25T04:00:00", "DAY_OBS": "2026-11-20"}, "20261120"),  # as given
    ]
    for seed, (cards, day) in enumerate(cases):
        status, body = await client.upload(fits_frame(seed=seed, **cards), f"f{seed}.fits")  # type: ignore[arg-type]
        assert (status, body["DAY_OBS"]) == (201, day), cards
