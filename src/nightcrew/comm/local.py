"""The in-process comm: modules sharing one Python process talk through a :class:`LocalNetwork`.

It is the default when no ``comm:`` is configured. It keeps the network's contract exactly:
arguments, results and events are encoded to wire values and decoded by the receiver's type
hints, so nothing works here that would fail over XMPP. Calls run inline in the caller's task (no
queue, no thread), which makes an in-process call cost microseconds.
"""

from __future__ import annotations

from typing import Any, Literal

from nightcrew.comm.base import Comm, PendingCall
from nightcrew.comm.rpc import fault_from_exception
from nightcrew.config import DataPath, InputPath
from nightcrew.errors import ConfigError, RemoteError
from nightcrew.security import Policy

__all__ = ["LocalComm", "LocalNetwork"]


class LocalNetwork:
    """The set of LocalComms that can reach each other (one per process by default).

    Args:
        rpc_grace: Wall seconds every call on this network may take beyond its timeout. Zero by
            default; a simulation on a fast clock wants some, because the CPU time of rendering
            and analysing frames does not shrink with the clock (a 10-s timeout is 31 ms of wall
            time at 320x), as XmppComm allows for the network.
    """

    _default: LocalNetwork | None = None

    def __init__(self, *, rpc_grace: float = 0.0) -> None:
        if not rpc_grace >= 0:
            raise ConfigError(f"must be >= 0 wall seconds, got {rpc_grace}", key="rpc_grace")
        self.rpc_grace = float(rpc_grace)
        self._comms: dict[str, LocalComm] = {}
        # Subscribers in the order they subscribed (a dict, not a set: a set of names is ordered by
        # their hashes, which change from run to run, and the order of delivery must not)
        self._subscribers: dict[str, dict[str, None]] = {}

    @classmethod
    def default(cls) -> LocalNetwork:
        """The process-wide network."""
        if cls._default is None:
            cls._default = cls()
        return cls._default

    @property
    def names(self) -> list[str]:
        return list(self._comms)

    def join(self, comm: LocalComm) -> None:
        if comm.name in self._comms:
            raise ConfigError(f"a module named '{comm.name}' is already running in this process")
        self._comms[comm.name] = comm
        for other in list(self._comms.values()):
            if other is not comm:
                other._client_online(comm.name)

    def leave(self, comm: LocalComm) -> None:
        if self._comms.get(comm.name) is not comm:
            return
        del self._comms[comm.name]
        for subscribers in self._subscribers.values():
            subscribers.pop(comm.name, None)
        for other in list(self._comms.values()):
            other._client_offline(comm.name)

    def get(self, name: str) -> LocalComm:
        comm = self._comms.get(name)
        if comm is None:
            raise RemoteError(f"module '{name}' is not online")
        return comm

    def subscribe(self, name: str, event: str) -> None:
        self._subscribers.setdefault(event, {})[name] = None

    def publish(self, sender: str, event: str, payload: dict[str, Any], acting: str | None = None) -> None:
        for name in self._subscribers.get(event, ()):
            receiver = self._comms.get(name)
            if receiver is not None and name != sender:
                receiver._deliver_event(event, payload, sender, acting)


class LocalComm(Comm):
    """Comm for modules in one process.

    Args:
        name: Module name, unique in the network (and its account in the access policy).
        network: The network to join; the process-wide one by default.
        policy: The access policy file (see :class:`~nightcrew.comm.base.Comm`).
        audit: The audit trail file (see :class:`~nightcrew.comm.base.Comm`).
    """

    def __init__(
        self,
        name: str,
        *,
        network: LocalNetwork | None = None,
        policy: InputPath | Literal["open"] | Policy | None = None,
        audit: DataPath | None = None,
    ) -> None:
        self._network = network or LocalNetwork.default()
        super().__init__(rpc_grace=self._network.rpc_grace, policy=policy, audit=audit)
        if not name:
            raise ConfigError("a LocalComm needs a module name")
        self._name = name

    @property
    def name(self) -> str:
        return self._name

    @property
    def clients(self) -> list[str]:
        return [n for n in self._network.names if n != self._name]

    async def _open_transport(self) -> None:
        self._network.join(self)

    async def _close_transport(self) -> None:
        self._network.leave(self)

    async def _fetch_interface_names(self, client: str) -> list[str]:
        return self._network.get(client).served_interfaces_for(self._name)

    async def _send_call(self, client: str, method: str, args: list[Any], call: PendingCall) -> None:
        callee = self._network.get(client)
        try:
            result = await callee._serve_call(method, args, call.announce, self._name, call.acting_as)
        except Exception as exc:
            call.set_fault(fault_from_exception(exc))
        else:
            call.set_result(result)

    async def _publish_event(self, name: str, payload: dict[str, Any], acting: str | None = None) -> None:
        self._network.publish(self._name, name, payload, acting)

    async def _subscribe_events(self, name: str) -> None:
        self._network.subscribe(self._name, name)
