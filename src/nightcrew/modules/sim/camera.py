"""A simulated camera: renders the sky the other simulated devices say it should see.

At the start of each exposure the camera asks, through the comm, where the telescope really points
(ISimTelescopeTruth), how far the focuser is from best focus (IFocuser + ISimFocuserTruth), which
filter is in the beam (IFilters), on which side of its pier a German-equatorial mount stands
(IPierSide: the field stands upside down, turned 180°, on the west side), whether the roof is open
(IRoof) and how cloudy it is (ISimWeatherTruth). It then waits the exposure time on the clock and
renders the frame with :func:`~nightcrew.sim.render.render_frame` in a worker thread, so the event
loop keeps serving calls. A device that is not configured (``None``) is simply absent; one that is
configured but does not answer gives a warning (once) and a sensible default: no telescope means no
light at all.

Stopped early (IStoppableExposure: bad weather ends a science frame), the camera renders the
frame anew for the seconds the shutter was open and keeps it.

The frame carries the camera's own cards (gain, read noise, pixel size, focal length, pixel scale)
and a few ``SIM-*`` cards with the simulator's truth (true pointing, FWHM, cloud cover) for tests
and tutorials, and the sky it shows (``SIM-SKY``: seed, depth and star sources, whose index files
:mod:`nightcrew.sim.sky_index` builds; ``SIM-STAR``: the real star sources and their versions).
It has no WCS: finding one is the plate solver's job. While the mount tracks at offset rates the
stars trail, and the body it follows (ISimTelescopeTruth.get_true_motion) is drawn where its
ephemeris puts it during the exposure (:mod:`.bodies`).

Its cooler follows :mod:`nightcrew.sim.thermal` (``cooler``: ambient, reach below ambient, time
constant), on the clock: a set point below its reach is accepted, as a real camera's is, with a
warning - the chip stays warmer, the power at 100 %, and its frames are flagged (TEMP-OK = F).
"""

from __future__ import annotations

import asyncio
import functools
import logging
import math
import threading
from collections.abc import Awaitable, Callable, Mapping
from dataclasses import fields, replace
from typing import Any, TypeVar

import numpy as np

from nightcrew.astro import julian_year
from nightcrew.errors import ConfigError, InterfaceError, NightcrewError
from nightcrew.interfaces import (
    Binning,
    CalibratorState,
    CoverState,
    ExposureStatus,
    FitsCard,
    ICoverCalibrator,
    IFilters,
    IFocuser,
    IPierSide,
    IRoof,
    IStoppableExposure,
    MotionStatus,
    PierSide,
    Window,
)
from nightcrew.modules.camera import BaseCamera, ExposureSettings, Frame
from nightcrew.modules.sim.bodies import exposure_motion
from nightcrew.modules.sim.interfaces import ISimFocuserTruth, ISimTelescopeTruth, ISimWeatherTruth
from nightcrew.modules.sim.scene import Atmosphere, Scene, StarFieldCache, conditions_at
from nightcrew.modules.telescope.following import parse_moving_target
from nightcrew.sim import projection, render, sky_index
from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.real_stars import star_sources
from nightcrew.sim.thermal import ChipTemperature, CoolerModel, advance_chip

__all__ = ["SimCamera"]

log = logging.getLogger(__name__)

T = TypeVar("T")
M = TypeVar("M")

_BINNINGS = (1, 2, 4)


