// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Pointing at horizontal coordinates, without tracking.
 */
export class IPointingAltAz extends RemoteInterface {
  /**
   * Current (alt, az) in degrees.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_altaz() {
    return this._invoke("get_altaz", arguments);
  }
  /**
   * Move to altitude ``alt`` and azimuth ``az`` (degrees, azimuth east of north).
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} alt [deg] minimum -90.0 maximum 90.0
   * @param {number} az [deg] minimum -360.0 maximum 360.0
   * @returns {Promise<null>}
   */
  move_altaz(alt, az) {
    return this._invoke("move_altaz", arguments);
  }
}
IPointingAltAz.spec = {
  "methods": {
    "get_altaz": {
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
    "move_altaz": {
      "params": [
        {
          "name": "alt",
          "required": true,
          "schema": {
            "maximum": 90.0,
            "minimum": -90.0,
            "type": "number",
            "x-unit": "deg"
          }
        },
        {
          "name": "az",
          "required": true,
          "schema": {
            "maximum": 360.0,
            "minimum": -360.0,
            "type": "number",
            "x-unit": "deg"
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
  "name": "IPointingAltAz",
  "schemas": {},
  "version": 1
};
IPointingAltAz.bases = [];
