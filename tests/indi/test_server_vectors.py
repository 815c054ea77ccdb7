"""The server's property model: what it writes is what the client side parses, requests are checked."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest
from astropy import units as u  # type: ignore[import-untyped]
from astropy.coordinates import FK5, SkyCoord  # type: ignore[import-untyped]
from astropy.time import Time  # type: ignore[import-untyped]

from nightcrew.astro import j2000_to_of_date, of_date_to_j2000
from nightcrew.bridges.indi.protocol import DefVector, IndiProtocolError, SetVector, parse_element
from nightcrew.bridges.indi.server_listener import IndiClient
from nightcrew.bridges.indi.server_vectors import (
    BlobMember,
    LightMember,
    NumberMember,
    Permission,
    Property,
    PropertyState,
    SwitchMember,
    SwitchRule,
    TextMember,
    blob_message,
    def_element,
    parse_new,
    set_element,
)
from nightcrew.bridges.indi.stream import IndiStreamParser
from nightcrew.errors import InvalidArgumentError


def eod() -> Property[NumberMember]:
    return Property(
        "telescope",
        "EQUATORIAL_EOD_COORD",
        "Eq. Coordinates",
        "Main Control",
        [
            NumberMember("RA", "RA", 5.5, 0.0, 24.0, 0.0, "%010.6m"),
            NumberMember("DEC", "DEC", -12.25, -90.0, 90.0, 0.0, "%010.6m"),
        ],
        timeout=300.0,
    )


def park() -> Property[SwitchMember]:
    return Property(
        "telescope",
        "TELESCOPE_PARK",
        "Parking",
        "Main",
        [SwitchMember("PARK", "P", True), SwitchMember("UNPARK", "U")],
    )


def new(text: str) -> ET.Element:
    return ET.fromstring(text)


def test_definitions_and_updates_parse_back_on_the_client_side() -> None:
    vector = eod()
    vector.message = "hello"
    parsed = parse_element(def_element(vector))
    assert isinstance(parsed, DefVector)
    assert parsed.vector.members == {"RA": 5.5, "DEC": -12.25}
    assert parsed.vector.limits["RA"] == (0.0, 24.0, 0.0)
    assert (parsed.vector.perm, parsed.vector.timeout, parsed.vector.message) == ("rw", 300.0, "hello")
    assert vector.message == ""  # a message is sent once
    vector.state = PropertyState.BUSY
    vector.by_name["RA"].value = 6.75
    update = parse_element(set_element(vector))
    assert isinstance(update, SetVector)
    assert update.state is PropertyState.BUSY
    assert update.members == {"RA": 6.75, "DEC": -12.25}

    light = Property(
        "d", "STATUS", "Status", "G", [LightMember("A", "a", PropertyState.ALERT)], perm=Permission.READ_ONLY
    )
    text = Property("d", "INFO", "Info", "G", [TextMember("T", "t", "a < b & c")], perm=Permission.READ_ONLY)
    assert isinstance(parse_element(def_element(light)), DefVector)
    assert isinstance(parse_element(def_element(park())), DefVector)
    parsed_text = parse_element(def_element(text))
    assert isinstance(parsed_text, DefVector) and parsed_text.vector.members == {"T": "a < b & c"}


def test_a_blob_arrives_whole_and_its_size_is_the_one_announced() -> None:
    vector = Property(
        "camera", "CCD1", "Image", "Info", [BlobMember("CCD1", "Image")], perm=Permission.READ_ONLY
    )
    data = bytes(range(256)) * 1000
    message = blob_message(vector, "CCD1", data, ".fits")
    stream = IndiStreamParser()
    received = []
    for start in range(0, len(message), 4096):  # in chunks, as over TCP
        received += stream.feed(message[start : start + 4096])
    assert len(received) == 1 and isinstance(received[0], SetVector)
    blob = received[0].members["CCD1"]
    assert getattr(blob, "data", None) == data and getattr(blob, "format", None) == ".fits"
    lying = message.replace(f'size="{len(data)}"'.encode(), b'size="1000"')
    with pytest.raises(IndiProtocolError, match=r"camera\.CCD1: BLOB CCD1 .*larger than"):
        IndiStreamParser().feed(lying)
    with pytest.raises(ValueError, match="has no member CCD2"):
        blob_message(vector, "CCD2", data, ".fits")


def test_requests_are_checked_against_the_property() -> None:
    vector = eod()
    ask = "<newNumberVector device='telescope' name='EQUATORIAL_EOD_COORD'>{}</newNumberVector>"
    assert parse_new(new(ask.format("<oneNumber name='RA'>12:30:00</oneNumber>")), vector) == {"RA": 12.5}
    assert parse_new(new(ask.format("<oneNumber name='DEC'>-5 30</oneNumber>")), vector) == {"DEC": -5.5}
    cases = {
        "<oneNumber name='RA'>25</oneNumber>": r"telescope\.EQUATORIAL_EOD_COORD\.RA=25 is outside 0\.\.24",
        "<oneNumber name='DEC'>north</oneNumber>": r"EQUATORIAL_EOD_COORD\.DEC: not a number: 'north'",
        "<oneNumber name='DEC'>nan</oneNumber>": r"EQUATORIAL_EOD_COORD\.DEC: not a finite number",
        "<oneNumber name='AZ'>1</oneNumber>": r"has no member 'AZ' \(members: RA, DEC\)",
        "<oneSwitch name='RA'>On</oneSwitch>": r"expected <oneNumber name=\.\.\.>, got <oneSwitch>",
        "": r"the request names no member",
    }
    for body, message in cases.items():
        with pytest.raises(InvalidArgumentError, match=message):
            parse_new(new(ask.format(body)), vector)
    with pytest.raises(
        InvalidArgumentError, match=r"EQUATORIAL_EOD_COORD is a Number property, not a Switch one"
    ):
        parse_new(new("<newSwitchVector><oneSwitch name='RA'>On</oneSwitch></newSwitchVector>"), vector)
    vector.perm = Permission.READ_ONLY
    with pytest.raises(InvalidArgumentError, match=r"telescope\.EQUATORIAL_EOD_COORD is read-only"):
        parse_new(new(ask.format("<oneNumber name='RA'>1</oneNumber>")), vector)


def test_switch_requests_follow_the_rule() -> None:
    vector = park()
    ask = "<newSwitchVector device='telescope' name='TELESCOPE_PARK'>{}</newSwitchVector>"
    assert parse_new(new(ask.format("<oneSwitch name='UNPARK'>On</oneSwitch>")), vector) == {
        "PARK": False,
        "UNPARK": True,
    }
    with pytest.raises(
        InvalidArgumentError, match=r"only one switch may be On \(OneOfMany\), got PARK, UNPARK"
    ):
        parse_new(
            new(ask.format("<oneSwitch name='PARK'>On</oneSwitch><oneSwitch name='UNPARK'>On</oneSwitch>")),
            vector,
        )
    with pytest.raises(InvalidArgumentError, match=r"one switch must be On \(OneOfMany\)"):
        parse_new(new(ask.format("<oneSwitch name='PARK'>Off</oneSwitch>")), vector)
    with pytest.raises(InvalidArgumentError, match=r"TELESCOPE_PARK\.PARK: a switch is On or Off, got 'yes'"):
        parse_new(new(ask.format("<oneSwitch name='PARK'>yes</oneSwitch>")), vector)
    vector.rule = SwitchRule.AT_MOST_ONE
    assert parse_new(new(ask.format("<oneSwitch name='PARK'>Off</oneSwitch>")), vector) == {"PARK": False}


@pytest.mark.parametrize("when", ["2000-01-01T12:00:00", "2026-11-10T22:00:00", "2027-06-01T00:00:00"])
def test_jnow_conversion_is_fk5_precession(when: str) -> None:
    """INDI's EQUATORIAL_EOD_COORD is the mean equator and equinox of date: FK5 at that equinox."""
    time = Time(when, scale="utc")
    for ra, dec in ((0.0, 0.0), (83.6, 22.0), (279.2, 38.8), (10.0, -75.0)):
        of_date = SkyCoord(ra * u.deg, dec * u.deg, frame=FK5(equinox="J2000")).transform_to(
            FK5(equinox=time)
        )
        ra_date, dec_date = j2000_to_of_date(ra, dec, time.unix)
        assert (
            of_date.separation(SkyCoord(ra_date * u.deg, dec_date * u.deg, frame=FK5(equinox=time))).arcsec
            < 0.5
        )
        back = of_date_to_j2000(ra_date, dec_date, time.unix)
        assert back == pytest.approx((ra, dec), abs=1e-9)