class SimCamera(BaseCamera, IStoppableExposure):
    """A camera in the simulated observatory.

    Args:
        telescope: Module offering ISimTelescopeTruth (None: no telescope, dark frames).
        focuser: Module offering IFocuser and ISimFocuserTruth (None: always in focus).
        filters: Module offering IFilters (None: no filter, throughput 1).
        roof: Module offering IRoof; light passes only while it is open (None: no roof).
        weather: Module offering ISimWeatherTruth (None: clear sky).
        calibrator: Module offering ICoverCalibrator (None: none): a closed cover keeps the sky
            out, a lit light in front of the optics (cover closed, or no cover) is a flat panel.
        panel_e_per_s: The panel's light at full brightness, electrons per pixel and second
            before the filter.
        detector: Fields of :class:`~nightcrew.sim.render.CameraModel` (chip_width, chip_height,
            pixel_size_um, gain_e_per_adu, read_noise_e, bias_adu, dark_e_per_s, full_well_e, ...).
        optics: Fields of :class:`~nightcrew.sim.render.Optics` (focal_length_mm, zero_point_mag,
            optics_fwhm_arcsec, defocus_arcsec_per_unit, moffat_beta); best focus comes from the focuser.
        seeing: Atmospheric seeing FWHM in arcseconds.
        extinction: Magnitudes of extinction per airmass.
        dark_sky: Sky brightness of a dark night, mag/arcsec².
        filter_throughputs: Throughput (0..1) per filter name; unlisted filters pass everything.
        catalog_depth: Faintest magnitude drawn (real stars to G=10, synthetic ones beyond).
        readout_time: Seconds to read the chip out.
        cooler: Fields of :class:`~nightcrew.sim.thermal.CoolerModel` (ambient, max_delta,
            time_constant).
        seed: Seed of noise and synthetic stars: the same seed gives the same night.
        **kwargs: Camera options (``filename_pattern``, ``fits_headers``, ...) and module options.
    """

    def __init__(
        self,
        *,
        telescope: str | ISimTelescopeTruth | None = "telescope",
        focuser: str | IFocuser | None = "focuser",
        filters: str | IFilters | None = "filters",
        roof: str | IRoof | None = "roof",
        weather: str | ISimWeatherTruth | None = "weather",
        calibrator: str | ICoverCalibrator | None = None,
        panel_e_per_s: float = 20000.0,
        detector: dict[str, float] | None = None,
        optics: dict[str, float] | None = None,
        seeing: float = 1.5,
        extinction: float = 0.2,
        dark_sky: float = 21.0,
        filter_throughputs: dict[str, float] | None = None,
        catalog_depth: float = 16.0,
        readout_time: float = 2.0,
        cooler: dict[str, float] | None = None,
        seed: int = 0,
        **kwargs: Any,
    ) -> None:
        # BaseCamera asks for the chip size while it is built, so the detector comes first.
        self._detector = _model_from_config(render.CameraModel, detector, "detector")
        self._optics = _model_from_config(render.Optics, optics, "optics")
        try:
            self._cooler = _model_from_config(CoolerModel, cooler, "cooler")
        except ValueError as exc:
            raise ConfigError(str(exc), key="cooler") from exc
        self._chip: ChipTemperature | None = None  # at ambient until the clock first asks
        super().__init__(**kwargs)
        self._telescope, self._focuser, self._filters = telescope, focuser, filters
        self._roof, self._weather = roof, weather
        if not (math.isfinite(panel_e_per_s) and panel_e_per_s >= 0):
            raise ConfigError(f"must be >= 0 electrons per second, got {panel_e_per_s}", key="panel_e_per_s")
        self._calibrator, self._panel_e_per_s = calibrator, float(panel_e_per_s)
        if not (seeing > 0 and extinction >= 0 and math.isfinite(dark_sky)):
            raise ConfigError(
                f"need seeing > 0, extinction >= 0 and a finite dark_sky, "
                f"got {seeing}, {extinction}, {dark_sky}",
                key="seeing",
            )
        self._atmosphere = Atmosphere(float(seeing), float(extinction), float(dark_sky))
        self._throughputs = dict(filter_throughputs or {})
        for name, value in self._throughputs.items():
            if not 0.0 <= value <= 1.0:
                raise ConfigError(f"must be within 0..1, got {value}", key=f"filter_throughputs.{name}")
        if not readout_time >= 0:
            raise ConfigError(f"must be >= 0 seconds, got {readout_time}", key="readout_time")
        self._readout_time = float(readout_time)
        try:
            catalog = StarCatalog(depth=catalog_depth, seed=seed)
        except ValueError as exc:
            raise ConfigError(str(exc), key="catalog_depth") from exc
        self._catalog = catalog
        self._stars = StarFieldCache(catalog)
        self._stars_lock = threading.Lock()  # an aborted render may still run in its thread
        self._rng = np.random.default_rng(seed)
        self._warned: set[str] = set()
        self.add_background_task(self._warm_up_task, restart=False)

    async def _warm_up_task(self) -> None:
        # Reading the bundled catalog takes a few seconds: do it now, not in the first readout.
        await asyncio.to_thread(self._blocking_warm_up)

    def _blocking_warm_up(self) -> None:
        with self._stars_lock:
            self._catalog.query(0.0, 0.0, 0.01)

    @functools.cached_property
    def _sky(self) -> tuple[str, str]:
        """The sky's id and its real star sources, for the frames' cards."""
        return sky_index.sky_id(self._catalog), star_sources()

    # --- BaseCamera hooks ----------------------------------------------------------------------

    def _hw_readout_allowance(self) -> float:
        return self._readout_time  # the render's remainder runs in clock.work: no clock time

    def _hw_full_frame(self) -> Window:
        return Window(0, 0, self._detector.chip_width, self._detector.chip_height)

    def _hw_binnings(self) -> list[Binning]:
        return [Binning(b, b) for b in _BINNINGS]

    @classmethod
    def coldest_setpoint(cls, options: Mapping[str, Any]) -> float | None:
        cooler = options.get("cooler") or {}
        try:
            return CoolerModel(**{k: float(v) for k, v in cooler.items()}).coldest
        except (TypeError, ValueError):  # the file's own check names what is wrong
            return None

    def _chip_now(self) -> ChipTemperature:
        """The chip's temperature now, the cooler as it was since the last look."""
        now = self.clock.time()
        state = self._chip or ChipTemperature(now, self._cooler.ambient)
        enabled, setpoint = self._cooling.enabled, self._cooling.setpoint
        self._chip = advance_chip(self._cooler, state, now, enabled=enabled, setpoint=setpoint)
        return self._chip

    async def _hw_set_cooling(self, enabled: bool, setpoint: float) -> None:
        self._chip_now()  # the chip so far followed the old set point
        if enabled and setpoint < self._cooler.coldest:
            log.warning(
                "%s: set point %g °C is below what the cooler can reach (%g °C: ambient %g °C - %g °C)",
                self.name,
                setpoint,
                self._cooler.coldest,
                self._cooler.ambient,
                self._cooler.max_delta,
            )

    async def _hw_cooling_power(self) -> float:
        return self._cooler.power(self._cooling.enabled, self._cooling.setpoint)

    async def _hw_ccd_temperature(self) -> float | None:
        return self._chip_now().temperature

    async def _hw_expose(self, settings: ExposureSettings) -> Frame:
        scene = await self._look_around() if settings.shutter_open else Scene(None, roof_open=False)
        # The shutter opens once the devices have answered: DATE-OBS and the render start from here.
        start = self._start_integration()
        rng = self._rng.spawn(1)[0]
        # The scene is fixed at the start, so render while the clock runs down the exposure: on a
        # fast clock the render time would otherwise show up as a long readout.
        render = asyncio.ensure_future(asyncio.to_thread(self._blocking_render, scene, settings, start, rng))
        try:
            exposed = await self._integrate(settings.exposure_time)
            if exposed < settings.exposure_time:  # stopped early: the chip saw light this long
                render.cancel()  # its thread still draws from ``rng``: the new render gets its own
                settings, rng = replace(settings, exposure_time=exposed), self._rng.spawn(1)[0]
                render = asyncio.ensure_future(
                    asyncio.to_thread(self._blocking_render, scene, settings, start, rng)
                )
            await self._set_exposure_status(ExposureStatus.READOUT)
            await self.clock.sleep(self._readout_time)
            async with self.clock.work("simulate"):  # the rest of the render: not the sky's time
                frame = await render
        finally:
            render.cancel()  # aborted: drop the frame (the thread finishes on its own)
        return frame

    # --- asking the other devices --------------------------------------------------------------

    async def _look_around(self) -> Scene:
        """What the telescope, focuser, filter wheel, roof and weather say right now."""
        # The side is asked of a telescope module (by name); one given as an object has none.
        pier = self._telescope if isinstance(self._telescope, str) else None
        no_motion: tuple[tuple[float, float], dict[str, Any] | None] = ((0.0, 0.0), None)
        # Three gathers (asked at once all the same): typed gather stops at six awaitables.
        (
            (radec, rotation, focus_error, filter_name, roof_open, clouds),
            (covered, panel),
            (rates, followed),
        ) = await asyncio.gather(
            asyncio.gather(
                self._ask("telescope", self._telescope, ISimTelescopeTruth, _true_radec, None),
                self._ask("telescope", pier, IPierSide, _field_rotation, 0.0),
                self._ask("focuser", self._focuser, IFocuser, self._focus_error, 0.0),
                self._ask("filters", self._filters, IFilters, _filter_name, None),
                self._ask("roof", self._roof, IRoof, _roof_open, True),
                self._ask("weather", self._weather, ISimWeatherTruth, _cloud_cover, 0.0),
            ),
            self._ask("calibrator", self._calibrator, ICoverCalibrator, _cover_and_panel, (False, 0.0)),
            self._ask("telescope", self._telescope, ISimTelescopeTruth, _true_motion, no_motion),
        )
        throughput = self._throughputs.get(filter_name, 1.0) if filter_name is not None else 1.0
        return Scene(
            radec,
            focus_error,
            filter_name,
            throughput,
            roof_open,
            clouds,
            covered=covered,
            panel=panel,
            field_rotation=rotation,
            rates=rates,
            followed=followed,
        )

    async def _ask(
        self,
        role: str,
        target: str | M | None,
        interface: type[M],
        question: Callable[[M], Awaitable[T]],
        default: T,
    ) -> T:
        """``question(proxy)``, or ``default`` if the device is absent or does not answer."""
        if target is None:
            return default
        try:
            peer = await self.proxy(target, interface)  # type: ignore[type-var]
            return await question(peer)
        except NightcrewError as exc:
            if role not in self._warned:
                self._warned.add(role)
                log.warning("%s: no answer from the %s (%s); assuming %r", self.name, role, exc, default)
            return default

    async def _focus_error(self, focuser: IFocuser) -> float:
        position = await focuser.get_focus() + await focuser.get_focus_offset()
        target = self._focuser
        if not isinstance(target, str | ISimFocuserTruth):
            raise InterfaceError(f"{target!r} is not a simulated focuser (ISimFocuserTruth)")
        truth = await self.proxy(target, ISimFocuserTruth)
        return position - await truth.get_best_focus()

    # --- rendering (in a worker thread) --------------------------------------------------------

    def _blocking_render(
        self, scene: Scene, settings: ExposureSettings, start: float, rng: np.random.Generator
    ) -> Frame:
        conditions = conditions_at(scene, self.site, start, self._atmosphere, self._panel_e_per_s)
        binning = settings.binning.x
        window = settings.window
        exposure = render.Exposure(
            exposure_time_s=settings.exposure_time,
            binning=binning,
            window=projection.Window(window.left, window.top, window.width, window.height),
            shutter_open=settings.shutter_open,
            filter_throughput=scene.throughput,
        )
        geometry = render.frame_geometry(self._detector, self._optics, exposure)
        stars = StarFieldCache.empty()
        if conditions.roof_open and scene.true_radec is not None:
            # The star positions at the clock's epoch (proper motion).
            jyear = julian_year(start)
            with self._stars_lock:
                stars = self._stars.stars(*scene.true_radec, render.field_radius_deg(geometry), jyear)
        pointing = projection.Pointing(*(scene.true_radec or (0.0, 0.0)), rotation_deg=scene.field_rotation)
        motion = None
        if scene.true_radec is not None and self.site is not None:
            # The mount's rates and the body it follows, from the start: the sky moves as they say.
            motion = exposure_motion(
                start=start,
                exposure_time=settings.exposure_time,
                pointing=scene.true_radec,
                rates=scene.rates,
                body=None if scene.followed is None else parse_moving_target(scene.followed)[0],
                site=self.site,
                pixel_scale_arcsec=geometry.pixel_scale_arcsec,
            )
        frame = render.render_frame(
            stars,
            pointing=pointing,
            focus=scene.focus_error,
            camera=self._detector,
            optics=self._optics,
            conditions=conditions,
            exposure=exposure,
            rng=rng,
            motion=motion,
        )
        scale = geometry.pixel_scale_arcsec * binning
        cards: dict[str, FitsCard] = {
            "GAIN": (self._detector.gain_e_per_adu, "Detector gain [e-/ADU]"),
            "RDNOISE": (self._detector.read_noise_e, "Read noise [e-]"),
            "XPIXSZ": (self._detector.pixel_size_um * binning, "Pixel width incl. binning [um]"),
            "YPIXSZ": (self._detector.pixel_size_um * binning, "Pixel height incl. binning [um]"),
            "FOCALLEN": (self._optics.focal_length_mm, "Focal length [mm]"),
            "PIXSCALE": (round(scale, 5), "Pixel scale incl. binning [arcsec/px]"),
            "SATURATE": (65535, "Saturation level [ADU]"),
            "SIM-FWHM": (round(frame.fwhm_px * scale, 3), "Simulator: star FWHM [arcsec]"),
            "SIM-CLD": (round(scene.cloud_cover, 3), "Simulator: cloud cover (0..1)"),
            "SIM-SUNA": (round(conditions.sun_altitude_deg, 2), "Simulator: Sun altitude [deg]"),
            "SIM-SEED": (self._catalog.seed, "Simulator: seed of the synthetic stars"),
            "SIM-DPTH": (self._catalog.depth, "Simulator: faintest catalog star drawn [mag]"),
            # Which sky this is: its index files are in ~/.cache/nightcrew/indexes/<seed-depth>.
            "SIM-SKY": (self._sky[0], "Simulator: sky id (seed, depth, sources hash)"),
            "SIM-STAR": (self._sky[1], "Simulator: real star sources"),
        }
        if scene.true_radec is not None:
            cards["SIM-RA"] = (round(scene.true_radec[0], 7), "Simulator: true RA of the axis [deg]")
            cards["SIM-DEC"] = (round(scene.true_radec[1], 7), "Simulator: true Dec of the axis [deg]")
        return Frame(frame.data, cards)


