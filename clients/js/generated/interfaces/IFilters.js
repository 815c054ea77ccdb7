// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IMotion } from "./IMotion.js";

/**
 * What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.
 * @typedef {"parked"|"initializing"|"idle"|"slewing"|"tracking"|"moving"|"parking"|"aborting"|"error"|"unknown"} MotionStatus
 */
/**
 * A filter wheel (or slide) with named filters.
 *
 * Extends IMotion (their methods are here too).
 */
export class IFilters extends RemoteInterface {
  /**
   * Name of the filter in the beam.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<string>}
   */
  get_filter() {
    return this._invoke("get_filter", arguments);
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
   * Names of the available filters.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Array<string>>}
   */
  list_filters() {
    return this._invoke("list_filters", arguments);
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
   * Move filter ``filter_name`` into the beam.
   *
   * Timeout: announced, 120 clock seconds.
   * @param {string} filter_name
   * @returns {Promise<null>}
   */
  set_filter(filter_name) {
    return this._invoke("set_filter", arguments);
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
IFilters.spec = {
  "methods": {
    "get_filter": {
      "params": [],
      "result": {
        "type": "string"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "list_filters": {
      "params": [],
      "result": {
        "items": {
          "type": "string"
        },
        "type": "array"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_filter": {
      "params": [
        {
          "name": "filter_name",
          "required": true,
          "schema": {
            "type": "string"
          }
        }
      ],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 120.0
      }
    }
  },
  "name": "IFilters",
  "schemas": {},
  "version": 1
};
IFilters.bases = [IMotion];
