"""A class whose hints cannot all be evaluated at run time, and a module that fails to import."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pathlib import PurePath


class HalfHinted:
    """``where``'s hint names a class imported only for type checkers: it must accept anything."""

    def __init__(self, where: PurePath, count: int = 0) -> None:
        self.where = where
        self.count = count
