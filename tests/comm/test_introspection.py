"""system.* on the wire: every module answers introspection, its catalogue entry and its clock."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

import pytest

from nightcrew.clock import AcceleratedClock
from nightcrew.comm.catalogue import interface_document
from nightcrew.comm.introspection import xmlrpc_type
from nightcrew.errors import InterfaceError, InvalidArgumentError, RemoteError
from nightcrew.interfaces import ImageType, ModuleState
from nightcrew.modules import Module

from .conftest import Network
from .sample import Calculator, Colour, ISlow, Measurement

START = datetime(2026, 11, 24, 22, 0, tzinfo=UTC)


async def test_list_signature_and_help(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    methods = await caller.comm.execute("calc", "system.listMethods", [])
    assert methods == sorted(methods)
    assert {
        "add",
        "divide",
        "wait",
        "get_state",
        "get_config_value",
        "system.listMethods",
        "system.clock",
    } <= set(methods)
    assert await caller.comm.execute("calc", "system.methodSignature", ["add"]) == [
        ["double", "double", "double"]
    ]
    assert await caller.comm.execute("calc", "system.methodSignature", ["measure"]) == [["struct", "string"]]
    assert await caller.comm.execute("calc", "system.methodSignature", ["get_state"]) == [["string"]]
    help_text = await caller.comm.execute("calc", "system.methodHelp", ["wait"])
    assert help_text == "Announces 100 * ``seconds`` (clock seconds) and takes ``seconds`` of wall time."


async def test_describe_module_and_interface(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    document = await caller.comm.execute("calc", "system.describe", [])
    assert document["info"]["title"] == "calc"
    assert document["x-interfaces"] == {"ICalculator": 1, "IConfig": 1, "IModule": 1, "ISlow": 1}
    by_name = {method["name"]: method for method in document["methods"]}
    assert by_name["add"]["params"][1] == {
        "name": "b",
        "required": False,
        "schema": {"type": "number", "default": 1.0},
    }
    assert by_name["wait"]["x-timeout"] == {"seconds": None, "announced": True, "computed_from": ["seconds"]}
    assert by_name["measure"]["result"]["schema"] == {"$ref": "#/components/schemas/Measurement"}
    assert document["components"]["schemas"]["Colour"]["enum"] == ["red", "green"]
    # One interface's entry is exactly what the catalogue says of it (the document crossed the wire intact).
    assert await caller.comm.execute("calc", "system.describe", ["ISlow"]) == interface_document(ISlow)


async def test_unknown_interface_module_or_method_is_one_clear_error(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    with pytest.raises(InterfaceError) as info:
        await caller.comm.execute("calc", "system.describe", ["ICamera"])
    assert (
        info.value.message
        == "module 'calc' does not offer ICamera (offers: ICalculator, IConfig, IModule, ISlow)"
    )
    with pytest.raises(InterfaceError, match=r"^calc: no method 'subtract' \(methods: add, crash, "):
        await caller.comm.execute("calc", "system.methodHelp", ["subtract"])
    with pytest.raises(InterfaceError, match=r"no method 'system.nothing' \(system methods: system.clock, "):
        await caller.comm.execute("calc", "system.nothing", [])
    with pytest.raises(InvalidArgumentError) as refused:
        await caller.comm.execute("calc", "system.methodHelp", [])
    assert refused.value.message == "system.methodHelp(): missing argument 'method'"
    with pytest.raises(RemoteError, match="'ghost' is not online"):
        await caller.comm.execute("ghost", "system.describe", [])


async def test_clock_speed_and_time_are_published(network: Network) -> None:
    clock = AcceleratedClock(START, speed=60)
    await network.start(Calculator, "calc", clock=clock)
    caller = await network.start(Module, "caller")
    answer = await caller.comm.execute("calc", "system.clock", [])
    assert answer["speed"] == 60.0
    # Clock time runs 60x: it has left START behind, by far less than a clock hour in this test.
    assert START <= answer["time"] < START + timedelta(hours=1)
    assert answer["time"].tzinfo is not None


async def test_introspection_works_in_error_state(network: Network) -> None:
    calc = await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    calc.set_error("broken for the test")
    assert await caller.comm.execute("calc", "get_state", []) == ModuleState.ERROR.value
    assert "add" in await caller.comm.execute("calc", "system.listMethods", [])


@pytest.mark.parametrize(
    ("hint", "name"),
    [
        (float, "double"),
        (int, "int"),
        (ImageType | None, "string"),
        (list[int], "array"),
        (tuple[float, float], "array"),
        (Measurement, "struct"),
        (dict[str, int], "struct"),
        (Colour, "string"),
        (bytes, "base64"),
        (datetime, "dateTime.iso8601"),
        (None, "nil"),
        (int | str, "undef"),
    ],
)
def test_xmlrpc_type_names(hint: object, name: str) -> None:
    assert xmlrpc_type(hint) == name
