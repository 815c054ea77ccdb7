// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IRunning } from "./IRunning.js";

/**
 * A continuous activity (a loop) that can be started and stopped.
 *
 * Extends IRunning (their methods are here too).
 */
export class IStartStop extends RemoteInterface {
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
IStartStop.spec = {
  "methods": {
    "start": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "stop": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IStartStop",
  "schemas": {},
  "version": 1
};
IStartStop.bases = [IRunning];
