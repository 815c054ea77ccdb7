"""``nightcrew archive``: a new token file, config errors that name file and key, and the server
run as a user would run it (a subprocess, stopped by SIGTERM)."""

from __future__ import annotations

import asyncio
import os
import signal
import stat
import sys
from pathlib import Path
from typing import Any

import aiohttp
import pytest

from nightcrew.cli.main import main
from nightcrew.config import build_object, load_config
from nightcrew.errors import ConfigError
from nightcrew.services.archive import load_archive_config
from nightcrew.testing.archive import fits_frame
from nightcrew.testing.processes import free_port
from nightcrew.vfs import ArchiveFile, VirtualFileSystem

REPO = Path(__file__).resolve().parents[2]
PATIENCE = 60.0


def test_new_token_is_written_for_its_owner_only_and_never_replaced(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    token = tmp_path / "archive.token"
    assert main(["archive", "--new-token", str(token)]) == 0
    assert stat.S_IMODE(token.stat().st_mode) == 0o600 and len(token.read_text().strip()) >= 40
    assert token.read_text().strip() not in capsys.readouterr().err
    assert main(["archive", "--new-token", str(token)]) == 2
    assert "exists; remove it first" in capsys.readouterr().err


def test_config_errors_name_the_file_and_key(tmp_path: Path) -> None:
    token = tmp_path / "token"
    token.write_text("a-token-of-enough-length\n")
    base = {"storage": "frames", "database": "sqlite:///a.db", "token_file": str(token)}
    token.chmod(0o644)
    with pytest.raises(
        ConfigError, match=r"a.yaml: key 'token_file': .*token is readable by others: chmod 600 it"
    ):
        load_archive_config(base, file="a.yaml")
    token.chmod(0o600)
    assert load_archive_config(base).token == "a-token-of-enough-length"
    assert "a-token-of-enough-length" not in repr(load_archive_config(base))
    cases: list[tuple[dict[str, Any], str]] = [
        ({**base, "colour": 1}, "key 'colour': unknown key 'colour'"),
        ({**base, "token": "x" * 20}, "key 'token': give exactly one of token"),
        ({**base, "database": "mysql://x"}, "key 'database': must be sqlite:///PATH or postgresql://"),
        ({**base, "port": "http"}, "key 'port': must be an integer, got 'http'"),
        ({**base, "max_upload_bytes": 100}, "key 'max_upload_bytes': must be at least one FITS block"),
        (
            {key: value for key, value in base.items() if key != "storage"},
            "key 'storage': a path or URL is required",
        ),
    ]
    for config, message in cases:
        with pytest.raises(ConfigError, match=message.replace("(", r"\(")):
            load_archive_config(config, file="a.yaml")


def test_the_examples_load(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["archive", "--new-token", "archive.token"]) == 0
    config = load_archive_config(dict(load_config(REPO / "examples/archive/archive.yaml")))
    assert (config.port, config.dialect, config.max_zip_frames) == (37190, "sqlite", 500)
    monkeypatch.setenv("NIGHTCREW_ARCHIVE_TOKEN", "t" * 32)
    watcher = load_config(REPO / "examples/archive/watcher.yaml")
    vfs = build_object(watcher["vfs"], VirtualFileSystem)
    assert isinstance(vfs, VirtualFileSystem) and isinstance(vfs.roots["archive"], ArchiveFile)


async def test_the_server_runs_until_sigterm(tmp_path: Path) -> None:
    token = tmp_path / "archive.token"
    assert main(["archive", "--new-token", str(token)]) == 0
    port = free_port()
    config = tmp_path / "archive.yaml"
    config.write_text(
        f"storage: {tmp_path / 'frames'}\ndatabase: sqlite:///{tmp_path / 'archive.db'}\n"
        f"token_file: {token}\nport: {port}\n"
    )
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "nightcrew",
        "archive",
        "--config",
        str(config),
        stderr=asyncio.subprocess.PIPE,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    assert process.stderr is not None
    try:
        async with asyncio.timeout(PATIENCE):
            line = (await process.stderr.readline()).decode()
        assert f"archive at http://127.0.0.1:{port} (sqlite database, frames in {tmp_path}/frames)" in line
        async with aiohttp.ClientSession() as http:
            headers = {"Authorization": f"Bearer {token.read_text().strip()}"}
            url = f"http://127.0.0.1:{port}/frames/upload/?filename=a.fits"
            async with http.post(url, data=fits_frame(), headers=headers) as response:
                assert response.status == 201
            async with http.get(f"http://127.0.0.1:{port}/health") as response:
                assert await response.json() == {"status": "ok", "frames": 1}
    finally:
        if process.returncode is None:
            process.send_signal(signal.SIGTERM)
        async with asyncio.timeout(PATIENCE):
            rest = (await process.stderr.read()).decode()
            assert await process.wait() == 0, rest
    assert token.read_text().strip() not in rest
