"""Reading YAML configuration files: includes, merges, environment placeholders, locations.

The file is *composed* (not loaded) with PyYAML, so every node still carries its line; nodes are
then turned into :class:`ConfigNode` / :class:`ConfigList` / plain scalars by :class:`_FileReader`,
which resolves, on the way:

* ``key: !include other.yaml`` — the content of ``other.yaml`` (path relative to the including
  file, may contain placeholders);
* ``<<: !include base.yaml`` (or ``<<: *anchor``, or a list of either) — a shallow merge: keys
  written in the including mapping win (the merged values they replace are not read at all, so
  their includes and placeholders need not resolve), and earlier merge sources win over later ones
  (YAML's rule);
* ``${NAME}`` / ``${NAME:-default}`` in scalar values (not in keys). When a plain (unquoted) scalar is
  exactly one placeholder, the substituted text is read again as a YAML scalar, so
  ``interval: ${INTERVAL:-10}`` is the int 10; a quoted scalar always stays a string.

Keys are always strings (``on:`` is the key ``"on"``, not ``True``), duplicate keys are an error,
and ``1e3`` is a float (YAML 1.1 would read it as a string).
"""

from __future__ import annotations

import os
from collections.abc import Collection, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from nightcrew.config._env import EnvSubstitutionError, substitute_env
from nightcrew.config._hints import describe_value
from nightcrew.config._nodes import ConfigList, ConfigNode, Location, join_key
from nightcrew.config._validator import is_secret_key
from nightcrew.config._yaml import MAX_NODES, LimitedLoader, compose_yaml, read_limited_text
from nightcrew.errors import ConfigError

__all__ = ["MERGE_TAG", "LoadedFile", "load_file", "written_keys"]

_INCLUDE_TAG = "!include"
MERGE_TAG = "tag:yaml.org,2002:merge"
_STR_TAG = "tag:yaml.org,2002:str"
_MAP_TAG = "tag:yaml.org,2002:map"
_SEQ_TAG = "tag:yaml.org,2002:seq"
_SCALAR_TAGS = {"tag:yaml.org,2002:" + name for name in ("str", "int", "float", "bool", "null", "timestamp")}


@dataclass
class LoadedFile:
    """What :func:`load_file` read.

    Attributes:
        value: The file's content (a :class:`ConfigNode` for a mapping).
        included: Resolved paths of every file included, directly or not.
    """

    value: Any
    included: set[Path] = field(default_factory=set)


def load_file(
    path: str | os.PathLike[str],
    environ: Mapping[str, str] | None = None,
    *,
    skip_keys: Collection[str] = (),
) -> LoadedFile:
    """Read one YAML file with its includes; the top-level keys in ``skip_keys`` (merged ones too)
    are left out unread, as keys a merge replaces are: their includes and placeholders need not resolve.

    Raises:
        ConfigError: Unreadable file, bad YAML, missing include, include cycle, unset variable, ...
    """
    reader = _FileReader(os.environ if environ is None else environ)
    display = os.path.normpath(os.fspath(path))
    value = reader.read(Path(display), display, stack=(), key="", unread=frozenset(skip_keys))
    return LoadedFile(value, reader.included)


def written_keys(node: MappingNode) -> set[str]:
    """The keys a mapping writes itself (not its ``<<`` merges): they replace merged ones unread."""
    return {str(k.value) for k, _ in node.value if isinstance(k, ScalarNode) and k.tag != MERGE_TAG}


def _location(file: str, node: Node) -> Location:
    return Location(file, node.start_mark.line + 1)


