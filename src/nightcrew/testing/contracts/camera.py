"""The camera contract: settings, exposures, files, events, refusals, abort and stop of an ICamera module."""

from __future__ import annotations

from typing import Any, ClassVar

import pytest

from nightcrew.errors import DeviceBusyError, InvalidArgumentError, NotSupportedError
from nightcrew.events import ExposureStatusChangedEvent, NewImageEvent
from nightcrew.interfaces import (
    Binning,
    ExposureStatus,
    IBinning,
    ICamera,
    ICooling,
    IExposureTime,
    IImageType,
    ImageType,
    IStoppableExposure,
    IWindow,
    Window,
)
from nightcrew.testing.contracts._base import (
    PROBE_CARDS_AFTER,
    PROBE_CARDS_BEFORE,
    ContractSetup,
    DeviceContract,
    timed_call,
)
from nightcrew.timeout import DEFAULT_TIMEOUT

__all__ = ["CameraContract"]

#: Cards every camera writes into every file.
REQUIRED_CARDS = (
    "DATE-OBS",
    "MJD-OBS",
    "EXPTIME",
    "IMAGETYP",
    "XBINNING",
    "YBINNING",
    "XORGSUBF",
    "YORGSUBF",
)


class CameraContract(DeviceContract):
    """Contract of an :class:`~nightcrew.interfaces.ICamera` module with exposure time, image
    type, binning and window (see :mod:`nightcrew.testing`).

    Files are read back through the module's own VFS. Frames use a window of 1/:attr:`window_divisor`
    of the chip in each direction, at the largest binning the camera lists, to keep readouts short.
    """

    interface = ICamera
    #: Seconds of the exposures that run to the end.
    exposure_time: ClassVar[float] = 0.5
    #: Seconds of the exposures the suite interrupts (busy, abort); long enough to catch them.
    long_exposure_time: ClassVar[float] = 60.0
    #: The window's width and height are the chip's divided by this.
    window_divisor: ClassVar[int] = 4
    #: Whether the camera has a cooler (ICooling works); one without must refuse with NotSupportedError.
    cooled: ClassVar[bool] = False
    #: °C the cooling case asks for (within any cooler's reach).
    cooling_setpoint: ClassVar[float] = 5.0

    # --- steps ---------------------------------------------------------------------------------

    async def _small_frame(self, contract: ContractSetup[Any]) -> tuple[Binning, Window]:
        """Set the largest listed binning and a centred window; return them."""
        binning_api = await contract.proxy(IBinning)
        window_api = await contract.proxy(IWindow)
        binning = max(await binning_api.list_binnings(), key=lambda b: b.x * b.y)
        full = await window_api.get_full_frame()
        bx, by = binning.x, binning.y
        width = max(bx, full.width // self.window_divisor // bx * bx)
        height = max(by, full.height // self.window_divisor // by * by)
        left = full.left + (full.width - width) // 2 // bx * bx
        top = full.top + (full.height - height) // 2 // by * by
        window = Window(left, top, width, height)
        await binning_api.set_binning(bx, by)
        await window_api.set_window(window.left, window.top, window.width, window.height)
        return binning, window

    async def _exposing(self, contract: ContractSetup[Any]) -> bool:
        return await (await contract.proxy(ICamera)).get_exposure_status() is ExposureStatus.EXPOSING

    async def _start_long_exposure(self, contract: ContractSetup[Any]) -> Any:
        camera = await contract.proxy(ICamera)
        await (await contract.proxy(IExposureTime)).set_exposure_time(self.long_exposure_time)
        return await self._start_interruptible(
            contract, lambda: camera.grab_data(), lambda: self._exposing(contract), "a long exposure"
        )

    async def _new_images(self, contract: ContractSetup[Any]) -> list[NewImageEvent]:
        return list(contract.events(NewImageEvent))

    # --- tests ---------------------------------------------------------------------------------

    async def test_settings_read_back_as_set(self, contract: ContractSetup[Any]) -> None:
        exposure = await contract.proxy(IExposureTime)
        await exposure.set_exposure_time(self.exposure_time)
        assert await exposure.get_exposure_time() == pytest.approx(self.exposure_time)
        image_type = await contract.proxy(IImageType)
        await image_type.set_image_type(ImageType.DARK)
        assert await image_type.get_image_type() is ImageType.DARK
        binning_api = await contract.proxy(IBinning)
        binnings = await binning_api.list_binnings()
        assert binnings, f"{contract.name} lists no binning"
        for binning in binnings:
            await binning_api.set_binning(binning.x, binning.y)
            assert await binning_api.get_binning() == binning
        binning, window = await self._small_frame(contract)
        assert await binning_api.get_binning() == binning
        assert await (await contract.proxy(IWindow)).get_window() == window

    async def test_bad_settings_are_refused_and_change_nothing(self, contract: ContractSetup[Any]) -> None:
        exposure = await contract.proxy(IExposureTime)
        await exposure.set_exposure_time(self.exposure_time)
        with pytest.raises(InvalidArgumentError):
            await exposure.set_exposure_time(-1.0)
        assert await exposure.get_exposure_time() == pytest.approx(self.exposure_time)
        binning_api = await contract.proxy(IBinning)
        window_api = await contract.proxy(IWindow)
        binning, window = await self._small_frame(contract)
        with pytest.raises(InvalidArgumentError):
            await binning_api.set_binning(999, 999)
        full = await window_api.get_full_frame()
        with pytest.raises(InvalidArgumentError):
            await window_api.set_window(full.left, full.top, full.width + 16, full.height)
        with pytest.raises(InvalidArgumentError):
            await window_api.set_window(full.left, full.top, 0, full.height)
        assert await binning_api.get_binning() == binning
        assert await window_api.get_window() == window
        if isinstance(contract.module, ICooling):
            with pytest.raises(InvalidArgumentError):
                await (await contract.proxy(ICooling)).set_cooling(True, -300.0)

    async def test_cooling_switches_and_its_cards_reach_the_frames(
        self, contract: ContractSetup[Any]
    ) -> None:
        cooling = await contract.proxy(ICooling)
        if not self.cooled:
            with pytest.raises(NotSupportedError):
                await cooling.set_cooling(True, self.cooling_setpoint)
            return
        await cooling.set_cooling(True, self.cooling_setpoint)
        try:
            status = await cooling.get_cooling()
            assert status.enabled and status.setpoint == pytest.approx(self.cooling_setpoint)
            assert 0.0 <= status.power <= 100.0
            assert status.temperature is None or -100.0 <= status.temperature <= 60.0
            await (await contract.proxy(IExposureTime)).set_exposure_time(self.exposure_time)
            await self._small_frame(contract)
            header = (await contract.module.vfs.read_fits(await self._dark(contract)))[0].header
            assert header["SET-TEMP"] == pytest.approx(self.cooling_setpoint)
            assert 0.0 <= header["COOLPOW"] <= 100.0
            if status.temperature is not None:
                assert isinstance(header["CCD-TEMP"], float) and isinstance(header["TEMP-OK"], bool)
        finally:
            await cooling.set_cooling(False, self.cooling_setpoint)
        status = await cooling.get_cooling()
        assert not status.enabled and status.power == 0.0
        assert "SET-TEMP" not in (await contract.module.vfs.read_fits(await self._dark(contract)))[0].header

    async def _dark(self, contract: ContractSetup[Any]) -> str:
        return await (await contract.proxy(ICamera)).grab_data(False, ImageType.DARK)

    async def test_an_exposure_writes_a_fits_file_and_announces_it(
        self, contract: ContractSetup[Any]
    ) -> None:
        camera = await contract.proxy(ICamera)
        await (await contract.proxy(IExposureTime)).set_exposure_time(self.exposure_time)
        await (await contract.proxy(IImageType)).set_image_type(ImageType.OBJECT)
        binning, window = await self._small_frame(contract)
        filename = await camera.grab_data()
        assert await camera.get_exposure_status() is ExposureStatus.IDLE
        assert await camera.get_exposure_progress() == 0.0  # 0 when idle (IExposure)
        assert await (await contract.proxy(IExposureTime)).get_exposure_time_left() == 0.0
        hdu = (await contract.module.vfs.read_fits(filename))[0]
        assert hdu.data.shape == (window.height // binning.y, window.width // binning.x)
        header = hdu.header
        missing = [key for key in REQUIRED_CARDS if key not in header]
        assert not missing, f"{filename} lacks {', '.join(missing)}"
        assert header["EXPTIME"] == pytest.approx(self.exposure_time)
        assert header["IMAGETYP"] == ImageType.OBJECT.value
        assert (header["XBINNING"], header["YBINNING"]) == (binning.x, binning.y)
        # The header providers on the network were asked, before and after the exposure.
        for key, (value, _) in {**PROBE_CARDS_BEFORE, **PROBE_CARDS_AFTER}.items():
            assert header.get(key) == value, f"{filename}: card {key} of the header providers missing"
        event = await contract.probe.wait_for_event(NewImageEvent, self.timeout, sender=contract.name)
        assert event.filename == filename
        await contract.wait_for(
            lambda: (
                [e.current for e in contract.events(ExposureStatusChangedEvent)][-1:] == [ExposureStatus.IDLE]
                and ExposureStatus.EXPOSING
                in [e.current for e in contract.events(ExposureStatusChangedEvent)]
            ),
            self.timeout,
            "ExposureStatusChangedEvent EXPOSING, then IDLE",
        )

    async def test_the_image_type_of_one_call_goes_to_header_and_event(
        self, contract: ContractSetup[Any]
    ) -> None:
        camera = await contract.proxy(ICamera)
        await (await contract.proxy(IExposureTime)).set_exposure_time(self.exposure_time)
        await (await contract.proxy(IImageType)).set_image_type(ImageType.OBJECT)
        await self._small_frame(contract)
        filename = await camera.grab_data(image_type=ImageType.DARK)
        assert (await contract.module.vfs.read_fits(filename))[0].header["IMAGETYP"] == ImageType.DARK.value
        event = await contract.probe.wait_for_event(NewImageEvent, self.timeout, sender=contract.name)
        assert (event.filename, event.image_type) == (filename, ImageType.DARK)
        assert await (await contract.proxy(IImageType)).get_image_type() is ImageType.OBJECT

    async def test_without_broadcast_no_event_is_sent(self, contract: ContractSetup[Any]) -> None:
        camera = await contract.proxy(ICamera)
        await (await contract.proxy(IExposureTime)).set_exposure_time(self.exposure_time)
        await self._small_frame(contract)
        quiet = await camera.grab_data(broadcast=False)
        loud = await camera.grab_data()
        # Events from one sender arrive in order: once the second is here, the first would be too.
        await contract.probe.wait_for_event(NewImageEvent, self.timeout, sender=contract.name)
        assert [e.filename for e in await self._new_images(contract)] == [loud]
        assert await contract.module.vfs.exists(quiet)

    async def test_a_second_exposure_while_exposing_is_busy(self, contract: ContractSetup[Any]) -> None:
        camera = await contract.proxy(ICamera)
        await self._small_frame(contract)
        grab = await self._start_long_exposure(contract)
        progress = await camera.get_exposure_progress()
        assert 0.0 <= progress <= 100.0
        left = await (await contract.proxy(IExposureTime)).get_exposure_time_left()
        assert 0.0 <= left <= self.long_exposure_time
        with pytest.raises(DeviceBusyError):
            await camera.grab_data()
        await camera.abort()
        await self._expect_aborted(grab)

    async def test_abort_ends_an_exposure_without_a_file(self, contract: ContractSetup[Any]) -> None:
        camera = await contract.proxy(ICamera)
        await self._small_frame(contract)
        grab = await self._start_long_exposure(contract)
        await camera.abort()
        await self._expect_aborted(grab)
        assert await camera.get_exposure_status() is ExposureStatus.IDLE
        # Usable again at once; its file is the only one announced.
        await (await contract.proxy(IExposureTime)).set_exposure_time(self.exposure_time)
        filename = await camera.grab_data()
        await contract.probe.wait_for_event(NewImageEvent, self.timeout, sender=contract.name)
        assert [e.filename for e in await self._new_images(contract)] == [filename]

    async def test_a_stopped_exposure_is_read_out_and_kept_saying_so(
        self, contract: ContractSetup[Any]
    ) -> None:
        names = await contract.probe.comm.get_interface_names(contract.name)
        vfs = contract.module.vfs
        if not isinstance(contract.module, IStoppableExposure):  # e.g. INDI: it can only abort
            assert "IStoppableExposure" not in names
            return
        assert "IStoppableExposure" in names
        await (await contract.proxy(IImageType)).set_image_type(ImageType.OBJECT)
        await self._small_frame(contract)
        grab = await self._start_long_exposure(contract)
        await (await contract.proxy(IStoppableExposure)).stop_exposure()
        filename = await grab
        header = (await vfs.read_fits(filename))[0].header
        assert header["CUTSHORT"] is True
        assert header["EXPREQ"] == pytest.approx(self.long_exposure_time)
        assert 0.0 <= header["EXPTIME"] < self.long_exposure_time
        event = await contract.probe.wait_for_event(NewImageEvent, self.timeout, sender=contract.name)
        assert event.filename == filename

    async def test_an_exposure_ends_within_the_timeout_it_announces(
        self, contract: ContractSetup[Any]
    ) -> None:
        # Longer than the default RPC timeout: a camera that announced nothing would be cut off.
        await (await contract.proxy(IExposureTime)).set_exposure_time(DEFAULT_TIMEOUT + 2.0)
        await self._small_frame(contract)
        announced, took = await timed_call(contract, "grab_data")
        assert took >= DEFAULT_TIMEOUT + 2.0
        assert took < announced, f"grab_data took {took:.1f} s but announced {announced:g} s"
