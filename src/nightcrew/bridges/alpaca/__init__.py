"""ASCOM Alpaca: the async client, the error mapping and the ImageBytes format.

Modules built on these live in :mod:`nightcrew.modules.alpaca`.
"""

from nightcrew.bridges.alpaca.client import DEVICE_TYPES, AlpacaClient, AlpacaDevice, check_server_url
from nightcrew.bridges.alpaca.errors import (
    AlpacaConnectionError,
    AlpacaNotConnectedError,
    AlpacaReplyError,
    error_from_reply,
    reply_from_error,
)

__all__ = [
    "DEVICE_TYPES",
    "AlpacaClient",
    "AlpacaConnectionError",
    "AlpacaDevice",
    "AlpacaNotConnectedError",
    "AlpacaReplyError",
    "check_server_url",
    "error_from_reply",
    "reply_from_error",
]
