"""Errors of the XMPP transport (importable without slixmpp)."""

from __future__ import annotations

from nightcrew.errors import NightcrewError

__all__ = ["XmppAuthError"]


class XmppAuthError(NightcrewError):
    """The XMPP server refused the login (wrong password, unknown account, no TLS where required)."""
