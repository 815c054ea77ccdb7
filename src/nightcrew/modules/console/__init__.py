"""The browser console: :class:`WebConsole` serves the observatory's pages and their API."""

from nightcrew.modules.console._auth import Role
from nightcrew.modules.console.console import STATIC_DIR, WebConsole
from nightcrew.security import hash_password, verify_password

__all__ = ["STATIC_DIR", "Role", "WebConsole", "hash_password", "verify_password"]
