// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * The best focus of a simulated focuser now (it drifts with temperature).
 */
export class ISimFocuserTruth extends RemoteInterface {
  /**
   * Position in mm at which stars are sharpest now; compare with get_focus() + offset.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_best_focus() {
    return this._invoke("get_best_focus", arguments);
  }
}
ISimFocuserTruth.spec = {
  "methods": {
    "get_best_focus": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "ISimFocuserTruth",
  "schemas": {},
  "version": 1
};
ISimFocuserTruth.bases = [];
