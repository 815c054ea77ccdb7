"""A module that exists but imports a package that does not (for the configuration tests)."""

from __future__ import annotations

import nightcrew_no_such_dependency  # type: ignore[import-not-found]  # noqa: F401


class Unreachable:
    pass
