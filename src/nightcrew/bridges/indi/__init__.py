"""The INDI protocol: an asyncio client (and the pure XML layer under it)."""

from nightcrew.bridges.indi.client import (
    IndiAlertError,
    IndiClient,
    IndiConnectionError,
    IndiTimeoutError,
    IndiUpdate,
)
from nightcrew.bridges.indi.protocol import (
    Blob,
    IndiError,
    IndiProtocolError,
    PropertyState,
    Vector,
    VectorKind,
)
from nightcrew.bridges.indi.stream import IndiStreamParser

__all__ = [
    "Blob",
    "IndiAlertError",
    "IndiClient",
    "IndiConnectionError",
    "IndiError",
    "IndiProtocolError",
    "IndiStreamParser",
    "IndiTimeoutError",
    "IndiUpdate",
    "PropertyState",
    "Vector",
    "VectorKind",
]
