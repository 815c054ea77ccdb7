"""The files of an observatory directory: site, comm, devices by role, and the robotic modules.

:func:`observatory_files` is pure apart from the passwords it is handed: options and named devices
in, ``{relative path: text}`` out. Each robotic module is written only where the devices it needs
exist (a mastermind needs telescope, camera, roof or dome and a weather verdict; focus a focuser;
flats a filter wheel that told its filter names), and the list of what was left out, and why,
comes back beside the files.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from nightcrew.night.init._found import FoundDevice
from nightcrew.night.init._options import InitOptions
from nightcrew.night.init._robotic import images_vfs, robotic_modules
from nightcrew.night.init._yaml import MERGE, Include, module_text
from nightcrew.security import starting_policy

__all__ = ["Layout", "observatory_files"]

#: Files that hold passwords: written with mode 0600 (their folder 0700).
SECRETS = "secrets"
POLICY = "access.policy"  # not *.yaml: `check` and `up` would take it for a module file
#: The people's accounts: the operator may do everything, the observer only read (policy, console).
PEOPLE = ("operator", "observer")


@dataclass
class Layout:
    """What ``init`` writes: file texts by relative path, and the modules left out with the reason."""

    files: dict[str, str] = field(default_factory=dict)
    modules: list[str] = field(default_factory=list)
    left_out: dict[str, str] = field(default_factory=dict)


def observatory_files(
    options: InitOptions, devices: dict[str, FoundDevice], password_for: Callable[[str], str]
) -> Layout:
    """The directory's files for the named devices (:func:`name_by_role`)."""
    layout = Layout()
    layout.files["shared/site.yaml"] = _site(options)
    modules: dict[str, tuple[str, dict[str, Any]]] = {
        name: (device.description, _device_config(name, device, options)) for name, device in devices.items()
    }
    robotic, layout.left_out = robotic_modules(options, devices)
    for name, (header, config, fragments) in robotic.items():
        modules[name] = (header, config)
        layout.files.update(fragments)
    if "watchdog" in robotic:
        # The dead-man's switch: what the watchdog secures closes and parks by itself when the
        # watchdog's heartbeat stops (docs/operations.md), so a frozen watchdog cannot leave it open.
        watchdog = robotic["watchdog"][1]
        for secured in (watchdog["roof"], watchdog["telescope"]):
            modules[secured][1]["watchdog"] = "watchdog"
    # People always get a password (the console's logins); modules only where they log in (XMPP).
    accounts = [*modules, *PEOPLE] if _xmpp(options) else list(PEOPLE)
    passwords = {name: password_for(name) for name in accounts}
    if "console" in modules:
        layout.files[f"{SECRETS}/console-accounts.yaml"] = _console_accounts(passwords)
    for name, (header, config) in modules.items():
        if _xmpp(options):
            config = {**config, "comm": _module_comm(name, options)}
        layout.files[f"{name}.yaml"] = module_text(header, config)
        layout.modules.append(name)
    if _xmpp(options):
        layout.files["comm.yaml"] = _comm(options)
        layout.files[POLICY] = _policy(list(modules))
        for person in PEOPLE:
            layout.files[f"{person}.yaml"] = module_text(
                f"The comm of the person '{person}' for `nightcrew modules|call|events|shell --comm "
                f"{person}.yaml`, or export NIGHTCREW_COMM={person}.yaml. Not a module.",
                _module_comm(person, options),
            )
    for name, password in passwords.items():
        where = f"the XMPP account {name}@{options.domain}" if _xmpp(options) else "the web console"
        layout.files[f"{SECRETS}/{name}.password"] = module_text(
            f"The password of '{name}' for {where} (random; mode 0600).", password
        )
    return layout


def _xmpp(options: InitOptions) -> bool:
    return options.comm == "xmpp"


def _site(options: InitOptions) -> str:
    body: dict[str, Any] = {
        "latitude": options.latitude,
        "longitude": options.longitude,
        "elevation": options.elevation,
    }
    if options.site_name:
        body["name"] = options.site_name
    return module_text(
        "Where the observatory stands (degrees north and east, metres). Not a module: a fragment the "
        "modules needing it include with `site: !include shared/site.yaml` (in shared/, so that "
        "*.yaml are the module files).\n"
        f"Local time zone: {options.timezone} (nightcrew itself works in UTC; logs and FITS headers "
        "are UTC).",
        body,
    )


def _module_comm(name: str, options: InitOptions) -> dict[str, Any]:
    return {
        MERGE: Include("comm.yaml"),
        "jid": f"{name}@{options.domain}",
        "password": Include(f"{SECRETS}/{name}.password"),
    }


def _comm(options: InitOptions) -> str:
    return module_text(
        "How every module reaches the XMPP server (not a module: each module file merges it under "
        "`comm:` and adds its own account). The accounts are registered by `nightcrew server init "
        "xmpp *.yaml`, run in this directory (docs/observatory.md); it also writes the certificate.",
        {
            "class": "nightcrew.comm.xmpp.XmppComm",
            "server": options.xmpp_server,
            "room": options.room,
            "ca_file": options.certificate,
            "policy": POLICY,
            "audit": "audit.jsonl",
        },
    )


def _policy(modules: list[str]) -> str:
    body = starting_policy(modules, {"operator": "operator", "observer": "observer"})
    return module_text(
        "The access policy every module's comm names (docs/security.md): the observatory's modules may "
        "call each other, the operator everything, the observer only what reads. Weather verdicts and "
        "safety alarms are trusted only from the safety modules. YAML, named *.policy so that "
        "`nightcrew check` and `nightcrew up` do not take it for a module file.",
        body,
    )


def _console_accounts(passwords: dict[str, str]) -> str:
    from nightcrew.security import hash_password

    body = {
        person: {"password_hash": hash_password(passwords[person]), "role": role}
        for person, role in (("operator", "operator"), ("observer", "viewer"))
    }
    return module_text(
        "The web console's logins (hashes only). The passwords are those in secrets/operator.password and "
        "secrets/observer.password.",
        body,
    )


def _device_config(name: str, device: FoundDevice, options: InitOptions) -> dict[str, Any]:
    config = dict(device.config)
    role = device.role
    if role == "telescope":
        config.update(site=Include("shared/site.yaml"), min_altitude=options.horizon, park_on_close=True)
    elif role == "camera":
        config.update(
            site=Include("shared/site.yaml"),
            vfs=images_vfs(options),
            filename_pattern="/images/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits",
        )
    elif role in ("roof", "dome"):
        config["park_on_close"] = True
        if role == "dome":
            config["follow"] = "telescope"
    elif role == "focuser" and "device" in config:
        config["steps_per_mm"] = 1000.0
    return config
