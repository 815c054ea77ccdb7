"""The robotic modules of an observatory directory, each only where the devices it needs exist.

Returns ``{module name: (header, config, {fragment path: text})}`` and ``{module: why left out}``.
"""

from __future__ import annotations

from typing import Any

from nightcrew.night.init._found import FoundDevice
from nightcrew.night.init._options import InitOptions
from nightcrew.night.init._yaml import Include, module_text

__all__ = ["Modules", "first_of", "images_vfs", "robotic_modules"]

Modules = dict[str, tuple[str, dict[str, Any], dict[str, str]]]

#: The task archive the scheduler, the mastermind and `nightcrew tasks --db` share (relative to
#: the directory; the scheduler keeps its plan there too, so a mastermind in another process sees it).
TASKS = "tasks.sqlite"
#: A first guess at a twilight flat's exposure time [s] from the Sun's altitude h [deg]; refit it
#: for your camera with `nightcrew flats fit` after the first twilight.
_FLAT_FUNCTION = "exp(-0.9203*(h + 4.0))"


def first_of(devices: dict[str, FoundDevice], *roles: str) -> str | None:
    """The name of the first device with one of ``roles`` (in the order the roles are given)."""
    for role in roles:
        for name, device in devices.items():
            if device.role == role:
                return name
    return None


def robotic_modules(options: InitOptions, devices: dict[str, FoundDevice]) -> tuple[Modules, dict[str, str]]:
    modules: Modules = {}
    left_out: dict[str, str] = {}
    telescope = first_of(devices, "telescope")
    camera = first_of(devices, "camera")
    enclosure = first_of(devices, "roof", "dome")
    focuser = first_of(devices, "focuser")
    filters = first_of(devices, "filters")
    stations = {name: d for name, d in devices.items() if d.role in ("safetymonitor", "conditions")}
    site = Include("shared/site.yaml")

    if stations:
        modules["weather"] = (
            "The weather verdict: judges the stations below and sends BadWeatherEvent / "
            "GoodWeatherEvent (roof and dome close by themselves on the first; the mastermind and "
            "the scheduler react to both). Add checks for your station's sensors (docs/configuration.md).",
            _weather(stations, options.good_weather_after),
            {},
        )
    else:
        left_out["weather"] = "no safety monitor or weather station found"

    if telescope and camera:
        modules["scheduler"] = (
            f"Plans the night from the task archive ({TASKS}; `nightcrew tasks --db {TASKS} add FILE`) "
            "and keeps the plan there, where the mastermind reads it. Re-plans when tasks change, a "
            "task fails or the weather turns good.",
            {
                "class": "nightcrew.modules.robotic.SchedulerModule",
                "site": site,
                "archive": {"class": "nightcrew.robotic.archives.SqliteTaskArchive", "path": TASKS},
                "step_s": 300,
                "slew_overhead_s": 60,
                "time_limit_s": 30,
                "max_sun_altitude": -12 if not filters else -3,
            },
            {},
        )
    else:
        left_out["scheduler"] = "needs a telescope and a camera"

    if focuser and camera:
        modules["focus"] = (
            "Finds the best focus from a series of frames (median FWHM of the stars, hyperbola fit).",
            {
                "class": "nightcrew.modules.focus.AutoFocusSeries",
                "camera": camera,
                "focuser": focuser,
                "vfs": images_vfs(options),  # reads the camera's frames
            },
            {},
        )
    else:
        left_out["focus"] = "needs a camera and a focuser"

    flat_filters = devices[filters].filter_names if filters else ()
    if camera and telescope and filters and flat_filters:
        functions = {name: {"1x1": _FLAT_FUNCTION} for name in flat_filters}
        fragment = {
            "shared/flat-functions.yaml": module_text(
                "Exposure time [s] of a twilight flat from the Sun's altitude h [deg], per filter and "
                "binning: a first guess. Fit yours with `nightcrew flats fit` after the first twilight. "
                "Not a module: included by flatfield.yaml and by the mastermind's SKY_FLAT script.",
                functions,
            )
        }
        modules["flatfield"] = (
            "Twilight sky flats: exposure time from the Sun's altitude, frames kept near the target level.",
            {
                "class": "nightcrew.modules.flatfield.FlatField",
                "site": site,
                "camera": camera,
                "filters": filters,
                "pointing": "flatpointing",
                "vfs": images_vfs(options),  # reads the camera's frames
                "functions": Include("shared/flat-functions.yaml"),
                "target": 30000,
                "min_exposure": 1.0,
                "max_exposure": 60.0,
            },
            fragment,
        )
        modules["flatpointing"] = (
            "Points the telescope at the flattest patch of the twilight sky, dithering between flats.",
            {"class": "nightcrew.modules.flatfield.FlatFieldPointing", "site": site, "telescope": telescope},
            {},
        )
    else:
        left_out["flatfield"] = "needs a camera, a telescope and a filter wheel that names its filters"

    if telescope and camera and enclosure and "weather" in modules:
        modules["mastermind"] = (
            "Runs the planned task due now whenever weather, roof and Sun allow; opens and closes the "
            "roof, parks the telescope, focuses when the temperature changed.",
            _mastermind(
                telescope,
                camera,
                enclosure,
                filters,
                "focus" in modules,
                "flatfield" in modules,
                first_of(devices, "cover"),
            ),
            {},
        )
        watch = {"weather": 120, "mastermind": 300}
        modules["watchdog"] = (
            "Closes the roof and parks the telescope when the weather verdict or the mastermind stays "
            "silent (frozen, crashed, offline) longer than the seconds under `watch`.",
            {
                "class": "nightcrew.modules.safety.SafetyWatchdog",
                "watch": watch,
                "roof": enclosure,
                "telescope": telescope,
                "weather": "weather",
                "interval": 10,
            },
            {},
        )
    else:
        left_out["mastermind"] = "needs a telescope, a camera, a roof or dome and a weather verdict"
        left_out["watchdog"] = "watches the mastermind and the weather verdict"

    if camera:
        modules["pipeline"] = (
            "The online reduction: every new science frame of the camera calibrated with the newest "
            "masters in reduced/masters (`nightcrew reduce` makes them), plate-solved with the catalog "
            "matcher and measured; written to reduced/ as <name>_red.fits. Add `solver_url:` for the "
            "solving service (`nightcrew solver`) or `solve_field: true` (docs/pipeline.md).",
            {
                "class": "nightcrew.modules.image.Pipeline",
                "masters": "/data/masters",
                "output": "/data",
                "sources": [camera],
                "vfs": images_vfs(options, data="reduced"),
            },
            {},
        )
    else:
        left_out["pipeline"] = "needs a camera"

    modules["console"] = (
        f"The web console on http://127.0.0.1:{options.console_port}/ (this machine only; put a TLS "
        "proxy in front to reach it from elsewhere). Logins: secrets/console-accounts.yaml.",
        {
            "class": "nightcrew.modules.console.WebConsole",
            "host": "127.0.0.1",
            "port": options.console_port,
            "title": options.site_name or "nightcrew observatory",
            "accounts": Include("secrets/console-accounts.yaml"),
            "site": site,
            "vfs": images_vfs(options),
        },
        {},
    )
    return modules, left_out


