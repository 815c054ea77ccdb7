"""A private XMPP server for nightcrew: ``nightcrew server init|start|stop|status``.

:func:`init_server` writes a Prosody configuration for loopback (or a given address), a
self-signed certificate and one account per module configuration; :func:`start_server` runs
Prosody in the background with its own data directory and pidfile, no root or systemd needed;
:func:`create_missing_passwords` makes the random passwords the files keep in ``secrets/``.
"""

from nightcrew.server._accounts import Account, accounts_from_configs, policies_named, policy_for_accounts
from nightcrew.server._prosody import (
    ServerSettings,
    init_server,
    register_account,
    server_status,
    start_server,
    stop_server,
)
from nightcrew.server._secrets import client_password, create_missing_passwords, read_password

__all__ = [
    "Account",
    "ServerSettings",
    "accounts_from_configs",
    "client_password",
    "create_missing_passwords",
    "init_server",
    "policies_named",
    "policy_for_accounts",
    "read_password",
    "register_account",
    "server_status",
    "start_server",
    "stop_server",
]
