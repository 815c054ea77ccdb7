"""What waits to be sent to one person: bounded, batched, rate-limited; pure (time is passed in).

A flood of log records must never block the module nor flood a phone: records go into a bounded
queue (the oldest fall out and are counted), a token bucket allows ``messages`` per ``per`` wall
seconds, and each message carries as many waiting lines as fit. Events go before log records and
are dropped only when events alone overflow. A message after drops starts by saying what was lost.
"""

from __future__ import annotations

from collections import Counter, deque
from dataclasses import dataclass

from nightcrew.errors import ConfigError

__all__ = ["MAX_MESSAGE_CHARS", "IncomingLimit", "Outbox", "RateLimit", "TokenBucket"]

#: Telegram takes 4096 characters a message; XMPP clients show long ones badly too.
MAX_MESSAGE_CHARS = 3500
#: One line of a message at most (a long traceback is cut).
MAX_LINE_CHARS = 1000


@dataclass(frozen=True)
class RateLimit:
    """At most ``messages`` messages per ``per`` wall seconds to one person, ``queue`` lines waiting."""

    messages: int = 20
    per: float = 60.0
    queue: int = 200

    def __post_init__(self) -> None:
        if isinstance(self.messages, bool) or not (isinstance(self.messages, int) and self.messages >= 1):
            raise ConfigError(f"must be an integer >= 1, got {self.messages!r}", key="rate_limit.messages")
        if (
            isinstance(self.per, bool)
            or not isinstance(self.per, int | float)
            or not 0 < self.per < float("inf")
        ):
            raise ConfigError(f"must be > 0 seconds, got {self.per!r}", key="rate_limit.per")
        if isinstance(self.queue, bool) or not (isinstance(self.queue, int) and self.queue >= 1):
            raise ConfigError(f"must be an integer >= 1, got {self.queue!r}", key="rate_limit.queue")


class TokenBucket:
    """``capacity`` messages at once, refilled at ``capacity / per`` a second."""

    def __init__(self, limit: RateLimit, now: float) -> None:
        self._capacity = float(limit.messages)
        self._rate = limit.messages / limit.per
        self._tokens = self._capacity
        self._updated = now

    def wait_time(self, now: float) -> float:
        """Seconds until a message may go (0: now)."""
        self._refill(now)
        return 0.0 if self._tokens >= 1.0 else (1.0 - self._tokens) / self._rate

    @property
    def is_full(self) -> bool:
        """Whether no message was taken lately (as of the last look)."""
        return self._tokens >= self._capacity

    def take(self, now: float) -> None:
        self._refill(now)
        self._tokens -= 1.0

    def _refill(self, now: float) -> None:
        self._tokens = min(self._capacity, self._tokens + (now - self._updated) * self._rate)
        self._updated = now


class IncomingLimit:
    """A token bucket per sender, for lines coming in; at most ``max_senders`` remembered."""

    def __init__(self, limit: RateLimit, max_senders: int = 10_000) -> None:
        self._limit = limit
        self._max_senders = max_senders
        self._buckets: dict[str, TokenBucket] = {}

    def allows(self, sender: str, now: float) -> bool:
        """Whether a line from ``sender`` now is taken (and counted)."""
        bucket = self._buckets.get(sender)
        if bucket is None:
            if len(self._buckets) >= self._max_senders:  # many senders: forget the quiet ones
                full = {k: b for k, b in self._buckets.items() if b.wait_time(now) == 0.0 and b.is_full}
                for key in full:
                    del self._buckets[key]
            bucket = self._buckets[sender] = TokenBucket(self._limit, now)
        if bucket.wait_time(now) > 0:
            return False
        bucket.take(now)
        return True


class Outbox:
    """Lines waiting for one person: events first, then log records; the oldest overflow is counted."""

    def __init__(self, capacity: int) -> None:
        self._events: deque[str] = deque()
        self._records: deque[tuple[str, str]] = deque()  # (level name, line)
        self._capacity = capacity
        self._dropped: Counter[str] = Counter()

    def __len__(self) -> int:
        return len(self._events) + len(self._records)

    @property
    def dropped(self) -> int:
        """Lines dropped since the last message (said at its start)."""
        return sum(self._dropped.values())

    def put_event(self, line: str) -> None:
        self._events.append(_cut(line))
        while len(self) > self._capacity and self._records:
            self._dropped[self._records.popleft()[0]] += 1
        if len(self._events) > self._capacity:
            self._events.popleft()
            self._dropped["event"] += 1

    def put_record(self, level: str, line: str) -> None:
        self._records.append((level, _cut(line)))
        if len(self) > self._capacity:
            self._dropped[self._records.popleft()[0]] += 1

    def take_message(self, max_chars: int = MAX_MESSAGE_CHARS) -> str | None:
        """The next message: a note of drops, then as many waiting lines as fit; None if none wait."""
        if not self and not self._dropped:
            return None
        lines = []
        if self._dropped:
            counts = ", ".join(f"{n} {what}" for what, n in sorted(self._dropped.items()))
            lines.append(f"[{self.dropped} dropped (too many to send): {counts}]")
            self._dropped.clear()
        size = sum(len(line) + 1 for line in lines)
        while self._events or self._records:
            line = self._events[0] if self._events else self._records[0][1]
            if lines and size + len(line) + 1 > max_chars:
                break
            if self._events:
                self._events.popleft()
            else:
                self._records.popleft()
            lines.append(line)
            size += len(line) + 1
        return "\n".join(lines)


def _cut(line: str) -> str:
    return line if len(line) <= MAX_LINE_CHARS else f"{line[:MAX_LINE_CHARS]}… ({len(line)} characters)"
