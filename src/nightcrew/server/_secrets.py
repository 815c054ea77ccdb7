"""One random password per account, made where the account's file says it is kept.

A module or person file keeps its password out of itself by including it from a ``secrets/``
folder (``password: !include secrets/roof.password``, as ``nightcrew init`` writes them).
``nightcrew server init`` makes every such file that does not exist yet: a fresh random password,
the file mode 0600 in a folder of mode 0700, so no two accounts share a password and nobody but
the owner reads one. Existing files are kept (so is a password given any other way). A file that
merges another (``<<: !include roof.yaml``, a one-line overlay) has the password lines of the merged
file too, unless it writes that key itself (the loader then never reads the merged one).
"""

from __future__ import annotations

import os
import secrets
from collections.abc import Iterable, Mapping
from pathlib import Path

from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from nightcrew.config._env import EnvSubstitutionError, substitute_env
from nightcrew.config._loader import MERGE_TAG, written_keys
from nightcrew.config._yaml import compose_yaml, read_limited_text
from nightcrew.errors import ConfigError

__all__ = ["SECRETS_FOLDER", "client_password", "create_missing_passwords", "read_password"]

#: The folder name that marks an included file as a secret ``server init`` may create.
SECRETS_FOLDER = "secrets"
_SUFFIX = ".password"
_PASSWORD_BYTES = 24  # 32 characters of URL-safe base64: 192 random bits
_INCLUDE = "!include"
#: Merged files followed into one another at most (the loader refuses a cycle on its own).
_MAX_MERGE_DEPTH = 8


def create_missing_passwords(
    paths: Iterable[str | os.PathLike[str]], *, environ: Mapping[str, str] | None = None
) -> list[Path]:
    """Write a random password into every missing ``secrets/NAME.password`` that one of the files
    includes as a ``password``; the files written.

    Raises:
        ConfigError: A file cannot be read, or an included path has an unset variable.
    """
    env = os.environ if environ is None else environ
    written = []
    for path in paths:
        for file, included, line in _password_includes(Path(path), env):
            name = _substituted(included, env, file, line, "password")
            target = file.parent / name
            if target.parent.name != SECRETS_FOLDER or not target.name.endswith(_SUFFIX):
                continue  # only the folder the docs name: never a file of the user's choosing
            if not target.exists():
                _write_private(target, secrets.token_urlsafe(_PASSWORD_BYTES))
                written.append(target)
    return written


def client_password(directory: str | os.PathLike[str], name: str) -> Path:
    """The password file of the client account ``name`` (``DIR/secrets/NAME.password``), made at
    random (mode 0600) unless it exists: for a client that has no module file (a JavaScript page,
    pyobs), so registering it needs no YAML."""
    target = Path(directory) / SECRETS_FOLDER / f"{name}{_SUFFIX}"
    if not target.exists():
        _write_private(target, secrets.token_urlsafe(_PASSWORD_BYTES))
    return target


def read_password(path: Path) -> str:
    """The password a file made by :func:`client_password` (or by hand, as YAML) keeps."""
    import yaml  # the file is a YAML scalar, as the `!include` that reads it expects

    value = yaml.safe_load(path.read_text())
    if not isinstance(value, str) or not value:
        raise ConfigError("must hold one non-empty string, the password", file=str(path))
    return value


def _password_includes(path: Path, env: Mapping[str, str]) -> Iterable[tuple[Path, str, int]]:
    """Every ``password: !include FILE`` the file's description reads: the file it is written in,
    the included file as written, and its line."""
    yield from _in_node(compose_yaml(read_limited_text(path), os.fspath(path)), path, env, frozenset(), 0)


def _in_node(
    node: Node | None, path: Path, env: Mapping[str, str], unread: frozenset[str], depth: int
) -> Iterable[tuple[Path, str, int]]:
    """``unread``: keys of this mapping another one replaces (not read: no password of theirs)."""
    if not isinstance(node, MappingNode):
        return
    written = unread | written_keys(node)
    for key, value in node.value:
        if key.tag == MERGE_TAG:
            for source in value.value if isinstance(value, SequenceNode) else [value]:
                yield from _in_merged(source, path, env, written, depth)
        elif not isinstance(key, ScalarNode) or key.value in unread:
            continue
        elif key.value == "password":
            if isinstance(value, ScalarNode) and value.tag == _INCLUDE:
                yield path, value.value, value.start_mark.line + 1
        else:
            yield from _in_node(value, path, env, frozenset(), depth)


def _in_merged(
    source: Node, path: Path, env: Mapping[str, str], unread: frozenset[str], depth: int
) -> Iterable[tuple[Path, str, int]]:
    if not (isinstance(source, ScalarNode) and source.tag == _INCLUDE):
        yield from _in_node(source, path, env, unread, depth)  # an anchor's mapping
        return
    merged = path.parent / _substituted(source.value, env, path, source.start_mark.line + 1, "<<")
    if merged.is_file() and depth < _MAX_MERGE_DEPTH:  # a missing one: the loader says so
        root = compose_yaml(read_limited_text(merged), os.fspath(merged))
        yield from _in_node(root, merged, env, unread, depth + 1)


def _substituted(text: str, env: Mapping[str, str], file: Path, line: int, key: str) -> str:
    try:
        return substitute_env(text, env)[0]
    except EnvSubstitutionError as exc:
        raise ConfigError(str(exc), file=os.fspath(file), line=line, key=key) from None


def _write_private(target: Path, password: str) -> None:
    target.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
    # Created 0600 from the start (no moment in which others could read it), never overwritten.
    descriptor = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(descriptor, "w") as stream:
        # Quoted: a YAML string whatever its characters (URL-safe base64 has no quote).
        stream.write(f"# A random password made by `nightcrew server init` (mode 0600).\n'{password}'\n")
