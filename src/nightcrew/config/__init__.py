"""Configuration: YAML files that describe modules, validated before anything is built.

A file describes one object: ``class`` is a dotted import path, every other key goes to the
constructor. Values may be descriptions of further objects (mappings with ``class``), included
files (``key: !include other.yaml``, ``<<: !include base.yaml``) and environment placeholders
(``${NAME}``, ``${NAME:-default}``)::

    class: nightcrew.modules.test.StandAlone
    <<: !include common.yaml
    message: Hello
    interval: ${INTERVAL:-10}

Typical use::

    config = load_config("standalone.yaml")   # ConfigNode: a dict that knows file and line of keys
    validate_config(config)                   # raises ConfigError naming file, line and key
    module = build_object(config)             # validates, then builds recursively

Every YAML text (configurations, task files, the access policy) is read through the one limited
reader in :mod:`~nightcrew.config._yaml` (:func:`parse_yaml`, :func:`load_data_file`): size,
nesting depth and alias expansion are bounded, so a hostile file gets a ConfigError, not a hang.

Every problem is reported as one :class:`~nightcrew.errors.ConfigError` whose text reads
``file:line: key 'comm.jid': message``.
"""

from __future__ import annotations

import os
from collections.abc import Collection, Mapping
from typing import Any

from nightcrew.config._builder import build_object, to_plain
from nightcrew.config._discovery import config_files
from nightcrew.config._env import unset_variable
from nightcrew.config._hints import describe_value
from nightcrew.config._loader import load_file
from nightcrew.config._nodes import ConfigList, ConfigNode, Location
from nightcrew.config._paths import DataPath, InputPath
from nightcrew.config._validator import check_value, is_secret_key, iter_problems
from nightcrew.config._yaml import load_data_file, parse_data, parse_yaml
from nightcrew.errors import ConfigError

__all__ = [
    "ConfigList",
    "ConfigNode",
    "DataPath",
    "InputPath",
    "Location",
    "build_object",
    "check_value",
    "config_files",
    "is_secret_key",
    "load_and_build",
    "load_config",
    "load_data_file",
    "parse_data",
    "parse_yaml",
    "to_plain",
    "unset_variable",
    "validate_config",
]


def load_config(
    path: str | os.PathLike[str],
    *,
    environ: Mapping[str, str] | None = None,
    skip_keys: Collection[str] = (),
) -> ConfigNode:
    """Read the object description in the YAML file ``path``, resolving includes and placeholders.

    Args:
        path: The file.
        environ: Values for ``${NAME}`` placeholders; ``os.environ`` by default.
        skip_keys: Top-level keys left out unread (for what the caller gives in their place).

    Raises:
        ConfigError: The file cannot be read or parsed, or is not a mapping.
    """
    loaded = load_file(path, environ, skip_keys=skip_keys)
    if not isinstance(loaded.value, ConfigNode):
        got = "an empty file" if loaded.value is None else describe_value(loaded.value)
        raise ConfigError(
            f"expected a mapping with a 'class' key at the top level, got {got}", file=os.fspath(path), line=1
        )
    return loaded.value


def validate_config(config: Mapping[str, Any], expected: type | None = None) -> None:
    """Check the object description ``config`` against its class's constructor; build nothing.

    Args:
        config: A mapping with ``class`` and the constructor's keys.
        expected: If given, the described class must derive from this one.

    Raises:
        ConfigError: The first problem found (unknown class, unknown or missing key, wrong type).
    """
    problem = next(iter_problems(config, expected), None)
    if problem is not None:
        raise problem


def load_and_build(
    path: str | os.PathLike[str], expected: type | None = None, *, environ: Mapping[str, str] | None = None
) -> Any:
    """:func:`load_config`, then :func:`build_object`."""
    return build_object(load_config(path, environ=environ), expected)
