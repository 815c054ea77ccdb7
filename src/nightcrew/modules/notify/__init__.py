"""Notifications and commands over chat: :class:`Telegram` and :class:`XmppChat`.

Both take the same commands (``/login``, ``/logout``, ``/loglevel``, ``/modules``, ``/exec``), map
each person to an account of the observatory's access policy, and forward log records and chosen
events with rate limits. See docs/security.md#notifications.
"""

from nightcrew.modules.notify._commands import parse_command
from nightcrew.modules.notify._dispatch import CommandDispatcher, execute_as
from nightcrew.modules.notify._module import DEFAULT_EVENTS, ChatModule
from nightcrew.modules.notify._outbox import Outbox, RateLimit
from nightcrew.modules.notify.telegram import Telegram
from nightcrew.modules.notify.xmppchat import XmppChat

__all__ = [
    "DEFAULT_EVENTS",
    "ChatModule",
    "CommandDispatcher",
    "Outbox",
    "RateLimit",
    "Telegram",
    "XmppChat",
    "execute_as",
    "parse_command",
]
