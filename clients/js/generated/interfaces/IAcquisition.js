// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IAbortable } from "./IAbortable.js";
import { IRunning } from "./IRunning.js";

/**
 * Centring the current target on the detector by iterated exposures and offsets.
 *
 * Extends IAbortable, IRunning (their methods are here too).
 */
export class IAcquisition extends RemoteInterface {
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
   * Acquire the target; return what was done (e.g. final offsets in degrees, iterations).
   *
   * Timeout: announced, 600 clock seconds.
   * @returns {Promise<object>}
   */
  acquire_target() {
    return this._invoke("acquire_target", arguments);
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
}
IAcquisition.spec = {
  "methods": {
    "acquire_target": {
      "params": [],
      "result": {
        "additionalProperties": true,
        "type": "object"
      },
      "timeout": {
        "announced": true,
        "seconds": 600.0
      }
    }
  },
  "name": "IAcquisition",
  "schemas": {},
  "version": 1
};
IAcquisition.bases = [IAbortable, IRunning];
