"""``nightcrew server init|start|stop|status DIR``: a private Prosody for nightcrew modules.

``init DIR [--host 127.0.0.1] [--port 5222] [--domain D] CONFIG...`` writes a Prosody
configuration, a self-signed certificate (``DIR/certs/<domain>.crt``, for the modules'
``ca_file``) and one account per module configuration with a ``comm: {jid, password}``
(``${VAR}`` resolved from the environment) and per person (a comm file alone, as operator.yaml).
A password a file includes from a ``secrets/`` folder (``password: !include
secrets/roof.password``) that does not exist yet is made: random, one per account, mode 0600.
``--account NAME`` registers a client that has no module file (a JavaScript page, pyobs) as a
person, its random password in ``DIR/secrets/NAME.password``. Module accounts own the room; people
are members. Unless it exists, or every module's comm names a
policy file that exists (as ``nightcrew init`` writes them), it writes the starting access policy
``DIR/access.policy`` (docs/security.md) for the modules' comms to name: the modules may call each
other, the ``--operator`` people everything, other people only what reads.
``start`` runs Prosody in the background with its data, log and pidfile in DIR; ``stop`` ends
it; ``status`` says whether it runs (exit 0) or not (exit 3). Using an existing Prosody or
ejabberd instead: see docs/xmpp-servers.md.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.night.init import module_text
from nightcrew.server import (
    Account,
    ServerSettings,
    accounts_from_configs,
    client_password,
    create_missing_passwords,
    init_server,
    policies_named,
    policy_for_accounts,
    read_password,
    server_status,
    start_server,
    stop_server,
)

#: The starting policy ``init`` writes beside the server's files (not *.yaml: no module file).
POLICY_FILE = "access.policy"
_POLICY_HEADER = (
    "The observatory's access policy, written once by `nightcrew server init` (docs/security.md); "
    "every module's comm names it. Modules may call each other, operators everything, observers "
    "only what reads; weather verdicts and safety alarms are trusted only from the safety modules."
)

#: An account name a client may be given (the local part of its JID, and a file name).
_ACCOUNT_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,62}")

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "server", help="a private XMPP server (Prosody)", description=__doc__.split("\n\n", 1)[1]
    )
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    init = actions.add_parser(
        "init",
        help="write config, certificate and accounts",
        usage="nightcrew server init DIR [--host HOST] [--port PORT] [--domain DOMAIN] [CONFIG ...]",
        description=_init_options().format_help().split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    init.add_argument("directory", metavar="DIR")
    # Options may come between DIR and the configs, which one argparse pass cannot take apart.
    init.add_argument("rest", nargs=argparse.REMAINDER, help=argparse.SUPPRESS)
    init.set_defaults(func=_init)
    for name, func, text in (
        ("start", _start, "start the server in the background"),
        ("stop", _stop, "stop the server"),
        ("status", _status, "tell whether the server runs"),
    ):
        action = actions.add_parser(name, help=text)
        action.add_argument("directory", metavar="DIR")
        action.set_defaults(func=func)
    return parser


def _init_options() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="nightcrew server init DIR", add_help=False)
    parser.add_argument("configs", nargs="*", metavar="CONFIG", help="module YAML files with comm.jid")
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on (default: loopback)")
    parser.add_argument("--port", type=int, default=5222, help="client port (default: 5222)")
    parser.add_argument("--domain", action="append", default=[], help="XMPP domain (default: from the JIDs)")
    parser.add_argument(
        "--open-room",
        action="store_true",
        help="let any account of the server enter the room (not members-only)",
    )
    parser.add_argument("--require-tls", action="store_true", help="require TLS on loopback too")
    parser.add_argument(
        "--account",
        action="append",
        default=[],
        metavar="NAME",
        help="register a client without a module file (a person: an observer unless --operator "
        "names it); its random password goes to DIR/secrets/NAME.password",
    )
    parser.add_argument(
        "--operator",
        action="append",
        default=[],
        metavar="NAME",
        help="a person who may call everything (default: operator); other people only read",
    )
    return parser


def _init(args: argparse.Namespace) -> int:
    options = _init_options().parse_intermixed_args(args.rest)
    for made in create_missing_passwords(options.configs):
        print(f"made a random password in {made} (mode 0600)")
    accounts = accounts_from_configs(options.configs)
    accounts += _client_accounts(args.directory, options.account, options.domain, accounts)
    modules = [a for a in accounts if not a.person]
    # Module accounts own the room; with any, it is members-only (docs/security.md). People are
    # members, admitted by the modules from the policy.
    settings = init_server(
        args.directory,
        accounts,
        host=options.host,
        port=options.port,
        domains=options.domain,
        room_owners=[a.jid for a in modules],
        members_only=bool(modules) and not options.open_room,
        require_tls=True if options.require_tls else None,
    )
    names = ", ".join(a.jid for a in accounts) or "no accounts"
    print(
        f"server in {args.directory}: {settings.host}:{settings.port}, {' '.join(settings.domains)}; {names}"
    )
    policy = Path(args.directory) / POLICY_FILE
    named = policies_named(options.configs)
    if policy.exists():
        print(f"kept the access policy {policy}")
        _tell_to_list(options.account, [policy])
    elif named and all(p is not None and p.is_file() for p in named):
        # Every module names a policy that exists (`nightcrew init` writes access.policy beside
        # them): one more here would be named by nobody.
        files = sorted({p for p in named if p is not None})
        print(f"the modules name their access policy ({', '.join(map(str, files))}); none written")
        _tell_to_list(options.account, files)
    elif accounts:
        body = policy_for_accounts(accounts, options.operator or ["operator"])
        policy.write_text(module_text(_POLICY_HEADER, body))
        print(f"wrote the access policy {policy}")
    return 0


def _client_accounts(
    directory: str, names: list[str], domains: list[str], accounts: list[Account]
) -> list[Account]:
    """The ``--account`` clients: people on the observatory's domain, each with its own password."""
    if not names:
        return []
    known = {a.user for a in accounts}
    domain = domains[0] if domains else next((a.domain for a in accounts), None)
    if domain is None:
        raise ConfigError("--account needs a domain: give --domain or the modules' files")
    for name in names:  # every name checked before any file is made
        if not _ACCOUNT_NAME.fullmatch(name):
            raise ConfigError(f"--account {name!r}: a name of letters, digits, '.', '_' or '-'")
        if name in known:
            raise ConfigError(f"--account {name!r}: a module or person file already has this account")
        known.add(name)
    made = []
    for name in names:
        path = client_password(directory, name)
        made.append(Account(name, domain, read_password(path), person=True))
        print(f"account {name}@{domain}: its password is in {path} (mode 0600)")
    return made


def _tell_to_list(names: list[str], policies: list[Path]) -> None:
    """An existing policy is the user's file: say what to add rather than edit it."""
    for name in names:
        print(
            f"add {name} to the accounts of {', '.join(map(str, policies))} (as observer or operator) "
            "to let it in"
        )


def _start(args: argparse.Namespace) -> int:
    pid = start_server(args.directory)
    settings = ServerSettings.load(Path(args.directory))
    print(f"prosody running (pid {pid}) on {settings.host}:{settings.port}")
    return 0


def _stop(args: argparse.Namespace) -> int:
    print("stopped" if stop_server(args.directory) else "not running")
    return 0


def _status(args: argparse.Namespace) -> int:
    pid = server_status(args.directory)
    print(f"running (pid {pid})" if pid is not None else "not running")
    return 0 if pid is not None else 3
