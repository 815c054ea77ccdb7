// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * The positions a focuser can reach (a focus series keeps within them).
 */
export class IFocusRange extends RemoteInterface {
  /**
   * Lowest and highest reachable position (base + offset) in mm.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_focus_range() {
    return this._invoke("get_focus_range", arguments);
  }
}
IFocusRange.spec = {
  "methods": {
    "get_focus_range": {
      "params": [],
      "result": {
        "maxItems": 2,
        "minItems": 2,
        "prefixItems": [
          {
            "type": "number"
          },
          {
            "type": "number"
          }
        ],
        "type": "array"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IFocusRange",
  "schemas": {},
  "version": 1
};
IFocusRange.bases = [];