def images_vfs(options: InitOptions, **more: str) -> dict[str, Any]:
    """The VFS with the camera's root ``images`` (and ``more`` roots: name → local folder), for the
    modules that read its frames by their VFS paths."""
    roots = {name: {"class": "nightcrew.vfs.LocalFile", "root": folder} for name, folder in more.items()}
    return {
        "class": "nightcrew.vfs.VirtualFileSystem",
        "roots": {"images": {"class": "nightcrew.vfs.LocalFile", "root": options.images}, **roots},
    }


def _weather(stations: dict[str, FoundDevice], good_after: float) -> dict[str, Any]:
    """Checks on what every station surely has: a safety monitor's (or INDI weather driver's) own
    verdict, ``safe``; rain and wind only from a station without one (sensors differ by device)."""
    checks: dict[str, Any] = {}
    judges = [name for name, d in stations.items() if d.role == "safetymonitor" or "device" in d.config]
    for name in judges or stations:
        if name in judges:
            checks[f"{name}.safe"] = {"class": "nightcrew.weather.Boolean", "good_when": True}
        else:
            checks[f"{name}.rain"] = {"class": "nightcrew.weather.Boolean", "good_when": False}
            checks[f"{name}.wind_speed"] = {"class": "nightcrew.weather.Switch", "bad_above": 50}
    return {
        "class": "nightcrew.modules.weather.Weather",
        "interval": 10,
        "min_good_time": good_after,
        "stations": {
            name: {"class": "nightcrew.modules.weather.ModuleStation", "module": name}
            for name in judges or stations
        },
        "checks": checks,
    }


def _mastermind(
    telescope: str,
    camera: str,
    roof: str,
    filters: str | None,
    focus: bool,
    flats: bool,
    panel: str | None,
) -> dict[str, Any]:
    imaging = {
        "class": "nightcrew.robotic.scripts.ImagingScript",
        "telescope": telescope,
        "camera": camera,
        "filters": filters,
    }
    calibration = {"class": "nightcrew.robotic.scripts.CalibrationScript"}
    scripts: dict[str, Any] = {
        "EXPOSE": imaging,
        "REPEAT_EXPOSE": imaging,
        "BIAS": calibration,
        "DARK": calibration,
    }
    if focus:
        scripts["AUTO_FOCUS"] = {"class": "nightcrew.robotic.scripts.AutoFocusScript", "focus": "focus"}
    if flats:
        scripts["SKY_FLAT"] = {
            "class": "nightcrew.robotic.scripts.SkyFlatScript",
            "flatfield": "flatfield",
            "functions": Include("shared/flat-functions.yaml"),
        }
    if panel:  # a flat panel (or a flip-flat) found: PANEL_FLAT tasks take their flats on it
        scripts["PANEL_FLAT"] = {
            "class": "nightcrew.robotic.scripts.PanelFlatScript",
            "camera": camera,
            "filters": filters,
            "calibrator": panel,
        }
    return {
        "class": "nightcrew.modules.robotic.mastermind.Mastermind",
        "site": Include("shared/site.yaml"),
        "archive": {"class": "nightcrew.robotic.archives.SqliteTaskArchive", "path": TASKS},
        "roof": roof,
        "telescope": telescope,
        "weather": "weather",
        "autofocus": "focus" if focus else None,
        "max_sun_altitude": -12,
        "twilight_max_sun_altitude": -3,
        "poll_interval": 30,
        "runner": {"class": "nightcrew.robotic.runner.TaskRunner", "scripts": scripts},
    }
