"""Supervising modules: ``nightcrew up DIR`` runs each module as a process and keeps it running.

Why not supervisord or circus (both on PyPI, both looked at): supervisord is a daemon with its own
INI configuration and an XML-RPC control API, not a library, so nightcrew would have to write its
configuration and talk to it through a second protocol; circus brings pyzmq and tornado for its
control channel. Neither knows a module configuration: the supervisor here reads the same YAML
files (a broken one is one clear error in ``status``, not a crash loop), restarts with backoff and
a limit, and serves its control socket with the standard library (~850 lines in all).
"""

from nightcrew.supervisor._control import SupervisorError, default_socket_path, send_request
from nightcrew.supervisor._discovery import ModuleFile, module_files
from nightcrew.supervisor._heartbeat import DEFAULT_FROZEN_AFTER, heartbeat_loop
from nightcrew.supervisor._logging import LOG_FORMATS, configure_logging
from nightcrew.supervisor._policy import RestartPolicy
from nightcrew.supervisor._process import DEFAULT_STOP_TIMEOUT, ModuleProcess, ModuleStatus
from nightcrew.supervisor._supervisor import Supervisor
from nightcrew.supervisor._systemd import systemd_units

__all__ = [
    "DEFAULT_FROZEN_AFTER",
    "DEFAULT_STOP_TIMEOUT",
    "LOG_FORMATS",
    "ModuleFile",
    "ModuleProcess",
    "ModuleStatus",
    "RestartPolicy",
    "Supervisor",
    "SupervisorError",
    "configure_logging",
    "default_socket_path",
    "heartbeat_loop",
    "module_files",
    "send_request",
    "systemd_units",
]
