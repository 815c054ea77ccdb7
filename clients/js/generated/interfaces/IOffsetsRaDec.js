// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Offsets along the RA and Dec axes, added to the target position (guiding, acquisition).
 */
export class IOffsetsRaDec extends RemoteInterface {
  /**
   * Current (dra, ddec) offsets in degrees.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[number, number]>}
   */
  get_offsets_radec() {
    return this._invoke("get_offsets_radec", arguments);
  }
  /**
   * Set the offsets along the RA axis (not scaled by cos dec) and Dec axis, in degrees.
   *
   * Timeout: announced, 60 clock seconds.
   * @param {number} dra [deg]
   * @param {number} ddec [deg]
   * @returns {Promise<null>}
   */
  set_offsets_radec(dra, ddec) {
    return this._invoke("set_offsets_radec", arguments);
  }
}
IOffsetsRaDec.spec = {
  "methods": {
    "get_offsets_radec": {
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
    "set_offsets_radec": {
      "params": [
        {
          "name": "dra",
          "required": true,
          "schema": {
            "type": "number",
            "x-unit": "deg"
          }
        },
        {
          "name": "ddec",
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
  "name": "IOffsetsRaDec",
  "schemas": {},
  "version": 1
};
IOffsetsRaDec.bases = [];
