"""``nightcrew init``: an observatory directory for real devices, found on Alpaca and INDI servers.

- :func:`find_devices` (:mod:`._alpaca`, :mod:`._indi`): what the servers offer, as
  :class:`FoundDevice` by role;
- :func:`name_by_role`: module names (``camera``; ``camera1``, ``camera2`` where a role repeats);
- :func:`observatory_files`: the directory's files (site, comm, policy, secrets, devices, robotic
  modules), pure apart from the passwords it is given;
- :func:`write_directory`: all files or none.

The CLI (``nightcrew.cli.init``) only turns answers into :class:`InitOptions`; docs/observatory.md
walks through it.
"""

from nightcrew.night.init._alpaca import ALPACA_ROLES, find_alpaca_devices, found_on_server
from nightcrew.night.init._find import find_devices
from nightcrew.night.init._found import ROLES, FoundDevice, name_by_role
from nightcrew.night.init._indi import find_indi_devices
from nightcrew.night.init._layout import Layout, observatory_files
from nightcrew.night.init._options import CommKind, InitOptions, parse_host_port
from nightcrew.night.init._write import write_directory
from nightcrew.night.init._yaml import Include, module_text

__all__ = [
    "ALPACA_ROLES",
    "ROLES",
    "CommKind",
    "FoundDevice",
    "Include",
    "InitOptions",
    "Layout",
    "find_alpaca_devices",
    "find_devices",
    "find_indi_devices",
    "found_on_server",
    "module_text",
    "name_by_role",
    "observatory_files",
    "parse_host_port",
    "write_directory",
]
