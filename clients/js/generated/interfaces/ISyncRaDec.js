// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Telling a mount where it really points (e.g. after a plate solve), so it corrects itself.
 */
export class ISyncRaDec extends RemoteInterface {
  /**
   * The mount points at ICRS (``ra``, ``dec``) degrees now; it must be tracking.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} ra [deg] minimum 0.0 exclusiveMaximum 360.0
   * @param {number} dec [deg] minimum -90.0 maximum 90.0
   * @returns {Promise<null>}
   */
  sync_radec(ra, dec) {
    return this._invoke("sync_radec", arguments);
  }
}
ISyncRaDec.spec = {
  "methods": {
    "sync_radec": {
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
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "ISyncRaDec",
  "schemas": {},
  "version": 1
};
ISyncRaDec.bases = [];
