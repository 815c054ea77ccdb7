"""Run by path in a child process: pygcn's VOEvent Transport Protocol client, one JSON line per event.

``python _pygcn_child.py HOST PORT IVORN`` connects to the broker (reconnecting with back-off, as
pygcn does), answers its iamalive and acknowledges each VOEvent (pygcn), and writes to stdout
``{"voevent": <base64 payload>}`` for each VOEvent and ``{"log": <level>, "message": ...}`` for
each of pygcn's log lines (without tracebacks). ``gcn.listen`` never returns, so it runs here,
where the parent stops it by its PID. Only the standard library and pygcn are imported.
"""

from __future__ import annotations

import base64
import json
import logging
import sys
from typing import Any


class _StdoutHandler(logging.Handler):
    def emit(self, record: logging.LogRecord) -> None:
        _write({"log": record.levelno, "message": record.getMessage()})


def _write(message: dict[str, Any]) -> None:
    sys.stdout.write(json.dumps(message) + "\n")
    sys.stdout.flush()


def main(host: str, port: int, ivorn: str) -> None:
    import gcn  # type: ignore[import-untyped]  # here: the parent does not need it

    log = logging.getLogger("pygcn")
    log.addHandler(_StdoutHandler())
    log.setLevel(logging.INFO)
    log.propagate = False

    def forward(payload: bytes, root: Any) -> None:
        _write({"voevent": base64.b64encode(payload).decode("ascii")})

    gcn.listen(host=host, port=port, ivorn=ivorn, handler=forward, log=log, max_reconnect_timeout=8)


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), sys.argv[3])
