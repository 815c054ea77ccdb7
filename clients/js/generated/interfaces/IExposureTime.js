// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * A settable exposure time.
 */
export class IExposureTime extends RemoteInterface {
  /**
   * Exposure time in seconds.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_exposure_time() {
    return this._invoke("get_exposure_time", arguments);
  }
  /**
   * Seconds left in the current exposure; 0 when not exposing.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_exposure_time_left() {
    return this._invoke("get_exposure_time_left", arguments);
  }
  /**
   * Set the exposure time in seconds for the next frames (up to the camera's maximum).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} exposure_time [s] minimum 0.0 maximum 86400.0
   * @returns {Promise<null>}
   */
  set_exposure_time(exposure_time) {
    return this._invoke("set_exposure_time", arguments);
  }
}
IExposureTime.spec = {
  "methods": {
    "get_exposure_time": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_exposure_time_left": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_exposure_time": {
      "params": [
        {
          "name": "exposure_time",
          "required": true,
          "schema": {
            "maximum": 86400.0,
            "minimum": 0.0,
            "type": "number",
            "x-unit": "s"
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
  "name": "IExposureTime",
  "schemas": {},
  "version": 1
};
IExposureTime.bases = [];
