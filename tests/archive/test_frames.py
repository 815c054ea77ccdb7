"""Frame details: the whole header, related frames both ways, thumbnails, downloads and zips."""

from __future__ import annotations

import io
import zipfile

from nightcrew.testing.archive import fits_frame

from .conftest import Client


async def upload(client: Client, name: str, **kwargs: object) -> dict[str, object]:
    status, body = await client.upload(fits_frame(**kwargs), name)  # type: ignore[arg-type]
    assert status == 201, body
    return body


async def test_headers_hold_every_card_in_order_with_comments(client: Client) -> None:
    frame = await upload(client, "a.fits", OBJECT="M 13", GAIN=1.5)
    status, body = await client.get(f"/frames/{frame['id']}/headers/")
    assert status == 200
    assert body["data"]["OBJECT"] == "M 13" and body["data"]["GAIN"] == 1.5 and body["data"]["NAXIS1"] == 32
    keys = [card[0] for card in body["cards"]]
    assert keys[:3] == ["SIMPLE", "BITPIX", "NAXIS"] and keys.index("DATE-OBS") < keys.index("OBJECT")


async def test_related_links_raw_and_reduced_and_masters_both_ways(client: Client) -> None:
    bias = await upload(
        client,
        "master-bias.fits",
        imagetyp="master_bias",
        exptime=0.0,
        date_obs="2026-11-24T17:00:00",
        seed=1,
    )
    flat = await upload(
        client,
        "master-flat.fits",
        imagetyp="master_flat",
        exptime=0.0,
        date_obs="2026-11-24T17:30:00",
        seed=2,
    )
    raw = await upload(client, "m13.fits", OBJECT="M 13", seed=3)
    reduced = await upload(
        client,
        "m13-red.fits",
        OBJECT="M 13",
        RAWFILE="m13.fits",
        BIASFILE="master-bias.fits",
        FLATFILE="master-flat.fits",
        seed=4,
    )
    # What `nightcrew reduce` writes today: the masters' DATE-OBS and size.
    old_style = await upload(
        client, "m13b_red.fits", OBJECT="M 13", CAL_BIAS="2026-11-24T17:00:00.000 x10", seed=5
    )
    assert reduced["RLEVEL"] == 91 and old_style["RLEVEL"] == 91 and raw["RLEVEL"] == 0

    async def related(frame: dict[str, object]) -> list[tuple[str, str]]:
        status, body = await client.get(f"/frames/{frame['id']}/related/")
        assert status == 200
        return sorted((item["relation"], item["basename"]) for item in body)

    assert await related(reduced) == [
        ("bias", "master-bias.fits"),
        ("flat", "master-flat.fits"),
        ("raw", "m13.fits"),
    ]
    assert await related(raw) == [("reduced", "m13-red.fits")]
    assert await related(bias) == [("calibrated", "m13-red.fits"), ("calibrated", "m13b_red.fits")]
    assert await related(flat) == [("calibrated", "m13-red.fits")]
    assert await related(old_style) == [("bias", "master-bias.fits")]


async def test_thumbnail_download_and_zip(client: Client) -> None:
    first = await upload(client, "a.fits", shape=(600, 400), seed=1)
    second = await upload(client, "b.fits", seed=2)
    status, png, kind = await client.get_bytes(f"/frames/{first['id']}/thumbnail/", size=128)
    assert status == 200 and kind == "image/png" and png.startswith(b"\x89PNG\r\n\x1a\n")
    width, height = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
    assert (width, height) == (80, 120)  # 400 x 600 binned by 5 to fit 128
    status, data, kind = await client.get_bytes(f"/frames/{second['id']}/download/")
    assert status == 200 and data == fits_frame(seed=2)
    status, data, kind = await client.get_bytes("/frames/zip/", frame_ids=f"{first['id']},{second['id']}")
    assert status == 200 and kind == "application/zip"
    with zipfile.ZipFile(io.BytesIO(data)) as bundle:
        assert sorted(bundle.namelist()) == ["20261124/a.fits", "20261124/b.fits"]
        assert bundle.read("20261124/b.fits") == fits_frame(seed=2)
    async with client.http.post(
        f"{client.archive.url}/frames/zip/", json={"frame_ids": [second["id"]]}
    ) as response:
        assert response.status == 200
        with zipfile.ZipFile(io.BytesIO(await response.read())) as bundle:
            assert bundle.namelist() == ["20261124/b.fits"]


async def test_unknown_frames_and_bad_ids_are_named(client: Client) -> None:
    await upload(client, "a.fits")
    assert await client.get("/frames/999/") == (404, {"error": "Not Found", "detail": "no frame with id 999"})
    status, body = await client.get("/frames/zip/", frame_ids="1,999")
    assert (status, body["detail"]) == (404, "no frames with ids 999")
    status, body = await client.get("/frames/zip/", frame_ids="")
    assert status == 400 and "frame_ids must list at least one frame id" in body["detail"]
    status, body = await client.get("/frames/1/thumbnail/", size=5000)
    assert status == 400 and "size must be within 16..1024, got 5000" in body["detail"]


async def test_a_raw_frame_shows_the_wcs_of_its_reduced_frame_once_solved(client: Client) -> None:
    raw = await upload(client, "ngc1.fits", OBJECT="NGC 1", seed=6)

    async def raw_header() -> dict[str, object]:
        status, body = await client.get(f"/frames/{raw['id']}/headers/")
        assert status == 200
        return body["data"]  # type: ignore[no-any-return]

    assert "CTYPE1" not in await raw_header()  # not solved yet
    solution = {"CTYPE1": "RA---TAN", "CTYPE2": "DEC--TAN", "CRVAL1": 1.84, "CRVAL2": 27.7, "CDELT1": -3e-4}
    await upload(client, "ngc1_red.fits", RAWFILE="ngc1.fits", seed=7, **solution)
    header = await raw_header()
    assert {key: header[key] for key in solution} == solution
    assert header["OBJECT"] == "NGC 1"  # its own cards stay
