"""Every interface method is async, abstract, documented and fully typed with wire-encodable types."""

from __future__ import annotations

import inspect
import types
import typing
from collections.abc import Callable
from typing import Any

import pytest

from nightcrew.interfaces.base import Interface, interface_methods, interfaces_of

from .catalogue import ALL_INTERFACES, declared_methods, method_id
from .wire_types import hint_problems

METHODS = declared_methods()
Method = tuple[type[Interface], str, Callable[..., Any]]


def _parameters(func: Callable[..., Any]) -> list[inspect.Parameter]:
    return list(inspect.signature(func).parameters.values())[1:]  # without self


def test_methods_were_found() -> None:
    assert len(METHODS) >= 70


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_method_is_async_and_abstract(item: Method) -> None:
    _, _, func = item
    assert inspect.iscoroutinefunction(func)
    assert getattr(func, "__isabstractmethod__", False)


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_method_has_one_line_docstring(item: Method) -> None:
    doc = (item[2].__doc__ or "").strip()
    assert doc, "missing docstring"
    assert "\n" not in doc, "docstring should be one line"


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_method_is_fully_typed(item: Method) -> None:
    _, _, func = item
    signature = inspect.signature(func)
    assert next(iter(signature.parameters)) == "self"
    for param in _parameters(func):
        assert param.annotation is not inspect.Parameter.empty, f"{param.name} has no type hint"
        assert param.kind in (param.POSITIONAL_OR_KEYWORD, param.KEYWORD_ONLY), f"*{param.name} not allowed"
    assert signature.return_annotation is not inspect.Parameter.empty, "no return type"
    typing.get_type_hints(func)  # every hint must resolve at run time, where the codec reads it


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_method_types_can_travel(item: Method) -> None:
    _, _, func = item
    problems = [p for name, hint in typing.get_type_hints(func).items() for p in hint_problems(hint, name)]
    assert problems == []


def _allows_none(hint: Any) -> bool:
    origin = typing.get_origin(hint)
    return (origin is typing.Union or origin is types.UnionType) and type(None) in typing.get_args(hint)


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_optional_arguments_have_defaults(item: Method) -> None:
    _, _, func = item
    hints = typing.get_type_hints(func)
    for param in _parameters(func):
        if _allows_none(hints[param.name]):
            assert param.default is not inspect.Parameter.empty, f"optional {param.name} needs a default"


def test_shared_method_names_have_one_signature() -> None:
    # A proxy maps a method name to one definition; two interfaces declaring the same name
    # differently would make calls on a module offering both ambiguous.
    seen: dict[str, tuple[str, Any]] = {}
    for iface, name, func in METHODS:
        shape = (inspect.signature(func), typing.get_type_hints(func))
        if name in seen:
            owner, other = seen[name]
            assert shape == other, f"{name}: {iface.__name__} differs from {owner}"
        else:
            seen[name] = (iface.__name__, shape)


@pytest.mark.parametrize("iface", ALL_INTERFACES, ids=lambda cls: cls.__name__)
def test_interface_methods_sees_inherited_methods(iface: type[Interface]) -> None:
    # The comm advertises/serves what interface_methods finds: it must match the abstract methods.
    found = set(interface_methods(interfaces_of(iface)))
    assert found == set(iface.__abstractmethods__)
