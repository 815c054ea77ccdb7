// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IMotion } from "./IMotion.js";

/**
 * What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.
 * @typedef {"parked"|"initializing"|"idle"|"slewing"|"tracking"|"moving"|"parking"|"aborting"|"error"|"unknown"} MotionStatus
 */
/**
 * A focuser: a base position plus an offset (e.g. from a focus model or filter).
 *
 * Extends IMotion (their methods are here too).
 */
export class IFocuser extends RemoteInterface {
  /**
   * Base focus position in mm.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_focus() {
    return this._invoke("get_focus", arguments);
  }
  /**
   * Offset in mm added to the base position.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_focus_offset() {
    return this._invoke("get_focus_offset", arguments);
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
   * Move the device into its safe parking position.
   *
   * Timeout: announced, 300 clock seconds.
   * @returns {Promise<null>}
   */
  park() {
    return this._invoke("park", arguments);
  }
  /**
   * Move to base focus position ``focus`` in mm.
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} focus
   * @returns {Promise<null>}
   */
  set_focus(focus) {
    return this._invoke("set_focus", arguments);
  }
  /**
   * Set the offset in mm added to the base position.
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} offset
   * @returns {Promise<null>}
   */
  set_focus_offset(offset) {
    return this._invoke("set_focus_offset", arguments);
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
IFocuser.spec = {
  "methods": {
    "get_focus": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_focus_offset": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_focus": {
      "params": [
        {
          "name": "focus",
          "required": true,
          "schema": {
            "type": "number"
          }
        }
      ],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 300.0
      }
    },
    "set_focus_offset": {
      "params": [
        {
          "name": "offset",
          "required": true,
          "schema": {
            "type": "number"
          }
        }
      ],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 300.0
      }
    }
  },
  "name": "IFocuser",
  "schemas": {},
  "version": 1
};
IFocuser.bases = [IMotion];
