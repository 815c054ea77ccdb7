// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * A model predicting the best focus from temperatures, filter, etc.
 */
export class IFocusModel extends RemoteInterface {
  /**
   * Best focus in mm for the current conditions.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_optimal_focus() {
    return this._invoke("get_optimal_focus", arguments);
  }
  /**
   * Move the focuser to the best focus for the current conditions.
   *
   * Timeout: announced, 300 clock seconds.
   * @returns {Promise<null>}
   */
  set_optimal_focus() {
    return this._invoke("set_optimal_focus", arguments);
  }
}
IFocusModel.spec = {
  "methods": {
    "get_optimal_focus": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_optimal_focus": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 300.0
      }
    }
  },
  "name": "IFocusModel",
  "schemas": {},
  "version": 1
};
IFocusModel.bases = [];