class _FileReader:
    """Turns YAML files into located values; one instance per top-level file."""

    def __init__(self, environ: Mapping[str, str]) -> None:
        self._environ = environ
        # Builds scalars from their tag and text, exactly as yaml.safe_load would.
        self._scalars = LimitedLoader("")
        self.included: set[Path] = set()
        self._converting: set[int] = set()
        # Aliases and includes are expanded here: count what they stand for (see _yaml.MAX_NODES).
        self._converted = 0

    def read(
        self,
        path: Path,
        display: str,
        stack: tuple[Path, ...],
        key: str,
        unread: frozenset[str] = frozenset(),
    ) -> Any:
        root = compose_yaml(read_limited_text(path, display), display)
        if root is None:
            return None
        return self._convert(root, display, (*stack, path.resolve()), key, unread)

    def _convert(
        self, node: Node, file: str, stack: tuple[Path, ...], key: str, unread: frozenset[str] = frozenset()
    ) -> Any:
        """``unread``: keys of a mapping to leave out (those that replace them are elsewhere)."""
        if node.tag == _INCLUDE_TAG:
            return self._include(node, file, stack, key, unread)
        # An alias is the same node object again; one inside itself would recurse forever.
        if id(node) in self._converting:
            raise ConfigError("recursive alias", file=file, line=node.start_mark.line + 1, key=key or None)
        self._converted += 1
        if self._converted > MAX_NODES:
            raise ConfigError(
                f"aliases and includes expand to more than {MAX_NODES} values",
                file=file,
                line=node.start_mark.line + 1,
            )
        self._converting.add(id(node))
        try:
            if isinstance(node, MappingNode):
                return self._mapping(node, file, stack, key, unread)
            if isinstance(node, SequenceNode):
                return self._sequence(node, file, stack, key)
            assert isinstance(node, ScalarNode)
            return self._scalar(node, file, key)
        finally:
            self._converting.discard(id(node))

    def _mapping(
        self, node: MappingNode, file: str, stack: tuple[Path, ...], key: str, unread: frozenset[str]
    ) -> ConfigNode:
        self._check_tag(node, _MAP_TAG, file, key)
        own = ConfigNode(location=_location(file, node))
        merge_sources: list[ConfigNode] = []
        # What the merged mappings need not read: the keys written here replace theirs.
        written = unread | written_keys(node)
        for key_node, value_node in node.value:
            if key_node.tag == MERGE_TAG:
                merge_sources.extend(self._merge_sources(value_node, file, stack, key, written))
                continue
            name = self._key(key_node, file, key)
            if name in unread:
                continue
            if name in own:
                first = own.location_of(name)
                raise ConfigError(
                    f"duplicate key '{name}' (first written on line {first.line if first else '?'})",
                    file=file,
                    line=key_node.start_mark.line + 1,
                    key=join_key(key, name),
                )
            value = self._convert(value_node, file, stack, join_key(key, name))
            own.set_located(name, value, _location(file, key_node))
        if not merge_sources:
            return own
        # Merged keys first (they are the base), then the mapping's own keys, which win.
        merged = ConfigNode(location=own.location)
        for source in merge_sources:
            for name, value in source.items():
                if name not in own and name not in merged:
                    merged.set_located(name, value, source.location_of(name))
        for name, value in own.items():
            merged.set_located(name, value, own.location_of(name))
        return merged

    def _merge_sources(
        self, node: Node, file: str, stack: tuple[Path, ...], key: str, unread: frozenset[str]
    ) -> list[ConfigNode]:
        nodes = node.value if isinstance(node, SequenceNode) and node.tag == _SEQ_TAG else [node]
        sources: list[ConfigNode] = []
        for source_node in nodes:
            value = self._convert(source_node, file, stack, key, unread)
            if not isinstance(value, ConfigNode):
                raise ConfigError(
                    f"'<<' merges a mapping (or an !include of one), got {describe_value(value)}",
                    file=file,
                    line=source_node.start_mark.line + 1,
                    key=join_key(key, "<<"),
                )
            sources.append(value)
        return sources

    def _sequence(self, node: SequenceNode, file: str, stack: tuple[Path, ...], key: str) -> ConfigList:
        self._check_tag(node, _SEQ_TAG, file, key)
        result = ConfigList(location=_location(file, node))
        for index, item in enumerate(node.value):
            result.append_located(
                self._convert(item, file, stack, join_key(key, index)), _location(file, item)
            )
        return result

    def _key(self, node: Node, file: str, parent: str) -> str:
        if not isinstance(node, ScalarNode) or node.tag not in _SCALAR_TAGS:
            raise ConfigError(
                "keys must be plain words, not collections or tagged values",
                file=file,
                line=node.start_mark.line + 1,
                key=parent or None,
            )
        # The text as written: YAML 1.1 would turn the keys on/off/yes/no into booleans.
        return str(node.value)

    def _scalar(self, node: ScalarNode, file: str, key: str) -> Any:
        self._check_tag(node, None, file, key)
        if node.tag == _STR_TAG and "$" in node.value:
            try:
                text, whole = substitute_env(node.value, self._environ)
            except EnvSubstitutionError as exc:
                raise ConfigError(
                    str(exc), file=file, line=node.start_mark.line + 1, key=key or None
                ) from None
            if not (whole and node.style is None):
                return text
            # Read the substituted text as YAML would have read it if written there.
            tag = self._scalars.resolve(ScalarNode, text, (True, False))  # type: ignore[no-untyped-call]
            node = ScalarNode(tag, text, node.start_mark, node.end_mark)
        try:
            return self._scalars.construct_object(node, deep=True)
        except (yaml.YAMLError, ValueError, TypeError, OverflowError) as exc:
            shown = node.value if len(node.value) <= 40 else node.value[:37] + "..."
            if is_secret_key(key):
                shown = "(not shown)"
            raise ConfigError(
                f"invalid value {shown!r}: {exc}",
                file=file,
                line=node.start_mark.line + 1,
                key=key or None,
            ) from exc

    def _include(
        self, node: Node, file: str, stack: tuple[Path, ...], key: str, unread: frozenset[str]
    ) -> Any:
        line = node.start_mark.line + 1
        if not isinstance(node, ScalarNode) or not node.value:
            raise ConfigError("!include needs a file name", file=file, line=line, key=key or None)
        try:
            name, _ = substitute_env(node.value, self._environ)
        except EnvSubstitutionError as exc:
            raise ConfigError(str(exc), file=file, line=line, key=key or None) from None
        display = os.path.normpath(os.path.join(os.path.dirname(file), name))
        target = Path(display)
        resolved = target.resolve()
        if resolved in stack:
            chain = " -> ".join([*(p.name for p in stack), resolved.name])
            raise ConfigError(f"include cycle: {chain}", file=file, line=line, key=key or None)
        if not target.is_file():
            raise ConfigError(
                f"cannot include '{name}': file {display} not found", file=file, line=line, key=key or None
            )
        self.included.add(resolved)
        return self.read(target, display, stack, key, unread)

    def _check_tag(self, node: Node, expected: str | None, file: str, key: str) -> None:
        allowed = {expected} if expected else _SCALAR_TAGS
        if node.tag not in allowed:
            raise ConfigError(
                f"unsupported tag {node.tag} (only !include is known)",
                file=file,
                line=node.start_mark.line + 1,
                key=key or None,
            )
