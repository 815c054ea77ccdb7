"""The access policy: roles for accounts, rights for roles, safety methods for safety roles.

A policy file::

    roles:
      observer: ["*.get_*", "*.is_*"]   # module.method patterns or interface names (ICamera)
      operator: ["*"]
      safety: []
    accounts:                                      # account (module or person) -> roles
      alice: [observer]
      mastermind: [operator]
      weather: [safety]
    safety_roles: [safety, observer]               # may always call the safety methods
    safety_methods: [roof.close_roof, telescope.park, "*.stop_motion"]   # this is the default
    events:                                        # event -> roles whose members may send it
      BadWeatherEvent: [safety]
      GoodWeatherEvent: [safety]
      SafetyAlarmEvent: [safety]
      SafetyClearedEvent: [safety]
    header_providers: [devices]                    # roles whose modules may give FITS headers

Rights that are not calls are events a role may send: who may submit rapid-response requests
that pre-empt the running task is who may send ``RapidResponseEvent`` (listed under ``events``
like the other events that move hardware; the starting policy gives it to ``modules`` and
``operator``).

A right with a dot is a shell-style pattern over ``module.method``; one without a dot is an
interface name (all its methods on any module), ``*`` is everything. An account not listed, or
listed without roles, may call nothing. Events named under ``events`` are accepted only from
accounts holding one of the roles given; other events from anyone, except the events that move
hardware (weather verdicts, safety alarms: ``nightcrew.events.hardware_event_names()``), which
are trusted from nobody unless named here. With ``header_providers``,
a camera takes FITS header cards only from accounts holding one of those roles.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from fnmatch import fnmatchcase
from typing import Any

from nightcrew.config import load_data_file
from nightcrew.errors import ConfigError
from nightcrew.events import RapidResponseEvent, hardware_event_names
from nightcrew.security._audit import GETTER_PREFIXES

__all__ = [
    "DEFAULT_SAFETY_METHODS",
    "OPEN_POLICY",
    "Policy",
    "closed_policy",
    "load_policy",
    "parse_policy",
    "starting_policy",
]

#: Methods the safety roles may always call (close and park: failing safe must never be refused).
DEFAULT_SAFETY_METHODS = ("roof.close_roof", "telescope.park", "*.stop_motion", "*.close_roof", "*.park")
_KEYS = ("roles", "accounts", "safety_roles", "safety_methods", "events", "header_providers")


@dataclass(frozen=True)
class Policy:
    """Rights of accounts; :meth:`allows` answers one call."""

    roles: Mapping[str, tuple[str, ...]]
    accounts: Mapping[str, tuple[str, ...]]
    safety_roles: frozenset[str] = frozenset()
    safety_methods: tuple[str, ...] = DEFAULT_SAFETY_METHODS
    events: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    header_providers: tuple[str, ...] | None = None
    source: str = field(default="", compare=False)
    #: Roles every caller holds besides its own (the closed default lets everyone read).
    everyone: tuple[str, ...] = ()

    def allows(self, caller: str, module: str, method: str, interface: str | None) -> bool:
        """Whether account ``caller`` may call ``method`` (of ``interface``) on ``module``."""
        roles = self.roles_of(caller)
        target = f"{module}.{method}"
        if any(role in self.safety_roles for role in roles) and any(
            fnmatchcase(target, pattern) for pattern in self.safety_methods
        ):
            return True
        for role in roles:
            for right in self.roles.get(role, ()):
                if right == "*" or ("." in right and fnmatchcase(target, right)):
                    return True
                if "." not in right and interface is not None and fnmatchcase(interface, right):
                    return True
        return False

    def accepts_event(self, sender: str, event: str, *, moves_hardware: bool = False) -> bool:
        """Whether an event called ``event`` is trusted from account ``sender``.

        An event that moves hardware (``Event.moves_hardware``) is trusted only from the roles
        named for it under ``events``; one the policy does not name, from nobody.
        """
        senders = self.events.get(event)
        if senders is None:
            return not moves_hardware
        return any(role in senders for role in self.accounts.get(sender, ()))

    def accepts_headers(self, provider: str) -> bool:
        """Whether FITS header cards from account ``provider`` may go into a frame."""
        roles = self.header_providers
        return roles is None or any(role in roles for role in self.accounts.get(provider, ()))

    def roles_of(self, caller: str) -> tuple[str, ...]:
        return self.accounts.get(caller, ()) + self.everyone


# --- the call side's defaults: closed unless a policy opens it ---------------------------------------

#: ``policy: open`` in a comm: every caller may call everything (a network comm warns at every start).
OPEN_POLICY = "open"


def closed_policy() -> Policy:
    """What a module on a network transport enforces without a policy: every account may call the
    getters (``get_*``, ``is_*``, ``list_*``, ``has_*``), nobody anything that changes state."""
    reads = tuple(f"*.{prefix}*" for prefix in GETTER_PREFIXES)
    return Policy(roles={"reader": reads}, accounts={}, everyone=("reader",), source="(no policy: closed)")


def starting_policy(modules: list[str], people: Mapping[str, str]) -> dict[str, Any]:
    """The policy (plain data, for a YAML file) that ``nightcrew init`` and ``nightcrew server init``
    write: the observatory's ``modules`` may call each other, a person (name → ``operator`` or
    ``observer``) everything or only what reads. Safety events come only from the safety modules
    (weather, watchdog and safety, where present); rapid-response requests that pre-empt from modules
    and operators; focus results and FITS header cards only from modules."""
    safety = [name for name in ("weather", "safety", "watchdog") if name in modules]
    accounts: dict[str, list[str]] = {
        name: ["modules", "safety"] if name in safety else ["modules"] for name in modules
    }
    accounts.update({person: [role] for person, role in people.items()})
    if "console" in modules:
        accounts.update(
            {"console": ["observer"], "console:viewer": ["observer"], "console:operator": ["operator"]}
        )
    return {
        "roles": {
            "operator": ["*"],
            # What reads, and nothing else: not IModule whole, whose reset_error and
            # set_config_value change state (its getters are among these).
            "observer": [f"*.{prefix}*" for prefix in GETTER_PREFIXES],
            "modules": ["*"],
            "safety": [],
        },
        "accounts": accounts,
        "safety_roles": ["safety"],
        # Every event class marked as moving hardware, so that a new one is not forgotten; the
        # right to submit rapid-response requests (which pre-empt a running task) goes to the
        # observatory's modules (e.g. the alerts listener) and the operators; and a focus series'
        # result, which the focus model learns from and then sets the focuser by (no safety matter,
        # so not marked: from any module, but a person cannot forge it).
        "events": {
            **{
                name: ["modules", "operator"] if name == RapidResponseEvent.event_name() else ["safety"]
                for name in hardware_event_names()
            },
            "FocusFoundEvent": ["modules"],
        },
        "header_providers": ["modules"],
    }


def load_policy(path: str | os.PathLike[str]) -> Policy:
    """The policy in the YAML file ``path``; ConfigError naming file and key for any problem."""
    name = os.fspath(path)
    return parse_policy(load_data_file(path), name)


def parse_policy(data: Any, source: str = "") -> Policy:
    """A policy from plain data (as read from its file)."""
    if not isinstance(data, Mapping):
        raise ConfigError("a policy is a mapping with 'roles' and 'accounts'", file=source or None)
    for key in data:
        if key not in _KEYS:
            raise ConfigError(f"unknown key (one of {', '.join(_KEYS)})", file=source or None, key=str(key))
    roles = {
        name: _words(rights, source, f"roles.{name}")
        for name, rights in _mapping(data, "roles", source).items()
    }
    accounts = {}
    for account, given in _mapping(data, "accounts", source).items():
        names = _words(given, source, f"accounts.{account}")
        unknown = [role for role in names if role not in roles]
        if unknown:
            raise ConfigError(f"unknown role '{unknown[0]}'", file=source or None, key=f"accounts.{account}")
        accounts[str(account)] = names
    safety_roles = _words(data.get("safety_roles", []), source, "safety_roles")
    for role in safety_roles:
        if role not in roles:
            raise ConfigError(f"unknown role '{role}'", file=source or None, key="safety_roles")
    methods = data.get("safety_methods")
    safety_methods = DEFAULT_SAFETY_METHODS if methods is None else _words(methods, source, "safety_methods")
    events = {
        str(name): _words(given, source, f"events.{name}")
        for name, given in _mapping(data, "events", source).items()
    }
    for name, given in events.items():
        unknown = [role for role in given if role not in roles]
        if unknown:
            raise ConfigError(f"unknown role '{unknown[0]}'", file=source or None, key=f"events.{name}")
    providers = data.get("header_providers")
    header_providers = None if providers is None else _words(providers, source, "header_providers")
    for role in header_providers or ():
        if role not in roles:
            raise ConfigError(f"unknown role '{role}'", file=source or None, key="header_providers")
    return Policy(roles, accounts, frozenset(safety_roles), safety_methods, events, header_providers, source)


def _mapping(data: Mapping[str, Any], key: str, source: str) -> Mapping[str, Any]:
    value = data.get(key, {})
    if not isinstance(value, Mapping):
        raise ConfigError("expected a mapping", file=source or None, key=key)
    return value


def _words(value: Any, source: str, key: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(item, str) and item for item in value):
        raise ConfigError("expected a list of names or patterns", file=source or None, key=key)
    return tuple(value)
