"""What a person types to a chat module, parsed into a command; pure, no I/O.

Commands: ``/login SECRET``, ``/logout``, ``/loglevel [LEVEL]``, ``/modules``,
``/exec module.method(args)`` and ``/help`` (``/start`` is Telegram's first message, taken as
help). Arguments of ``/exec`` are Python literals read by :func:`~nightcrew.comm.calls.parse_shell_call`
(``ast.literal_eval``: numbers, strings, lists, dicts, True/False/None), never evaluated as code.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

from nightcrew.comm.calls import parse_shell_call
from nightcrew.errors import InvalidArgumentError

__all__ = [
    "HELP",
    "LOG_LEVELS",
    "MAX_LINE_CHARS",
    "Command",
    "Exec",
    "Help",
    "LogLevel",
    "Login",
    "Logout",
    "Modules",
    "level_number",
    "parse_command",
]

#: Longest line taken: a call's arguments are small values, never data.
MAX_LINE_CHARS = 2000
#: Levels ``/loglevel`` takes; OFF forwards no log records (events still come).
LOG_LEVELS = ("DEBUG", "INFO", "WARNING", "ERROR", "CRITICAL", "OFF")

HELP = (
    "Commands:\n"
    "/login SECRET - log in (first of all)\n"
    "/logout - log out (no more messages)\n"
    "/loglevel [LEVEL] - show or set the least level of log records sent to you "
    f"({', '.join(LOG_LEVELS)})\n"
    "/modules - the modules online\n"
    "/exec module.method(arguments) - call a method, e.g. /exec roof.close_roof()"
)


@dataclass(frozen=True)
class Help:
    pass


@dataclass(frozen=True)
class Login:
    secret: str = ""

    def __repr__(self) -> str:  # never the secret in a log line
        return "Login(secret=...)"


@dataclass(frozen=True)
class Logout:
    pass


@dataclass(frozen=True)
class LogLevel:
    level: str | None  # None: show the current one


@dataclass(frozen=True)
class Modules:
    pass


@dataclass(frozen=True)
class Exec:
    module: str
    method: str
    args: tuple[object, ...]


Command = Help | Login | Logout | LogLevel | Modules | Exec


def parse_command(text: str) -> Command:
    """The command in one chat line; InvalidArgumentError saying what is wrong for anything else."""
    line = text.strip()
    if len(line) > MAX_LINE_CHARS:
        raise InvalidArgumentError(f"line too long ({len(line)} characters, at most {MAX_LINE_CHARS})")
    if not line.startswith("/"):
        raise InvalidArgumentError("commands start with '/'; send /help for the list")
    word, _, rest = line.partition(" ")
    # In a group, Telegram writes commands as /exec@botname.
    name = word[1:].partition("@")[0].lower()
    rest = rest.strip()
    if name in ("help", "start"):
        return Help()
    if name == "login":
        if not rest:
            raise InvalidArgumentError("usage: /login SECRET")
        return Login(rest)
    if name == "logout":
        return Logout()
    if name == "modules":
        return Modules()
    if name == "loglevel":
        return LogLevel(_level(rest) if rest else None)
    if name == "exec":
        return _exec(rest)
    raise InvalidArgumentError(f"unknown command /{name[:40]}; send /help for the list")


def _level(word: str) -> str:
    level = word.upper()
    if level not in LOG_LEVELS:
        raise InvalidArgumentError(f"unknown level {word[:40]!r}; one of {', '.join(LOG_LEVELS)}")
    return level


def _exec(call: str) -> Exec:
    if not call:
        raise InvalidArgumentError("usage: /exec module.method(arguments), e.g. /exec roof.close_roof()")
    try:
        target, args = parse_shell_call(call)
    except (RecursionError, MemoryError, ValueError) as exc:  # hostile nesting or huge numbers
        raise InvalidArgumentError(f"cannot read the call: {type(exc).__name__}") from None
    module, _, method = target.partition(".")
    return Exec(module, method, tuple(args))


def level_number(level: str) -> int:
    """The logging number of a ``/loglevel`` name (OFF above every level)."""
    return logging.CRITICAL + 10 if level == "OFF" else int(logging.getLevelName(level))