# --- questions to the devices (each returns one plain value) ---------------------------------------


async def _true_radec(telescope: ISimTelescopeTruth) -> tuple[float, float] | None:
    ra, dec = await telescope.get_true_radec()
    return float(ra), float(dec)


async def _field_rotation(telescope: IPierSide) -> float:
    # A GEM's flip turns the camera half round on the sky: north up on the east side (and on a
    # mount without sides), north down on the west side.
    return 180.0 if await telescope.get_pier_side() is PierSide.WEST else 0.0


async def _true_motion(telescope: ISimTelescopeTruth) -> tuple[tuple[float, float], dict[str, Any] | None]:
    (ra_rate, dec_rate), followed = await telescope.get_true_motion()
    return (float(ra_rate), float(dec_rate)), followed


async def _filter_name(filters: IFilters) -> str | None:
    return await filters.get_filter()


async def _cover_and_panel(calibrator: ICoverCalibrator) -> tuple[bool, float]:
    """Whether the cover keeps the sky out, and the lit panel's brightness (0..1) in front of the optics."""
    cover = await calibrator.get_cover_state()
    covered = cover not in (CoverState.OPEN, CoverState.NOT_PRESENT)
    if cover not in (CoverState.CLOSED, CoverState.NOT_PRESENT):
        return covered, 0.0  # the light shines on the cover's back, or past the optics
    if await calibrator.get_calibrator_state() is not CalibratorState.READY:
        return covered, 0.0
    return covered, await calibrator.get_brightness() / await calibrator.get_max_brightness()


