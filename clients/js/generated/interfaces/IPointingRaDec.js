// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Pointing at equatorial (ICRS) coordinates, and tracking them.
 */
export class IPointingRaDec extends RemoteInterface {
  /**
   * Current (ra, dec) in degrees.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_radec() {
    return this._invoke("get_radec", arguments);
  }
  /**
   * Slew to right ascension ``ra`` and declination ``dec`` (degrees) and track.
   *
   * Timeout: announced, 300 clock seconds.
   * @param {number} ra [deg] minimum 0.0 exclusiveMaximum 360.0
   * @param {number} dec [deg] minimum -90.0 maximum 90.0
   * @returns {Promise<null>}
   */
  move_radec(ra, dec) {
    return this._invoke("move_radec", arguments);
  }
}
IPointingRaDec.spec = {
  "methods": {
    "get_radec": {
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
    "move_radec": {
      "params": [
        {
          "name": "ra",
          "required": true,
          "schema": {
            "exclusiveMaximum": 360.0,
            "minimum": 0.0,
            "type": "number",
            "x-unit": "deg"
          }
        },
        {
          "name": "dec",
          "required": true,
          "schema": {
            "maximum": 90.0,
            "minimum": -90.0,
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
  "name": "IPointingRaDec",
  "schemas": {},
  "version": 1
};
IPointingRaDec.bases = [];
