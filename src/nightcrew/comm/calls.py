"""The text form of a call, ``module.method(arguments)``, as the shell and the web console take it."""

from __future__ import annotations

import ast
from typing import Any

from nightcrew.errors import InvalidArgumentError

__all__ = ["parse_shell_call"]


def parse_shell_call(line: str) -> tuple[str, list[Any]]:
    """``camera.set_filter("R")`` → (``camera.set_filter``, ``["R"]``); arguments are Python literals."""
    try:
        tree = ast.parse(line.strip(), mode="eval")
    except SyntaxError as exc:
        # The line is shown cut: a hostile one may be kilobytes long.
        raise InvalidArgumentError(f"not a call: {line.strip()[:80]!r} ({exc.msg})") from exc
    call = tree.body
    if (
        not isinstance(call, ast.Call)
        or not isinstance(call.func, ast.Attribute)
        or not isinstance(call.func.value, ast.Name)
    ):
        raise InvalidArgumentError(f"expected module.method(arguments), got {line.strip()[:80]!r}")
    if call.keywords:
        raise InvalidArgumentError("keyword arguments are not supported; give all arguments in order")
    try:
        args = [ast.literal_eval(arg) for arg in call.args]
    except ValueError as exc:
        raise InvalidArgumentError(f"arguments must be literals (numbers, strings, lists …): {exc}") from exc
    return f"{call.func.value.id}.{call.func.attr}", args
