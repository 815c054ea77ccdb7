"""Alerts from a VOEvent broker turned into rapid-response requests (docs/rapid-response.md)."""

from nightcrew.modules.alerts._notice import Notice, NoticeError, parse_notice
from nightcrew.modules.alerts._rules import AlertRules, Rejected, request_for
from nightcrew.modules.alerts.listener import AlertListener

__all__ = ["AlertListener", "AlertRules", "Notice", "NoticeError", "Rejected", "parse_notice", "request_for"]
