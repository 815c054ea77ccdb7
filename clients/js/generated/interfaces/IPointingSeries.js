// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IAbortable } from "./IAbortable.js";

/**
 * Measuring a pointing model by solving images across the sky.
 *
 * Extends IAbortable (their methods are here too).
 */
export class IPointingSeries extends RemoteInterface {
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
   * Run a pointing series and return the VFS path of the measured positions.
   *
   * Timeout: announced, 7200 clock seconds.
   * @returns {Promise<string>}
   */
  start_pointing_series() {
    return this._invoke("start_pointing_series", arguments);
  }
}
IPointingSeries.spec = {
  "methods": {
    "start_pointing_series": {
      "params": [],
      "result": {
        "type": "string"
      },
      "timeout": {
        "announced": true,
        "seconds": 7200.0
      }
    }
  },
  "name": "IPointingSeries",
  "schemas": {},
  "version": 1
};
IPointingSeries.bases = [IAbortable];
