// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Offsets along the altitude and azimuth axes, added to the target position.
 */
export class IOffsetsAltAz extends RemoteInterface {
  /**
   * Current (dalt, daz) offsets in degrees.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_offsets_altaz() {
    return this._invoke("get_offsets_altaz", arguments);
  }
  /**
   * Set the offsets along the altitude and azimuth axes, in degrees.
   *
   * Timeout: announced, 60 clock seconds.
   * @param {number} dalt [deg]
   * @param {number} daz [deg]
   * @returns {Promise<null>}
   */
  set_offsets_altaz(dalt, daz) {
    return this._invoke("set_offsets_altaz", arguments);
  }
}
IOffsetsAltAz.spec = {
  "methods": {
    "get_offsets_altaz": {
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
    "set_offsets_altaz": {
      "params": [
        {
          "name": "dalt",
          "required": true,
          "schema": {
            "type": "number",
            "x-unit": "deg"
          }
        },
        {
          "name": "daz",
          "required": true,
          "schema": {
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
        "seconds": 60.0
      }
    }
  },
  "name": "IOffsetsAltAz",
  "schemas": {},
  "version": 1
};
IOffsetsAltAz.bases = [];
