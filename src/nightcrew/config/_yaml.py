"""The one way nightcrew reads YAML (and JSON data files): parsing with limits.

Every YAML text nightcrew reads — module configurations, task files, the access policy, command
line values — goes through :func:`compose_yaml`, so a hostile file cannot make the reader grow
without bound or recurse until the interpreter gives up:

* **size**: a file (or text) longer than :data:`MAX_BYTES` is refused before it is parsed;
* **depth**: collections nested deeper than :data:`MAX_DEPTH` are refused while composing (PyYAML's
  composer recurses; ~600 levels used to end in a RecursionError traceback);
* **aliases**: more than :data:`MAX_ALIASES` alias uses, or a document whose aliases expand to more
  than :data:`MAX_NODES` nodes (the "billion laughs" bomb: ten lines, gigabytes once expanded), is
  refused by counting, without expanding anything.

Problems are :class:`~nightcrew.errors.ConfigError` naming the file and, where known, the line.
"""

from __future__ import annotations

import json
import math
import os
import re
from pathlib import Path
from typing import Any

import yaml
from yaml.events import AliasEvent
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from nightcrew.errors import ConfigError

__all__ = [
    "MAX_ALIASES",
    "MAX_BYTES",
    "MAX_DEPTH",
    "MAX_NODES",
    "LimitedLoader",
    "check_data_limits",
    "compose_yaml",
    "load_data_file",
    "parse_data",
    "parse_yaml",
    "read_limited_text",
]

#: Largest text read as YAML or JSON (bytes). Configurations and task files are a few kB.
MAX_BYTES = 1_000_000
#: Deepest nesting of mappings and lists.
MAX_DEPTH = 40
#: Most alias uses (``*anchor``) in one document.
MAX_ALIASES = 1_000
#: Most nodes a document may stand for once every alias is expanded.
MAX_NODES = 200_000


class LimitedLoader(yaml.SafeLoader):
    """SafeLoader that counts depth and aliases while composing; also reads ``1e3`` as a float."""

    def __init__(self, stream: Any) -> None:
        super().__init__(stream)
        self._depth = 0
        self._aliases = 0

    def compose_node(self, parent: Node | None, index: Any) -> Node | None:
        if self.check_event(AliasEvent):
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                mark = self.peek_event().start_mark  # type: ignore[no-untyped-call]
                raise _LimitError(f"more than {MAX_ALIASES} aliases", mark.line + 1)
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                mark = self.peek_event().start_mark  # type: ignore[no-untyped-call]
                raise _LimitError(f"nested deeper than {MAX_DEPTH} levels", mark.line + 1)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1


LimitedLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?[0-9][0-9_]*[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


class _LimitError(Exception):
    def __init__(self, message: str, line: int | None) -> None:
        super().__init__(message)
        self.message = message
        self.line = line


def read_limited_text(path: str | os.PathLike[str], display: str | None = None) -> str:
    """The UTF-8 text of ``path``; ConfigError if unreadable, too large or not UTF-8."""
    name = display if display is not None else os.fspath(path)
    try:
        with open(path, "rb") as stream:
            data = stream.read(MAX_BYTES + 1)
    except FileNotFoundError:
        raise ConfigError("file not found", file=name) from None
    except OSError as exc:
        raise ConfigError(f"cannot read file: {exc.strerror or exc}", file=name) from None
    if len(data) > MAX_BYTES:
        raise ConfigError(f"file larger than {MAX_BYTES} bytes", file=name)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise ConfigError(f"not UTF-8 text (byte 0x{data[exc.start]:02x})", file=name, line=line) from None


def compose_yaml(text: str, file: str, loader: type[LimitedLoader] = LimitedLoader) -> Node | None:
    """The node tree of the YAML document ``text`` (from ``file``), checked against the limits."""
    if len(text) > MAX_BYTES:
        raise ConfigError(f"text larger than {MAX_BYTES} bytes", file=file)
    try:
        root: Node | None = yaml.compose(text, Loader=loader)
    except _LimitError as exc:
        raise ConfigError(exc.message, file=file, line=exc.line) from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        context = f" ({exc.context})" if exc.context else ""
        raise ConfigError(
            f"invalid YAML: {exc.problem}{context}", file=file, line=mark.line + 1 if mark else None
        ) from None
    except yaml.YAMLError as exc:
        raise ConfigError(f"invalid YAML: {exc}", file=file) from None
    except RecursionError:  # a guard above the composer's own recursion, should the limit be raised
        raise ConfigError(f"nested deeper than {MAX_DEPTH} levels", file=file) from None
    if root is not None:
        _check_expanded_size(root, file)
    return root


def _check_expanded_size(root: Node, file: str) -> None:
    # Each node counted once with the size of its subtree: an alias bomb is found without expanding.
    sizes: dict[int, int] = {}
    open_nodes: set[int] = set()  # entered, children not yet sized: meeting one again is a cycle
    stack: list[tuple[Node, bool]] = [(root, False)]
    while stack:
        node, children_done = stack.pop()
        if id(node) in sizes:
            continue
        children = _children(node)
        if not children_done:
            if id(node) in open_nodes:
                raise ConfigError("recursive alias", file=file, line=node.start_mark.line + 1)
            open_nodes.add(id(node))
            stack.append((node, True))
            stack.extend((child, False) for child in children if id(child) not in sizes)
            continue
        open_nodes.discard(id(node))
        size = 1 + sum(sizes.get(id(child), 0) for child in children)
        if size > MAX_NODES:
            raise ConfigError(
                f"aliases expand to more than {MAX_NODES} values", file=file, line=node.start_mark.line + 1
            )
        sizes[id(node)] = size


def _children(node: Node) -> list[Node]:
    if isinstance(node, SequenceNode):
        return list(node.value)
    if isinstance(node, MappingNode):
        return [part for pair in node.value for part in pair]
    return []


def parse_yaml(text: str, file: str) -> Any:
    """The plain value (dicts, lists, scalars) of the YAML document ``text``."""
    root = compose_yaml(text, file)
    if root is None:
        return None
    loader = LimitedLoader("")
    try:
        return loader.construct_document(root)
    except (yaml.YAMLError, ValueError, TypeError, OverflowError) as exc:
        raise _first_bad_scalar(root, file) or ConfigError(f"invalid value: {exc}", file=file) from None


def _first_bad_scalar(root: Node, file: str) -> ConfigError | None:
    """The first scalar that cannot be built (``2026-02-30``), named with its line."""
    loader = LimitedLoader("")
    stack = [root]
    seen: set[int] = set()
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, ScalarNode):
            try:
                loader.construct_object(node)
            except (yaml.YAMLError, ValueError, TypeError, OverflowError) as exc:
                shown = node.value if len(node.value) <= 40 else node.value[:37] + "..."
                return ConfigError(
                    f"invalid value {shown!r}: {exc}", file=file, line=node.start_mark.line + 1
                )
        stack.extend(reversed(_children(node)))
    return None


def parse_data(text: str, file: str, *, as_json: bool = False) -> Any:
    """The plain value of a YAML or JSON document, within the same limits for both."""
    if not as_json:
        return parse_yaml(text, file)
    if len(text) > MAX_BYTES:
        raise ConfigError(f"text larger than {MAX_BYTES} bytes", file=file)
    try:
        data = json.loads(text, parse_constant=_refuse_constant)
    except _LimitError as exc:
        raise ConfigError(exc.message, file=file) from None
    except json.JSONDecodeError as exc:
        raise ConfigError(f"invalid JSON: {exc.msg}", file=file, line=exc.lineno) from None
    except RecursionError:
        raise ConfigError(f"nested deeper than {MAX_DEPTH} levels", file=file) from None
    check_data_limits(data, file)
    return data


def _refuse_constant(name: str) -> Any:
    raise _LimitError(f"{name} is not a number JSON allows", None)


def check_data_limits(data: Any, file: str) -> None:
    """ConfigError if plain ``data`` nests deeper than :data:`MAX_DEPTH` or holds a NaN/infinity."""
    stack: list[tuple[Any, int]] = [(data, 0)]
    while stack:
        value, depth = stack.pop()
        if isinstance(value, dict | list):
            if depth >= MAX_DEPTH:
                raise ConfigError(f"nested deeper than {MAX_DEPTH} levels", file=file)
            items = value.values() if isinstance(value, dict) else value
            stack.extend((item, depth + 1) for item in items)
        elif isinstance(value, float) and not math.isfinite(value):
            raise ConfigError(f"{value} is not a finite number", file=file)


def load_data_file(path: str | os.PathLike[str]) -> Any:
    """The plain value of a YAML or JSON (by suffix ``.json``) file, read and parsed with limits."""
    name = os.fspath(path)
    return parse_data(read_limited_text(path), name, as_json=Path(name).suffix.lower() == ".json")
