"""systemd units for production hosts: one for the supervisor, or one per module.

The units run ``nightcrew`` with the Python that runs this command, log with journald's level
prefixes (``--log-format systemd``) and restart on failure. One unit for ``nightcrew up DIR`` is
the default (``nightcrew status`` then works as everywhere); ``per_module`` writes one
``nightcrew-<module>.service`` per module file instead, with systemd doing the restarts.
"""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

from nightcrew.supervisor._discovery import module_files

__all__ = ["systemd_units"]

_UNIT = """\
[Unit]
Description={description}
After=network-online.target prosody.service
Wants=network-online.target

[Service]
Type=simple
WorkingDirectory={workdir}
{environment}ExecStart={exec_start}
Restart=on-failure
RestartSec=2
# A module closes cleanly on SIGTERM (nightcrew run); the supervisor stops every module first.
# Closing parks the mount and closes the roof: give it the time (see --stop-timeout), not 90 s.
KillSignal=SIGTERM
TimeoutStopSec=600

[Install]
WantedBy=multi-user.target
"""


def systemd_units(
    directory: Path, *, per_module: bool = False, environment_file: Path | None = None
) -> dict[str, str]:
    """Unit file name → text for the modules of ``directory`` (nothing is written here)."""
    directory = directory.resolve()
    base = [sys.executable, "-m", "nightcrew", "--log-format", "systemd"]
    environment = f"EnvironmentFile={environment_file.resolve()}\n" if environment_file else ""

    def unit(description: str, command: list[str]) -> str:
        return _UNIT.format(
            description=description,
            workdir=directory,
            environment=environment,
            exec_start=shlex.join(command),
        )

    if not per_module:
        command = [*base, "up", str(directory), "--log-dir", "/var/log/nightcrew"]
        return {"nightcrew.service": unit(f"nightcrew supervisor for {directory}", command)}
    units = {}
    for module in module_files(directory):
        units[f"nightcrew-{module.name}.service"] = unit(
            f"nightcrew module {module.name}", [*base, "run", str(module.path.resolve())]
        )
    return units
