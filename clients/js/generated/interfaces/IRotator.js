// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IMotion } from "./IMotion.js";

/**
 * What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.
 * @typedef {"parked"|"initializing"|"idle"|"slewing"|"tracking"|"moving"|"parking"|"aborting"|"error"|"unknown"} MotionStatus
 */
/**
 * A rotator: a sky position angle (mechanical angle plus a sync offset) that it can move to.
 *
 * ``stop_motion`` halts a running move where it is.
 *
 * Extends IMotion (their methods are here too).
 */
export class IRotator extends RemoteInterface {
  /**
   * Current mechanical angle in degrees (0..360).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_mechanical_angle() {
    return this._invoke("get_mechanical_angle", arguments);
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
   * Current sky position angle in degrees (0..360).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_position_angle() {
    return this._invoke("get_position_angle", arguments);
  }
  /**
   * Whether the rotator turns the other way.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<boolean>}
   */
  get_rotator_reversed() {
    return this._invoke("get_rotator_reversed", arguments);
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
   * Turn to mechanical angle ``angle`` in degrees (0..360), ignoring the sync offset.
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} angle [deg] minimum -360.0 maximum 360.0
   * @returns {Promise<null>}
   */
  move_mechanical(angle) {
    return this._invoke("move_mechanical", arguments);
  }
  /**
   * Turn to sky position angle ``angle`` in degrees (0..360).
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} angle [deg] minimum -360.0 maximum 360.0
   * @returns {Promise<null>}
   */
  move_position_angle(angle) {
    return this._invoke("move_position_angle", arguments);
  }
  /**
   * Turn by ``delta`` degrees from the current position angle (negative turns back).
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} delta [deg] minimum -360.0 maximum 360.0
   * @returns {Promise<null>}
   */
  move_position_angle_by(delta) {
    return this._invoke("move_position_angle_by", arguments);
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
   * Whether the rotator turns the other way (for optical trains that mirror the image).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {boolean} reverse
   * @returns {Promise<null>}
   */
  set_rotator_reversed(reverse) {
    return this._invoke("set_rotator_reversed", arguments);
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
IRotator.spec = {
  "methods": {
    "get_mechanical_angle": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_position_angle": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_rotator_reversed": {
      "params": [],
      "result": {
        "type": "boolean"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "move_mechanical": {
      "params": [
        {
          "name": "angle",
          "required": true,
          "schema": {
            "maximum": 360.0,
            "minimum": -360.0,
            "type": "number",
            "x-unit": "deg"
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
    "move_position_angle": {
      "params": [
        {
          "name": "angle",
          "required": true,
          "schema": {
            "maximum": 360.0,
            "minimum": -360.0,
            "type": "number",
            "x-unit": "deg"
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
    "move_position_angle_by": {
      "params": [
        {
          "name": "delta",
          "required": true,
          "schema": {
            "maximum": 360.0,
            "minimum": -360.0,
            "type": "number",
            "x-unit": "deg"
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
    "set_rotator_reversed": {
      "params": [
        {
          "name": "reverse",
          "required": true,
          "schema": {
            "type": "boolean"
          }
        }
      ],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IRotator",
  "schemas": {},
  "version": 1
};
IRotator.bases = [IMotion];
