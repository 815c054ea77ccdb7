"""The pure INDI layer: parsing, building, and the stream parser's errors (no server needed)."""

from __future__ import annotations

import base64
import zlib

import pytest

from nightcrew.bridges.indi import Blob, IndiProtocolError, IndiStreamParser, PropertyState, VectorKind
from nightcrew.bridges.indi.protocol import (
    DefVector,
    DelProperty,
    IndiMessage,
    SetVector,
    enable_blob,
    new_vector,
    parse_number,
)

DEF_NUMBER = (
    b'<defNumberVector device="Scope" name="EQUATORIAL_EOD_COORD" state="Idle" perm="rw" timeout="60">'
    b'<defNumber name="RA" format="%010.6m" min="0" max="24" step="0">5.5</defNumber>'
    b'<defNumber name="DEC" format="%010.6m" min="-90" max="90" step="0">-12:30:00</defNumber>'
    b"</defNumberVector>"
)


def _blob(data: bytes, *, size: int | None = None, fmt: str = ".fits", name: str = "CCD1") -> bytes:
    text = base64.b64encode(data)
    announced = len(data) if size is None else size
    encoded = (announced + 2) // 3 * 4
    return (
        f'<setBLOBVector device="CCD" name="{name}" state="Ok">'
        f'<oneBLOB name="{name}" size="{announced}" enclen="{encoded}" format="{fmt}">'.encode()
        + text
        + b"</oneBLOB></setBLOBVector>"
    )


def test_numbers_decimal_and_sexagesimal() -> None:
    assert parse_number(" 5.25 ") == 5.25
    assert parse_number("-12:30:00") == -12.5
    assert parse_number("1 30") == 1.5
    with pytest.raises(ValueError, match="not a number"):
        parse_number("abc:def")


def test_a_def_vector_split_anywhere_parses_the_same() -> None:
    stream = DEF_NUMBER + b'<message device="Scope" message="hello"/><delProperty device="Scope" name="X"/>'
    for cut in (1, 7, 50, len(DEF_NUMBER) - 3, len(DEF_NUMBER) + 5):
        parser = IndiStreamParser()
        messages = parser.feed(stream[:cut]) + parser.feed(stream[cut:])
        parser.close()
        assert isinstance(messages[0], DefVector)
        vector = messages[0].vector
        assert (vector.device, vector.name, vector.kind) == (
            "Scope",
            "EQUATORIAL_EOD_COORD",
            VectorKind.NUMBER,
        )
        assert vector.members == {"RA": 5.5, "DEC": -12.5} and vector.limits["RA"] == (0.0, 24.0, 0.0)
        assert messages[1:] == [IndiMessage("Scope", "hello"), DelProperty("Scope", "X", "")]


def test_set_vectors_carry_state_and_values() -> None:
    parser = IndiStreamParser()
    (message,) = parser.feed(
        b'<setSwitchVector device="Scope" name="TELESCOPE_PARK" state="Busy" message="parking">'
        b'<oneSwitch name="PARK">On</oneSwitch><oneSwitch name="UNPARK">Off</oneSwitch></setSwitchVector>'
    )
    assert message == SetVector(
        "Scope",
        "TELESCOPE_PARK",
        VectorKind.SWITCH,
        PropertyState.BUSY,
        {"PARK": True, "UNPARK": False},
        None,
        "parking",
    )


def test_blobs_are_decoded_and_decompressed() -> None:
    data = bytes(range(256)) * 100
    parser = IndiStreamParser()
    (plain,) = parser.feed(_blob(data))
    compressed = zlib.compress(data)
    text = base64.b64encode(compressed)
    head = (
        f'<setBLOBVector device="CCD" name="CCD1"><oneBLOB name="CCD1" size="{len(data)}" format=".fits.z">'
    )
    (packed,) = parser.feed(head.encode() + text + b"</oneBLOB></setBLOBVector>")
    assert isinstance(plain, SetVector) and isinstance(packed, SetVector)
    assert plain.members["CCD1"] == Blob(data, ".fits") == packed.members["CCD1"]


def test_malformed_xml_names_device_and_property() -> None:
    parser = IndiStreamParser()
    with pytest.raises(IndiProtocolError, match=r"Scope\.EQUATORIAL_EOD_COORD: malformed XML"):
        parser.feed(DEF_NUMBER[:150] + b"<<oops>" + DEF_NUMBER[150:])


def test_bad_values_name_device_property_and_member() -> None:
    parser = IndiStreamParser()
    with pytest.raises(IndiProtocolError, match=r"Scope\.EQUATORIAL_EOD_COORD: member RA: not a number"):
        parser.feed(DEF_NUMBER.replace(b">5.5<", b">fast<"))
    with pytest.raises(IndiProtocolError, match=r"Scope\.P: unknown state 'Sleepy'"):
        IndiStreamParser().feed(b'<setTextVector device="Scope" name="P" state="Sleepy"></setTextVector>')


