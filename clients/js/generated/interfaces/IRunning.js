// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * The module has an activity that may be running.
 */
export class IRunning extends RemoteInterface {
  /**
   * Whether the activity is running.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<boolean>}
   */
  is_running() {
    return this._invoke("is_running", arguments);
  }
}
IRunning.spec = {
  "methods": {
    "is_running": {
      "params": [],
      "result": {
        "type": "boolean"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IRunning",
  "schemas": {},
  "version": 1
};
IRunning.bases = [];
