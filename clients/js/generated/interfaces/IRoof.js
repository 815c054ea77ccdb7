// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IMotion } from "./IMotion.js";

/**
 * What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.
 * @typedef {"parked"|"initializing"|"idle"|"slewing"|"tracking"|"moving"|"parking"|"aborting"|"error"|"unknown"} MotionStatus
 */
/**
 * A roof or shutter; stop_motion stops it halfway.
 *
 * Extends IMotion (their methods are here too).
 */
export class IRoof extends RemoteInterface {
  /**
   * Close the roof completely.
   *
   * Timeout: announced, 300 clock seconds.
   * @returns {Promise<null>}
   */
  close_roof() {
    return this._invoke("close_roof", arguments);
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
   * Open the roof completely.
   *
   * Timeout: announced, 300 clock seconds.
   * @returns {Promise<null>}
   */
  open_roof() {
    return this._invoke("open_roof", arguments);
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
IRoof.spec = {
  "methods": {
    "close_roof": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 300.0
      }
    },
    "open_roof": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 300.0
      }
    }
  },
  "name": "IRoof",
  "schemas": {},
  "version": 1
};
IRoof.bases = [IMotion];
