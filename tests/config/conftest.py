"""Fixtures for the configuration tests: a scratch directory to write YAML files into."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

WriteFiles = Callable[..., Path]


@pytest.fixture
def write(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> WriteFiles:
    """``write({"a.yaml": text, ...})`` writes the files below a fresh working directory and returns
    the path of the first (relative, so messages name it as written)."""
    monkeypatch.chdir(tmp_path)

    def write_files(files: dict[str, str]) -> Path:
        for name, text in files.items():
            path = tmp_path / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
        return Path(next(iter(files)))

    return write_files
