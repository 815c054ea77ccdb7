"""Writing module files as people write them: a comment header, then YAML with ``!include`` and ``<<``."""

from __future__ import annotations

import json
import textwrap
from typing import Any

import yaml

__all__ = ["MERGE", "Include", "module_text"]

#: The merge key (``<<: !include comm.yaml``): written unquoted, so that the loader merges.
MERGE = "<<"


class Include(str):
    """A value written as ``!include PATH`` (a path relative to the file it is written into)."""


class _Dumper(yaml.SafeDumper):
    def ignore_aliases(self, data: Any) -> bool:
        return True  # a script written twice reads better than &id001 / *id001


_Dumper.add_representer(Include, lambda dumper, value: dumper.represent_scalar("!include", str(value)))


def module_text(header: str, body: dict[str, Any] | str | list[Any]) -> str:
    """``header`` (each line made a comment) followed by ``body`` as block YAML."""
    lines = [wrapped for line in header.strip().splitlines() for wrapped in textwrap.wrap(line, 96) or [""]]
    comment = "".join(f"# {line}".rstrip() + "\n" for line in lines)
    if isinstance(body, str):  # a scalar alone: one quoted line (no "..." document end marker)
        return comment + json.dumps(body) + "\n"
    text = yaml.dump(
        body, Dumper=_Dumper, sort_keys=False, default_flow_style=False, allow_unicode=True, width=100
    )
    # PyYAML quotes the merge key as a plain string; the loader merges only an unquoted one.
    text = text.replace(f"'{MERGE}':", f"{MERGE}:")
    return comment + text