async def _roof_open(roof: IRoof) -> bool:
    # A roof is IDLE when open (PARKED closed, MOVING/PARKING on its way): light only when open.
    return await roof.get_motion_status() is MotionStatus.IDLE


async def _cloud_cover(weather: ISimWeatherTruth) -> float:
    return float(await weather.get_cloud_cover())


def _model_from_config(model: type[T], values: Mapping[str, float] | None, key: str) -> T:
    """``model(**values)`` with every value checked: known field, finite, integer where needed."""
    defaults = {f.name: getattr(model(), f.name) for f in fields(model)}  # type: ignore[arg-type]
    typed: dict[str, float | int] = {}
    for name, value in (values or {}).items():
        if name not in defaults:
            raise ConfigError(f"unknown key; known keys: {', '.join(defaults)}", key=f"{key}.{name}")
        if not math.isfinite(value):
            raise ConfigError(f"must be a finite number, got {value}", key=f"{key}.{name}")
        if isinstance(defaults[name], int):
            if not float(value).is_integer():
                raise ConfigError(f"must be a whole number, got {value}", key=f"{key}.{name}")
            typed[name] = int(value)
        else:
            typed[name] = float(value)
    for name in ("chip_width", "chip_height", "pixel_size_um", "gain_e_per_adu", "focal_length_mm"):
        if name in typed and not typed[name] > 0:
            raise ConfigError(f"must be > 0, got {typed[name]}", key=f"{key}.{name}")
    return model(**typed)
