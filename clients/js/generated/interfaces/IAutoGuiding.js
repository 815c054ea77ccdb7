// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IExposureTime } from "./IExposureTime.js";
import { IStartStop } from "./IStartStop.js";

/**
 * State of a closed-loop controller such as auto-guiding.
 * @typedef {"stopped"|"acquiring"|"closed"|"lost"} LoopState
 */
/**
 * Closed-loop guiding on a guide camera; start/stop open and close the loop.
 *
 * Extends IExposureTime, IStartStop (their methods are here too).
 */
export class IAutoGuiding extends RemoteInterface {
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
   * State of the guiding loop.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<LoopState>}
   */
  get_loop_state() {
    return this._invoke("get_loop_state", arguments);
  }
  /**
   * Whether the activity is running.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<boolean>}
   */
  is_running() {
    return this._invoke("is_running", arguments);
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
  /**
   * Start the activity; returns once it started.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<null>}
   */
  start() {
    return this._invoke("start", arguments);
  }
  /**
   * Stop the activity; returns once it stopped.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<null>}
   */
  stop() {
    return this._invoke("stop", arguments);
  }
}
IAutoGuiding.spec = {
  "methods": {
    "get_loop_state": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/LoopState"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IAutoGuiding",
  "schemas": {
    "LoopState": {
      "description": "State of a closed-loop controller such as auto-guiding.",
      "enum": [
        "stopped",
        "acquiring",
        "closed",
        "lost"
      ],
      "title": "LoopState",
      "type": "string"
    }
  },
  "version": 1
};
IAutoGuiding.bases = [IExposureTime, IStartStop];
