"""pyobs-core modules for tests/comm/test_pyobs_interop.py; they run in pyobs' own venv.

Started by pyobs' runner (``pyobs config.yaml``) with this directory on PYTHONPATH; written
against pyobs-core 2.19's public API (Module, Interface, events, proxies, ``timeout``).

* ``PyCamera`` offers pyobs' own ``IData``: ``grab_data`` returns a made-up path and sends
  pyobs' ``NewImageEvent``; ``IReducer.reduce`` sends a ``NewImageEvent`` with pyobs' ``raw`` field,
  which nightcrew's event lacks.
* ``Shooter`` offers ``IInteropShooter``, an interface nightcrew's test declares under the same name:
  it calls a nightcrew module's ``IData.grab_data`` and waits for that module's ``NewImageEvent``;
  ``add_remote`` calls a nightcrew ``ICalculator.add``, with arguments as given or as a
  dataclass nightcrew cannot take for a number; ``call_remote`` calls any method without arguments;
  ``headers`` reads a module's FITS cards the way pyobs' cameras do (``entry.value``, ``.comment``);
  ``states`` reads a filter wheel's IFilters and IMotion states as pyobs' GUIs do (subscribe_state).
"""

from __future__ import annotations

import asyncio
import dataclasses
from abc import ABCMeta, abstractmethod
from typing import Any

from pyobs.events import NewImageEvent  # type: ignore[import-not-found]
from pyobs.interfaces import (  # type: ignore[import-not-found]
    IData,
    IFilters,
    IFitsHeaderBefore,
    IMotion,
    Interface,
)
from pyobs.modules import Module, timeout  # type: ignore[import-not-found]
from pyobs.utils.enums import ImageType  # type: ignore[import-not-found]


class IInteropShooter(Interface, metaclass=ABCMeta):  # type: ignore[misc]
    @abstractmethod
    async def shoot(self, camera: str, broadcast: bool, **kwargs: Any) -> list[str]: ...

    @abstractmethod
    async def add_remote(self, module: str, a: float, b: float, as_dataclass: bool, **kwargs: Any) -> str: ...

    @abstractmethod
    async def call_remote(self, module: str, method: str, **kwargs: Any) -> str: ...

    @abstractmethod
    async def headers(self, module: str, **kwargs: Any) -> list[str]: ...

    @abstractmethod
    async def states(self, module: str, **kwargs: Any) -> list[str]: ...


class ICalculator(Interface, metaclass=ABCMeta):  # type: ignore[misc]
    @abstractmethod
    async def add(self, a: float, b: float, **kwargs: Any) -> float: ...


@dataclasses.dataclass
class Pair:
    a: float
    b: float


class IReducer(Interface, metaclass=ABCMeta):  # type: ignore[misc]
    @abstractmethod
    async def reduce(self, filename: str, **kwargs: Any) -> None: ...


class PyCamera(Module, IData, IReducer):  # type: ignore[misc]
    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._count = 0

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(NewImageEvent)  # declared as sent: peers subscribe

    async def grab_data(self, broadcast: bool = True, **kwargs: Any) -> str:
        self._count += 1
        filename = f"/pyobs/images/frame-{self._count:04d}.fits"
        if broadcast:
            await self.comm.send_event(NewImageEvent(filename, ImageType.OBJECT))
        return filename

    async def reduce(self, filename: str, **kwargs: Any) -> None:
        await self.comm.send_event(NewImageEvent(f"{filename}.reduced", ImageType.OBJECT, raw=filename))


class Shooter(Module, IInteropShooter):  # type: ignore[misc]
    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._images: asyncio.Queue[tuple[str, str]] = asyncio.Queue()

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(NewImageEvent, self._on_new_image)

    async def _on_new_image(self, event: NewImageEvent, sender: str, **kwargs: Any) -> bool:
        await self._images.put((sender, event.filename))
        return True

    @timeout(30)  # type: ignore[untyped-decorator]  # announced: longer than the default 10 s
    async def shoot(self, camera: str, broadcast: bool, **kwargs: Any) -> list[str]:
        async with self.proxy(camera, IData) as remote:
            filename = await remote.grab_data(broadcast)
        sender, heard = await asyncio.wait_for(self._image_from(camera), 20)
        return [filename, heard, sender]

    async def _image_from(self, camera: str) -> tuple[str, str]:
        while True:  # other modules' images (pyobs' own camera) may be queued before
            sender, heard = await self._images.get()
            if sender == camera:
                return sender, heard

    async def add_remote(self, module: str, a: float, b: float, as_dataclass: bool, **kwargs: Any) -> str:
        try:
            if as_dataclass:
                annotation = {"a": Pair, "b": float, "return": float}
                result = await self.comm.execute(module, "add", annotation, Pair(a, b), b)
            else:
                async with self.proxy(module, ICalculator) as calculator:
                    result = await calculator.add(a, b)
        except Exception as exc:
            return f"{type(exc).__name__}: {getattr(exc, 'message', exc)}"
        return f"{type(result).__name__} {result!r}"

    async def call_remote(self, module: str, method: str, **kwargs: Any) -> str:
        try:
            result = await self.comm.execute(module, method, {"return": Any})
        except Exception as exc:
            return f"{type(exc).__name__}: {getattr(exc, 'message', exc)}"
        return f"{type(result).__name__} {result!r}"

    async def headers(self, module: str, **kwargs: Any) -> list[str]:
        async with self.proxy(module, IFitsHeaderBefore) as provider:
            cards = await provider.get_fits_header_before()
        return [f"{key}={entry.value!r}/{entry.comment}" for key, entry in cards.items()]

    @timeout(30)  # type: ignore[untyped-decorator]
    async def states(self, module: str, **kwargs: Any) -> list[str]:
        got: dict[str, Any] = {}
        both = asyncio.Event()

        def keep(name: str) -> Any:
            def callback(state: Any) -> None:
                got[name] = state
                if len(got) == 2:
                    both.set()

            return callback

        await self.comm.subscribe_state(module, IFilters, keep("filter"))
        await self.comm.subscribe_state(module, IMotion, keep("motion"))
        await asyncio.wait_for(both.wait(), 20)
        return [str(got["filter"].filter), str(got["motion"].status)]
