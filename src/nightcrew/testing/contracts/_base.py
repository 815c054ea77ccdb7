"""What every contract suite shares: the setup a subclass provides, the probe, interrupt windows."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable, Coroutine
from dataclasses import dataclass
from typing import Any, ClassVar, Generic, TypeVar

import pytest

from nightcrew.clock import Clock
from nightcrew.comm.rpc import RpcServer
from nightcrew.errors import AbortedError
from nightcrew.events import (
    BadWeatherEvent,
    Event,
    ExposureStatusChangedEvent,
    FilterChangedEvent,
    GoodWeatherEvent,
    MotionStatusChangedEvent,
    MoveAltAzEvent,
    MoveRaDecEvent,
    NewImageEvent,
    OffsetsAltAzEvent,
    OffsetsRaDecEvent,
    RoofClosedEvent,
    RoofClosingEvent,
    RoofOpenedEvent,
)
from nightcrew.interfaces import (
    FitsCard,
    IFitsHeaderAfter,
    IFitsHeaderBefore,
    Interface,
    ModuleState,
    MotionStatus,
)
from nightcrew.modules import Module
from nightcrew.testing.recording import EventRecorder
from nightcrew.testing.waiting import Condition, wait_for
from nightcrew.timeout import DEFAULT_TIMEOUT

__all__ = ["ContractProbe", "ContractSetup", "DeviceContract", "timed_call"]

M = TypeVar("M", bound=Module)
IT = TypeVar("IT", bound=Interface)
T = TypeVar("T")
E = TypeVar("E", bound=Event)

#: Every event a contract suite looks at.
CONTRACT_EVENTS: list[type[Event]] = [
    MotionStatusChangedEvent,
    MoveRaDecEvent,
    MoveAltAzEvent,
    OffsetsRaDecEvent,
    OffsetsAltAzEvent,
    FilterChangedEvent,
    NewImageEvent,
    ExposureStatusChangedEvent,
    RoofOpenedEvent,
    RoofClosingEvent,
    RoofClosedEvent,
]

#: The cards the probe gives a camera before and after each exposure.
PROBE_CARDS_BEFORE: dict[str, FitsCard] = {"PROBEBEF": ("before", "Contract suite probe, before exposure")}
PROBE_CARDS_AFTER: dict[str, FitsCard] = {"PROBEAFT": ("after", "Contract suite probe, after exposure")}


class ContractProbe(EventRecorder, IFitsHeaderBefore, IFitsHeaderAfter):
    """The other module on the device's network: records events, calls through proxies, gives
    FITS cards (:data:`PROBE_CARDS_BEFORE` / ``_AFTER``) and sends weather events.

    Start it on the same network as the device, before the device (so it hears everything).
    """

    def __init__(self, **kwargs: Any) -> None:
        kwargs.setdefault("types", CONTRACT_EVENTS)
        super().__init__(**kwargs)

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return dict(PROBE_CARDS_BEFORE)

    async def get_fits_header_after(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return dict(PROBE_CARDS_AFTER)

    async def send_bad_weather(self, reason: str = "contract suite") -> None:
        await self.comm.send_event(BadWeatherEvent(reason=reason))

    async def send_good_weather(self) -> None:
        await self.comm.send_event(GoodWeatherEvent())


@dataclass
class ContractSetup(Generic[M]):
    """What a suite's ``contract`` fixture yields: the started device module and the probe.

    Attributes:
        module: The device module under test, started (READY).
        probe: A started :class:`ContractProbe` on the same network.
    """

    module: M
    probe: ContractProbe

    @property
    def clock(self) -> Clock:
        """The device module's clock: every timeout of the suites is in its seconds."""
        return self.module.clock

    @property
    def name(self) -> str:
        return self.module.name

    async def proxy(self, interface: type[IT]) -> IT:
        """The device as another module sees it (calls go through the comm, errors keep their class)."""
        return await self.probe.comm.proxy(self.module.name, interface)

    async def wait_for(self, condition: Condition, clock_seconds: float, message: str = "") -> float:
        """:func:`~nightcrew.testing.wait_for` on the device's clock."""
        return await wait_for(
            condition, clock_seconds, clock=self.clock, message=message or "condition not met"
        )

    def events(self, event_type: type[E]) -> list[E]:
        """Events of ``event_type`` the probe heard from the device."""
        return self.probe.of(event_type, sender=self.module.name)

    def statuses(self) -> list[MotionStatus]:
        """Motion statuses the device announced (MotionStatusChangedEvent), oldest first."""
        return [e.status for e in self.probe.of(MotionStatusChangedEvent, sender=self.module.name)]


async def timed_call(setup: ContractSetup[Any], method: str, *args: Any) -> tuple[float, float]:
    """Serve one call of ``method`` as the comm does (:class:`~nightcrew.comm.rpc.RpcServer`) and
    return (the timeout it announced — the default if none —, the clock seconds it took)."""
    announced: list[float] = []
    server = RpcServer(setup.module)
    start = setup.clock.time()
    await server.handle(method, list(args), announced.append)
    took = setup.clock.time() - start
    return (announced[-1] if announced else DEFAULT_TIMEOUT), took


class DeviceContract:
    """Base of the contract suites: the ``contract`` fixture a subclass must provide, and shared
    parameters and steps. Tests of a suite are collected only in a subclass named ``Test*``.
    """

    #: The interface the device must offer.
    interface: ClassVar[type[Interface]] = Interface
    #: Clock seconds any single motion, exposure, event or status change may take in the suite.
    timeout: ClassVar[float] = 300.0

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        """Override in the subclass: yield a :class:`ContractSetup` with the started device."""
        yield self._no_setup()

    def _no_setup(self) -> ContractSetup[Any]:
        raise NotImplementedError(
            f"{type(self).__name__} must override the 'contract' fixture: an async fixture yielding "
            "ContractSetup(module, probe) with the device module started (see nightcrew.testing)"
        )

    # --- shared tests --------------------------------------------------------------------------

    async def test_the_device_is_ready_and_offers_the_interface(self, contract: ContractSetup[Any]) -> None:
        assert contract.module.state is ModuleState.READY
        assert isinstance(contract.module, self.interface), (
            f"{contract.name} offers no {self.interface.__name__}"
        )
        assert isinstance(await contract.proxy(self.interface), self.interface)

    # --- steps for the suites ------------------------------------------------------------------

    async def _start_interruptible(
        self,
        contract: ContractSetup[Any],
        call: Callable[[], Coroutine[Any, Any, T]],
        busy: Callable[[], Awaitable[bool]],
        what: str,
    ) -> asyncio.Task[T]:
        """Start ``call()`` and return its task once ``busy()`` says it runs.

        Fails (not skips) when the call ends first: the suite's long motion was too short for
        this device; raise the suite's parameter for it.
        """
        task = asyncio.ensure_future(call())

        async def running_or_done() -> bool:
            return task.done() or await busy()

        await contract.wait_for(running_or_done, self.timeout, f"{contract.name} never began {what}")
        if task.done():
            task.result()  # its own error first, if it failed
            pytest.fail(f"{contract.name} finished {what} before it could be interrupted: make it longer")
        return task

    async def _expect_aborted(self, task: asyncio.Task[Any]) -> None:
        """The interrupted call ended with AbortedError (its motion was stopped by someone else)."""
        with pytest.raises(AbortedError):
            await task
