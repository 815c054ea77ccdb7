"""Calling a module's method on behalf of a browser: check, decode by the interface, call, to JSON."""

from __future__ import annotations

import asyncio
import inspect
from typing import Any

from nightcrew.comm.base import Comm
from nightcrew.comm.calls import parse_shell_call
from nightcrew.comm.codec import decode, method_parameters
from nightcrew.errors import InterfaceError, InvalidArgumentError, NightcrewError, RemoteError
from nightcrew.interfaces.base import interface_methods
from nightcrew.modules.console._describe import to_json
from nightcrew.modules.console._directory import ModuleDirectory
from nightcrew.modules.console._http import ApiError, error_body, status_of

__all__ = ["call_json", "call_many", "parse_shell_line"]

#: Calls one /api/read request may hold.
MAX_READS = 50


def parse_shell_line(line: str) -> tuple[str, str, list[Any]]:
    """(module, method, arguments) of a shell line; the CLI shell's parser and its errors."""
    target, args = parse_shell_call(line)
    module, _, method = target.partition(".")
    return module, method, args


async def call_json(
    comm: Comm, directory: ModuleDirectory, module: str, method: str, args: list[Any] | dict[str, Any]
) -> Any:
    """Call ``module.method`` with JSON ``args`` (positional list or by name); the result as JSON.

    Raises ApiError 404 for a module not online or a method it does not offer, and the nightcrew
    error of a bad argument (400) or of the remote call (502/504).
    """
    entry = directory.get(module)
    if entry is None:
        raise ApiError(404, "RemoteError", f"module '{module}' is not online")
    declaration = interface_methods(entry.interfaces).get(method)
    if declaration is None:
        raise ApiError(404, "InterfaceError", f"module '{module}' has no method '{method}'")
    values = _arguments(method, declaration, args)
    try:
        proxy = await comm.proxy(module)
        result = await getattr(proxy, method)(*values)
    except RemoteError as exc:
        if exc.module is None and module not in comm.clients:  # it left before or during the call
            raise ApiError(404, "RemoteError", f"module '{module}' is not online") from exc
        raise
    except InterfaceError as exc:  # it came back with other interfaces
        raise ApiError(404, "InterfaceError", str(exc)) from exc
    return to_json(result)


def _arguments(method: str, declaration: Any, args: list[Any] | dict[str, Any]) -> list[Any]:
    """The full positional argument list, each decoded by its hint (so a bad one is named here)."""
    params, _ = method_parameters(declaration)
    by_name = dict(args) if isinstance(args, dict) else {}
    positional = list(args) if isinstance(args, list) else []
    if len(positional) > len(params):
        raise InvalidArgumentError(f"{method}() takes {len(params)} arguments, got {len(positional)}")
    unknown = set(by_name) - {p.name for p in params}
    if unknown:
        raise InvalidArgumentError(f"{method}() has no parameter {', '.join(sorted(unknown))}")
    values = []
    for index, param in enumerate(params):
        if index < len(positional):
            value = positional[index]
        elif param.name in by_name:
            value = by_name[param.name]
        elif param.default is not inspect.Parameter.empty:
            values.append(param.default)
            continue
        else:
            raise InvalidArgumentError(f"{method}() is missing argument '{param.name}'")
        values.append(decode(value, param.hint, f"{method}() argument '{param.name}'"))
    return values


async def call_many(comm: Comm, directory: ModuleDirectory, calls: list[Any]) -> list[dict[str, Any]]:
    """Run read calls concurrently; each answer is ``{"result": ...}`` or ``{"error": {...}}``."""

    async def one(call: dict[str, Any]) -> dict[str, Any]:
        try:
            result = await call_json(comm, directory, call["module"], call["method"], call.get("args", []))
        except ApiError as exc:
            return error_body(exc.error_class, exc.message)
        except NightcrewError as exc:
            body = error_body(type(exc).__name__, exc.message, exc.module)
            body["error"]["status"] = status_of(exc)
            return body
        return {"result": result}

    return list(await asyncio.gather(*(one(c) for c in calls)))
