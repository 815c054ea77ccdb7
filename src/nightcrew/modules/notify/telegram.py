"""The Telegram module: people talk to the observatory through a Telegram bot.

Made with python-telegram-bot's :class:`telegram.Bot` (the Bot API client: HTTP, JSON, errors),
driven by the module itself: long polling of ``getUpdates`` in a background task, ``sendMessage``
for replies and notifications. Only private chats are answered (a bot added to a group would
otherwise tell the group). Create the bot with Telegram's @BotFather; see docs/security.md.

Example (``examples/notify/telegram.yaml``)::

    class: nightcrew.modules.notify.Telegram
    token: ${TELEGRAM_TOKEN}
    users:
      123456789: {account: alice, secret_hash: "scrypt$16384$8$1$..."}
"""

from __future__ import annotations

import asyncio
import datetime
import logging
import os
from collections.abc import Coroutine
from typing import TYPE_CHECKING, Any

from nightcrew.errors import ConfigError, RemoteError
from nightcrew.modules.notify._module import ChatModule
from nightcrew.modules.notify._users import users_from_config

if TYPE_CHECKING:
    from telegram import Bot, Update

__all__ = ["Telegram"]

log = logging.getLogger(__name__)

DEFAULT_BASE_URL = "https://api.telegram.org/bot"
_NETWORK_BACKOFF = (1.0, 2.0, 5.0, 10.0, 30.0)


def _telegram_id(key: Any) -> str:
    """A Telegram user id (an integer; names can change, ids cannot)."""
    try:
        return str(int(str(key)))
    except ValueError:
        raise ConfigError(f"'{key}' is not a Telegram user id (a number)", key=f"users.{key}") from None


