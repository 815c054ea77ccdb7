// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Pointing state of a German-equatorial mount, as ASCOM's ``SideOfPier`` defines it.
 *
 * EAST is the normal state (the tube on the east side of the pier, looking west of the meridian);
 * WEST the through-the-pole state (tube on the west side, looking east). A mount that tracks
 * across the meridian keeps its side until it flips, so the side is not a function of hour angle.
 * @typedef {"east"|"west"|"unknown"} PierSide
 */
/**
 * The pointing state of a German-equatorial mount (see :class:`PierSide`).
 */
export class IPierSide extends RemoteInterface {
  /**
   * The side a slew to ICRS (``ra``, ``dec``) degrees would end on now (UNKNOWN if it cannot tell).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} ra [deg] minimum 0.0 exclusiveMaximum 360.0
   * @param {number} dec [deg] minimum -90.0 maximum 90.0
   * @returns {Promise<PierSide>}
   */
  get_destination_pier_side(ra, dec) {
    return this._invoke("get_destination_pier_side", arguments);
  }
  /**
   * The side of the pier the mount is on now (UNKNOWN if it cannot tell).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<PierSide>}
   */
  get_pier_side() {
    return this._invoke("get_pier_side", arguments);
  }
}
IPierSide.spec = {
  "methods": {
    "get_destination_pier_side": {
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
        "$ref": "#/components/schemas/PierSide"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_pier_side": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/PierSide"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IPierSide",
  "schemas": {
    "PierSide": {
      "description": "Pointing state of a German-equatorial mount, as ASCOM's ``SideOfPier`` defines it.\n\nEAST is the normal state (the tube on the east side of the pier, looking west of the meridian);\nWEST the through-the-pole state (tube on the west side, looking east). A mount that tracks\nacross the meridian keeps its side until it flips, so the side is not a function of hour angle.",
      "enum": [
        "east",
        "west",
        "unknown"
      ],
      "title": "PierSide",
      "type": "string"
    }
  },
  "version": 1
};
IPierSide.bases = [];
