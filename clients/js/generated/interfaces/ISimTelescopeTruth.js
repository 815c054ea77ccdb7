// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Where a simulated telescope really points (pointing error, drift and periodic error included).
 */
export class ISimTelescopeTruth extends RemoteInterface {
  /**
   * True ICRS (ra, dec) in degrees; get_radec() gives what the mount reports.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_true_radec() {
    return this._invoke("get_true_radec", arguments);
  }
}
ISimTelescopeTruth.spec = {
  "methods": {
    "get_true_radec": {
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
  "name": "ISimTelescopeTruth",
  "schemas": {},
  "version": 1
};
ISimTelescopeTruth.bases = [];
