"""``${NAME}`` and ``${NAME:-default}`` substitution in configuration scalars.

Secrets and per-site values come from the environment, so they never need to be written into a
YAML file. ``$${`` writes a literal ``${``. Like the shell, ``:-`` uses the default when the variable
is unset *or* empty.
"""

from __future__ import annotations

import re
from collections.abc import Mapping

__all__ = ["EnvSubstitutionError", "substitute_env", "unset_variable"]

# One alternative per case: escaped "$${", a complete placeholder, an unterminated one.
_TOKEN = re.compile(r"\$\$\{|\$\{([^}]*)\}|\$\{")
_PLACEHOLDER_BODY = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)(?::-(.*))?", re.DOTALL)
_WHOLE_PLACEHOLDER = re.compile(r"\$\{[^}]*\}")


class EnvSubstitutionError(Exception):
    """A placeholder cannot be substituted; the caller adds file, line and key."""


#: The one wording of an unset variable (``nightcrew check`` groups these by variable).
_UNSET = "environment variable {} is not set"
_UNSET_PATTERN = re.compile(r"environment variable (\S+) is not set")


def unset_variable(message: str) -> str | None:
    """The variable an error message says is unset, else None."""
    match = _UNSET_PATTERN.fullmatch(message)
    return match.group(1) if match else None


def substitute_env(text: str, environ: Mapping[str, str]) -> tuple[str, bool]:
    """Replace the placeholders in ``text`` by values from ``environ``.

    Returns:
        The substituted text, and whether ``text`` consisted of exactly one placeholder (then the
        caller may read the result as a YAML scalar of its own, e.g. an int).

    Raises:
        EnvSubstitutionError: A variable without default is not set, or a placeholder is malformed.
    """

    def replace(match: re.Match[str]) -> str:
        token = match.group(0)
        if token == "$${":
            return "${"
        body = match.group(1)
        if body is None:
            raise EnvSubstitutionError(f"unterminated placeholder in {text!r} (missing '}}')")
        parsed = _PLACEHOLDER_BODY.fullmatch(body)
        if parsed is None:
            raise EnvSubstitutionError(
                f"malformed placeholder {token!r} (use ${{NAME}} or ${{NAME:-default}})"
            )
        name, default = parsed.group(1), parsed.group(2)
        value = environ.get(name)
        if default is not None:
            return value if value else default
        if value is None:
            raise EnvSubstitutionError(_UNSET.format(name))
        return value

    substituted = _TOKEN.sub(replace, text)
    return substituted, _WHOLE_PLACEHOLDER.fullmatch(text) is not None