class Telegram(ChatModule):
    """A Telegram bot for the observatory's people.

    Args:
        token: The bot's token from @BotFather (use ``${TELEGRAM_TOKEN}``; never logged).
        users: Telegram user id → ``{account, secret_hash}`` (see ChatModule); a person who sends
            /help to the bot is told their id.
        base_url: The Bot API's address (another one only for a local Bot API server or a test).
        poll_timeout: Wall seconds one ``getUpdates`` long poll may wait for news.
        **kwargs: ChatModule options (log_level, events, rate_limit) and module options.
    """

    channel = "telegram"

    def __init__(
        self,
        *,
        token: str,
        users: dict[Any, Any],
        base_url: str = DEFAULT_BASE_URL,
        poll_timeout: float = 30.0,
        **kwargs: Any,
    ) -> None:
        if not isinstance(token, str) or ":" not in token:
            raise ConfigError("expected the bot's token from @BotFather (value not shown)", key="token")
        if not 0 < poll_timeout <= 600:
            raise ConfigError(f"must be > 0 and <= 600 seconds, got {poll_timeout}", key="poll_timeout")
        super().__init__(users=users_from_config(users, normalise=_telegram_id), **kwargs)
        self._token = token
        self._base_url = base_url
        self._poll_timeout = float(poll_timeout)
        self._bot: Bot | None = None
        self._side_tasks: set[asyncio.Task[None]] = set()
        self._offset: int | None = None  # of the next update to take
        self.add_background_task(self._poll_loop, restart=False)

    def __repr__(self) -> str:
        return f"<Telegram {self.name}>"  # never the token

    async def open(self) -> None:
        from telegram import Bot
        from telegram.request import HTTPXRequest

        _quiet_http_logs()
        # python-telegram-bot 22 warns on every flood-control reply unless the process opts in to
        # its coming type for `retry_after` (a timedelta), which _seconds() takes.
        os.environ.setdefault("PTB_TIMEDELTA", "true")
        # Long polls on a request object of their own, so that sending never waits for one.
        self._bot = Bot(
            self._token,
            base_url=self._base_url,
            request=HTTPXRequest(connection_pool_size=4),
            get_updates_request=HTTPXRequest(connection_pool_size=1),
        )
        await super().open()

    async def close(self) -> None:
        await super().close()
        for task in list(self._side_tasks):
            task.cancel()
        await asyncio.gather(*self._side_tasks, return_exceptions=True)
        bot, self._bot = self._bot, None
        if bot is not None:
            try:
                if self._offset is not None:  # confirm what was taken: not to be delivered again
                    await bot.get_updates(offset=self._offset, timeout=0, limit=1)
                await bot.shutdown()
            except Exception as exc:  # closing must not fail for a network that is gone
                log.debug("closing the bot's HTTP clients: %s", self._scrub(str(exc)))

    async def _poll_loop(self) -> None:
        from telegram.error import InvalidToken, NetworkError, RetryAfter, TelegramError, TimedOut

        bot = self._bot
        assert bot is not None
        failures = 0
        initialized = False
        while True:
            try:
                if not initialized:
                    await bot.initialize()  # getMe: checks the token
                    initialized = True
                updates = await bot.get_updates(
                    offset=self._offset, timeout=int(self._poll_timeout), allowed_updates=["message"]
                )
            except InvalidToken:
                self.set_error("Telegram refused the bot's token")
                return
            except RetryAfter as exc:
                await asyncio.sleep(_seconds(exc.retry_after))
                continue
            except TimedOut:
                continue  # a long poll that outlived its HTTP timeout: ask again
            except (NetworkError, TelegramError) as exc:
                delay = _NETWORK_BACKOFF[min(failures, len(_NETWORK_BACKOFF) - 1)]
                failures += 1
                log.warning(
                    "%s: Telegram unreachable (%s); again in %g s", self.name, self._scrub(str(exc)), delay
                )
                await asyncio.sleep(delay)
                continue
            failures = 0
            for update in updates:
                self._offset = update.update_id + 1
                self._take(update)

    def _take(self, update: Update) -> None:
        message = update.message
        if message is None or message.from_user is None or not message.text:
            return
        if message.chat.type != "private":
            return  # a bot added to a group would tell the group
        if message.text.lstrip().lower().startswith("/login"):
            self._spawn_deletion(message.chat.id, message.message_id)
        age = (datetime.datetime.now(datetime.UTC) - message.date).total_seconds()
        self.received(str(message.from_user.id), str(message.chat.id), message.text, age=age)

    def _spawn_deletion(self, chat_id: int, message_id: int) -> None:
        """Delete a /login message from the chat (bots may, in private chats): the secret should
        not stay readable on a phone that is lost or lent."""
        self._spawn(self._delete(chat_id, message_id))

    def _spawn(self, work: Coroutine[Any, Any, None]) -> None:
        task = asyncio.get_running_loop().create_task(work)
        self._side_tasks.add(task)
        task.add_done_callback(self._side_tasks.discard)

    async def _delete(self, chat_id: int, message_id: int) -> None:
        from telegram.error import TelegramError

        if self._bot is None:
            return
        try:
            await self._bot.delete_message(chat_id=chat_id, message_id=message_id)
        except TelegramError as exc:
            log.warning("%s: could not delete a /login message: %s", self.name, self._scrub(exc.message))

    async def _send(self, address: str, text: str) -> None:
        from telegram.error import RetryAfter, TelegramError

        bot = self._bot
        if bot is None:
            raise RemoteError("the Telegram bot is closed")
        try:
            await bot.send_message(chat_id=int(address), text=text)
        except RetryAfter as exc:
            # Telegram's own flood control: wait as told, then the caller tries again.
            await asyncio.sleep(min(_seconds(exc.retry_after), 60.0))
            raise RemoteError("Telegram asked to slow down") from exc
        except TelegramError as exc:
            raise RemoteError(f"Telegram: {self._scrub(exc.message)}") from exc

    def _scrub(self, text: str) -> str:
        return text.replace(self._token, "<token>")


def _seconds(value: int | float | datetime.timedelta) -> float:
    return value.total_seconds() if isinstance(value, datetime.timedelta) else float(value)


def _quiet_http_logs() -> None:
    """httpx logs every request at INFO with its URL, and a Bot API URL holds the token."""
    for name in ("httpx", "httpcore", "telegram"):
        logger = logging.getLogger(name)
        if logger.level == logging.NOTSET:
            logger.setLevel(logging.WARNING)
