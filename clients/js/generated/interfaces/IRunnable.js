// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IAbortable } from "./IAbortable.js";

/**
 * A finite action that runs to its end when asked.
 *
 * Extends IAbortable (their methods are here too).
 */
export class IRunnable extends RemoteInterface {
  /**
   * Abort the current action; the aborted call raises AbortedError.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<null>}
   */
  abort() {
    return this._invoke("abort", arguments);
  }
  /**
   * Run the action and return when it is done.
   *
   * Timeout: announced, 3600 clock seconds.
   * @returns {Promise<null>}
   */
  run() {
    return this._invoke("run", arguments);
  }
}
IRunnable.spec = {
  "methods": {
    "run": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 3600.0
      }
    }
  },
  "name": "IRunnable",
  "schemas": {},
  "version": 1
};
IRunnable.bases = [IAbortable];
