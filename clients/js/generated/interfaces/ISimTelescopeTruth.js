// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * A German-equatorial mount passed one of its limits (on a real one, the tube met the pier).
 *
 * Attributes:
 *     time: Unix time the limit was passed.
 *     hour_angle: Hour angle of the pointing then, degrees.
 *     side: Side of the pier the mount was on.
 *     reason: Which limit, in words.
 * @typedef {{hour_angle: number, reason: string, side: PierSide, time: number}} PierCollision
 */
/**
 * Pointing state of a German-equatorial mount, as ASCOM's ``SideOfPier`` defines it.
 *
 * EAST is the normal state (the tube on the east side of the pier, looking west of the meridian);
 * WEST the through-the-pole state (tube on the west side, looking east). A mount that tracks
 * across the meridian keeps its side until it flips, so the side is not a function of hour angle.
 * @typedef {"east"|"west"|"unknown"} PierSide
 */
/**
 * Where a simulated telescope really points (pointing error, drift and periodic error included).
 */
export class ISimTelescopeTruth extends RemoteInterface {
  /**
   * Every time a German-equatorial mount passed a pier limit (none for other mounts).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Array<PierCollision>>}
   */
  get_pier_collisions() {
    return this._invoke("get_pier_collisions", arguments);
  }
  /**
   * The offset rates the mount tracks at now (arcsec/s of RA and Dec) and the moving target
   * it follows (as given to move_ephemeris; None when it follows none).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<[[number, number], object|null]>}
   */
  get_true_motion() {
    return this._invoke("get_true_motion", arguments);
  }
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
    "get_pier_collisions": {
      "params": [],
      "result": {
        "items": {
          "$ref": "#/components/schemas/PierCollision"
        },
        "type": "array"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_true_motion": {
      "params": [],
      "result": {
        "maxItems": 2,
        "minItems": 2,
        "prefixItems": [
          {
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
          {
            "anyOf": [
              {
                "additionalProperties": true,
                "type": "object"
              },
              {
                "type": "null"
              }
            ]
          }
        ],
        "type": "array"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
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
  "schemas": {
    "PierCollision": {
      "description": "A German-equatorial mount passed one of its limits (on a real one, the tube met the pier).\n\nAttributes:\n    time: Unix time the limit was passed.\n    hour_angle: Hour angle of the pointing then, degrees.\n    side: Side of the pier the mount was on.\n    reason: Which limit, in words.",
      "properties": {
        "hour_angle": {
          "title": "Hour Angle",
          "type": "number"
        },
        "reason": {
          "title": "Reason",
          "type": "string"
        },
        "side": {
          "$ref": "#/components/schemas/PierSide"
        },
        "time": {
          "title": "Time",
          "type": "number"
        }
      },
      "required": [
        "time",
        "hour_angle",
        "side",
        "reason"
      ],
      "title": "PierCollision",
      "type": "object"
    },
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
ISimTelescopeTruth.bases = [];
