"""The scheduler and the mastermind open the task archive their own file names (docs/configuration.md).

As an operator writes it: ``archive: {class: ...SqliteTaskArchive, path: tasks.sqlite}``, the path
relative to the file's folder (not the working directory), tasks added with ``nightcrew tasks add``;
the plan goes into the archive, where a mastermind in another process reads it.
"""

from __future__ import annotations

import logging
from datetime import UTC, datetime
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.config import build_object, load_config
from nightcrew.modules import Module
from nightcrew.modules.robotic import Mastermind, SchedulerModule
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.samples import sample_paths
from nightcrew.testing import Observatory

#: Dusk on the night of the sample tasks (2026-11-10).
DUSK = datetime(2026, 11, 10, 18, 30, tzinfo=UTC)

SCHEDULER = """\
class: nightcrew.modules.robotic.SchedulerModule
site: {latitude: 51.56, longitude: 9.94, elevation: 201}
archive: {class: nightcrew.robotic.archives.SqliteTaskArchive, path: tasks.sqlite}
time_limit_s: 10
"""

MASTERMIND = """\
class: nightcrew.modules.robotic.Mastermind
site: {latitude: 51.56, longitude: 9.94, elevation: 201}
archive: {class: nightcrew.robotic.archives.SqliteTaskArchive, path: tasks.sqlite}
runner: {class: nightcrew.robotic.runner.TaskRunner, scripts: {}}
autostart: false
"""


def _module_file(path: Path, text: str, obs: Observatory) -> Module:
    """The module ``path`` describes, on ``obs``'s network and clock (as ``nightcrew sim`` builds it)."""
    path.write_text(text, encoding="utf-8")
    config = load_config(path)
    config.update(comm=obs.comm(path.stem), clock=obs.clock)
    module = build_object(config, Module)
    assert isinstance(module, Module)
    return module


@pytest.fixture
def observatory(tmp_path: Path) -> Path:
    """A folder whose task archive holds the double cluster, added as an operator adds it."""
    folder = tmp_path / "observatory"
    folder.mkdir()
    double_cluster = next(path for path in sample_paths() if path.stem == "double-cluster")
    assert main(["tasks", "--db", str(folder / "tasks.sqlite"), "add", str(double_cluster)]) == 0
    return folder


async def test_the_scheduler_plans_from_the_archive_its_file_names_into_that_archive(
    observatory: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # a relative path in a file is not read against the working directory
    database = observatory / "tasks.sqlite"

    async with Observatory(epoch=DUSK) as obs:
        scheduler = _module_file(observatory / "scheduler.yaml", SCHEDULER, obs)
        assert isinstance(scheduler, SchedulerModule)
        await scheduler.open()
        try:

            async def planned() -> bool:
                return await scheduler.get_plan() is not None

            await obs.wait_for(planned, 600, message="no plan")
            plan = await scheduler.get_plan()
            assert plan is not None and plan.slots
            # The plan is in the archive (its schedule store by default), for a mastermind elsewhere.
            reader = SqliteTaskArchive(database, clock=obs.clock, poll_interval=0)
            await reader.open()
            try:
                entries = await reader.read_schedule()
            finally:
                await reader.close()
            assert {entry.task_id for entry in entries} == {slot.task_id for slot in plan.slots}
        finally:
            await scheduler.close()
    assert not list(elsewhere.iterdir())
    assert "is not open" not in caplog.text


async def test_the_mastermind_opens_and_closes_the_archive_its_file_names(tmp_path: Path) -> None:
    async with Observatory(epoch=DUSK) as obs:
        mastermind = _module_file(tmp_path / "mastermind.yaml", MASTERMIND, obs)
        assert isinstance(mastermind, Mastermind)
        await mastermind.open()
        await mastermind.close()
    assert (tmp_path / "tasks.sqlite").is_file()


def test_check_names_a_missing_input_file_with_its_file_and_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.WARNING)
    (tmp_path / "weather.yaml").write_text(
        "class: nightcrew.modules.test.StandAlone\n"
        "comm:\n"
        "  class: nightcrew.comm.xmpp.XmppComm\n"
        "  jid: weather@observatory.local\n"
        "  password: secret\n"
        "  ca_file: certs/observatory.crt\n",
        encoding="utf-8",
    )
    assert main(["check", str(tmp_path)]) == 2
    error = capsys.readouterr().err.strip()
    assert error == (
        f"{tmp_path}/weather.yaml:6: key 'comm.ca_file': file {tmp_path}/certs/observatory.crt not found"
    )
    (tmp_path / "certs").mkdir()
    (tmp_path / "certs" / "observatory.crt").write_text("a certificate\n", encoding="utf-8")
    assert main(["check", str(tmp_path)]) == 0
