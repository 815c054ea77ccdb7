"""One random password per account, made where the account's file says it is kept.

A module or person file keeps its password out of itself by including it from a ``secrets/``
folder (``password: !include secrets/roof.password``, as ``nightcrew init`` writes them).
``nightcrew server init`` makes every such file that does not exist yet: a fresh random password,
the file mode 0600 in a folder of mode 0700, so no two accounts share a password and nobody but
the owner reads one. Existing files are kept (so is a password given any other way).
"""

from __future__ import annotations

import os
import secrets
from collections.abc import Iterable, Mapping
from pathlib import Path

from yaml.nodes import MappingNode, Node, ScalarNode

from nightcrew.config._env import EnvSubstitutionError, substitute_env
from nightcrew.config._yaml import compose_yaml, read_limited_text
from nightcrew.errors import ConfigError

__all__ = ["SECRETS_FOLDER", "client_password", "create_missing_passwords", "read_password"]

#: The folder name that marks an included file as a secret ``server init`` may create.
SECRETS_FOLDER = "secrets"
_SUFFIX = ".password"
_PASSWORD_BYTES = 24  # 32 characters of URL-safe base64: 192 random bits


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
        text = read_limited_text(path)
        root = compose_yaml(text, os.fspath(path))
        for included, line in _password_includes(root):
            try:
                name, _ = substitute_env(included, env)
            except EnvSubstitutionError as exc:
                raise ConfigError(str(exc), file=os.fspath(path), line=line, key="password") from None
            target = Path(os.path.dirname(os.fspath(path))) / name
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


def _password_includes(node: Node | None) -> Iterable[tuple[str, int]]:
    """Every ``password: !include FILE`` in the tree: the file as written and its line."""
    if not isinstance(node, MappingNode):
        return
    for key, value in node.value:
        if isinstance(key, ScalarNode) and key.value == "password":
            if isinstance(value, ScalarNode) and value.tag == "!include":
                yield value.value, value.start_mark.line + 1
        else:
            yield from _password_includes(value)


def _write_private(target: Path, password: str) -> None:
    target.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
    # Created 0600 from the start (no moment in which others could read it), never overwritten.
    descriptor = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(descriptor, "w") as stream:
        # Quoted: a YAML string whatever its characters (URL-safe base64 has no quote).
        stream.write(f"# A random password made by `nightcrew server init` (mode 0600).\n'{password}'\n")
