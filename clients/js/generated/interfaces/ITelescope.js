// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IMotion } from "./IMotion.js";
import { IPointingAltAz } from "./IPointingAltAz.js";
import { IPointingRaDec } from "./IPointingRaDec.js";

/**
 * What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.
 * @typedef {"parked"|"initializing"|"idle"|"slewing"|"tracking"|"moving"|"parking"|"aborting"|"error"|"unknown"} MotionStatus
 */
/**
 * A telescope mount: a moving device that points in both coordinate systems.
 *
 * Extends IMotion, IPointingAltAz, IPointingRaDec (their methods are here too).
 */
export class ITelescope extends RemoteInterface {
  /**
   * Current (alt, az) in degrees.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_altaz() {
    return this._invoke("get_altaz", arguments);
  }
  /**
   * Motion status of ``device``, or of the module as a whole (None, or a name the module lacks).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {string|null} [device] default null
   * @returns {Promise<MotionStatus>}
   */
  get_motion_status(device) {
    return this._invoke("get_motion_status", arguments);
  }
  /**
   * Current (ra, dec) in degrees.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_radec() {
    return this._invoke("get_radec", arguments);
  }
  /**
   * Initialise the device (home, unpark, power on) and leave it idle.
   *
   * Timeout: announced, 300 clock seconds.
   * @returns {Promise<null>}
   */
  init() {
    return this._invoke("init", arguments);
  }
  /**
   * Whether the device is ready (initialised, not in error).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<boolean>}
   */
  is_ready() {
    return this._invoke("is_ready", arguments);
  }
  /**
   * Move to altitude ``alt`` and azimuth ``az`` (degrees, azimuth east of north).
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} alt [deg] minimum -90.0 maximum 90.0
   * @param {number} az [deg] minimum -360.0 maximum 360.0
   * @returns {Promise<null>}
   */
  move_altaz(alt, az) {
    return this._invoke("move_altaz", arguments);
  }
  /**
   * Slew to right ascension ``ra`` and declination ``dec`` (degrees) and track.
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} ra [deg] minimum 0.0 exclusiveMaximum 360.0
   * @param {number} dec [deg] minimum -90.0 maximum 90.0
   * @returns {Promise<null>}
   */
  move_radec(ra, dec) {
    return this._invoke("move_radec", arguments);
  }
  /**
   * Move the device into its safe parking position.
   *
   * Timeout: announced, 300 clock seconds.
   * @returns {Promise<null>}
   */
  park() {
    return this._invoke("park", arguments);
  }
  /**
   * Stop any motion of ``device`` (or of all devices: None, or a name the module lacks) now.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {string|null} [device] default null
   * @returns {Promise<null>}
   */
  stop_motion(device) {
    return this._invoke("stop_motion", arguments);
  }
}
ITelescope.spec = {
  "methods": {},
  "name": "ITelescope",
  "schemas": {},
  "version": 1
};
ITelescope.bases = [IMotion, IPointingAltAz, IPointingRaDec];