def test_a_truncated_stream_names_the_open_message() -> None:
    parser = IndiStreamParser()
    assert parser.feed(DEF_NUMBER[:150]) == []
    with pytest.raises(
        IndiProtocolError, match=r"Scope\.EQUATORIAL_EOD_COORD: the stream ended inside a message"
    ):
        parser.close()
    halfway_through_a_tag = IndiStreamParser()
    assert halfway_through_a_tag.feed(DEF_NUMBER[:40]) == []
    with pytest.raises(IndiProtocolError, match="the stream ended inside a message"):
        halfway_through_a_tag.close()


def test_a_stream_that_ends_between_messages_is_complete() -> None:
    parser = IndiStreamParser()
    assert len(parser.feed(DEF_NUMBER + b"\n")) == 1
    parser.close()


def test_a_blob_larger_or_smaller_than_announced_is_an_error() -> None:
    data = b"x" * 3000
    with pytest.raises(
        IndiProtocolError, match=r"CCD\.CCD1: BLOB CCD1 holds 3000 bytes, larger than the 2000"
    ):
        IndiStreamParser().feed(_blob(data, size=2000))
    with pytest.raises(IndiProtocolError, match=r"smaller than the 4000"):
        IndiStreamParser().feed(_blob(data, size=4000))


def test_a_blob_far_larger_than_announced_is_cut_off_while_it_streams() -> None:
    stream = _blob(b"y" * 1_000_000, size=100)
    parser = IndiStreamParser()
    with pytest.raises(IndiProtocolError, match=r"CCD\.CCD1: BLOB CCD1 is larger than announced"):
        for start in range(0, len(stream), 65536):
            parser.feed(stream[start : start + 65536])
            assert start < 200_000, "the oversized BLOB was not stopped early"


def test_client_messages() -> None:
    assert new_vector("Scope", "ON_COORD_SET", VectorKind.SWITCH, {"TRACK": True, "SLEW": False}) == (
        b'<newSwitchVector device="Scope" name="ON_COORD_SET"><oneSwitch name="TRACK">On</oneSwitch>'
        b'<oneSwitch name="SLEW">Off</oneSwitch></newSwitchVector>\n'
    )
    assert b'<oneNumber name="RA">5.5</oneNumber>' in new_vector("S", "C", VectorKind.NUMBER, {"RA": 5.5})
    assert b"a&lt;b" in new_vector("S", "T", VectorKind.TEXT, {"X": "a<b"})
    assert enable_blob("CCD & co") == b'<enableBLOB device="CCD &amp; co">Also</enableBLOB>\n'
    with pytest.raises(ValueError, match="expected a number"):
        new_vector("S", "C", VectorKind.NUMBER, {"RA": "fast"})


def test_a_blob_split_anywhere_parses_the_same() -> None:
    data = bytes(range(256)) * 4
    stream = DEF_NUMBER + _blob(data) + b'<message device="CCD" message="done"/>'
    for chunk in (1, 3, 7, 9, 10, 64, 1000):
        parser = IndiStreamParser()
        messages = [
            m for start in range(0, len(stream), chunk) for m in parser.feed(stream[start : start + chunk])
        ]
        parser.close()
        assert isinstance(messages[1], SetVector) and messages[1].members == {"CCD1": Blob(data, ".fits")}
        assert messages[2] == IndiMessage("CCD", "done")


def test_line_broken_base64_split_anywhere_decodes_while_it_streams() -> None:
    data = bytes(range(256)) * 7
    lines = base64.encodebytes(data)  # 76 characters a line, as libindi breaks them
    stream = _blob(data).replace(base64.b64encode(data), b"\n" + lines)
    for chunk in (1, 5, 77, 300):
        parser = IndiStreamParser()
        messages = [
            m for start in range(0, len(stream), chunk) for m in parser.feed(stream[start : start + chunk])
        ]
        assert isinstance(messages[0], SetVector) and messages[0].members == {"CCD1": Blob(data, ".fits")}


def test_a_blob_that_is_not_base64_names_device_property_and_member() -> None:
    stream = _blob(b"z" * 300).replace(b"enp6", b"en*6", 1)
    with pytest.raises(IndiProtocolError, match=r"CCD\.CCD1: BLOB CCD1 cannot be decoded"):
        IndiStreamParser().feed(stream)
    cut_short = _blob(b"z" * 300).replace(b"</oneBLOB>", b"Q</oneBLOB>")
    with pytest.raises(IndiProtocolError, match=r"CCD1 cannot be decoded: .*incomplete quad"):
        IndiStreamParser().feed(cut_short)