def test_blobs_go_only_to_clients_that_asked_for_them() -> None:
    client = IndiClient(1 << 20, lambda client: None)
    assert client.wants("camera", "CCD_EXPOSURE", is_blob=False)
    assert not client.wants("camera", "CCD1", is_blob=True)  # Never until asked, as the protocol says
    client.set_blob_policy(ET.fromstring('<enableBLOB device="camera">Also</enableBLOB>'))
    assert client.wants("camera", "CCD1", is_blob=True) and client.wants(
        "camera", "CCD_EXPOSURE", is_blob=False
    )
    assert not client.wants("telescope", "CCD1", is_blob=True)
    client.set_blob_policy(ET.fromstring('<enableBLOB device="camera" name="CCD1">Only</enableBLOB>'))
    assert client.wants("camera", "CCD1", is_blob=True)
    client.set_blob_policy(ET.fromstring('<enableBLOB device="camera">Only</enableBLOB>'))
    assert not client.wants("camera", "CCD_EXPOSURE", is_blob=False)
    # An invalid policy is ignored.
    client.set_blob_policy(ET.fromstring('<enableBLOB device="camera">Sometimes</enableBLOB>'))
    assert not client.wants("camera", "CCD_EXPOSURE", is_blob=False)
    assert client.wants(None, None, is_blob=False)  # the server's own messages
