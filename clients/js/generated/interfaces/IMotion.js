// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IReady } from "./IReady.js";

/**
 * What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.
 * @typedef {"parked"|"initializing"|"idle"|"slewing"|"tracking"|"moving"|"parking"|"aborting"|"error"|"unknown"} MotionStatus
 */
/**
 * A device that can be initialised, parked and stopped, and reports its motion status.
 *
 * A module may drive several devices (e.g. a mount and its focuser, or a dome: its ``azimuth``
 * rotation beside the shutter); ``device`` then names one of them, and None (or a name the module
 * does not have) means the module as a whole.
 *
 * Extends IReady (their methods are here too).
 */
export class IMotion extends RemoteInterface {
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
IMotion.spec = {
  "methods": {
    "get_motion_status": {
      "params": [
        {
          "name": "device",
          "required": false,
          "schema": {
            "anyOf": [
              {
                "type": "string"
              },
              {
                "type": "null"
              }
            ],
            "default": null
          }
        }
      ],
      "result": {
        "$ref": "#/components/schemas/MotionStatus"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "init": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 300.0
      }
    },
    "park": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 300.0
      }
    },
    "stop_motion": {
      "params": [
        {
          "name": "device",
          "required": false,
          "schema": {
            "anyOf": [
              {
                "type": "string"
              },
              {
                "type": "null"
              }
            ],
            "default": null
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
  "name": "IMotion",
  "schemas": {
    "MotionStatus": {
      "description": "What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.",
      "enum": [
        "parked",
        "initializing",
        "idle",
        "slewing",
        "tracking",
        "moving",
        "parking",
        "aborting",
        "error",
        "unknown"
      ],
      "title": "MotionStatus",
      "type": "string"
    }
  },
  "version": 1
};
IMotion.bases = [IReady];
