// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * A mount that points at a moving target and follows it (non-sidereal tracking).
 */
export class INonSidereal extends RemoteInterface {
  /**
   * The offset rates (d(ra)/dt, d(dec)/dt) added to sidereal tracking now, in arcsec/s.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_tracking_rates() {
    return this._invoke("get_tracking_rates", arguments);
  }
  /**
   * Slew to the moving ``target`` (as in a task file) and follow it until the next move.
   *
   * Timeout: announced, 300 clock seconds.
   * @param {object} target
   * @returns {Promise<null>}
   */
  move_ephemeris(target) {
    return this._invoke("move_ephemeris", arguments);
  }
}
INonSidereal.spec = {
  "methods": {
    "get_tracking_rates": {
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
    },
    "move_ephemeris": {
      "params": [
        {
          "name": "target",
          "required": true,
          "schema": {
            "additionalProperties": true,
            "type": "object"
          }
        }
      ],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 300.0
      }
    }
  },
  "name": "INonSidereal",
  "schemas": {},
  "version": 1
};
INonSidereal.bases = [];
