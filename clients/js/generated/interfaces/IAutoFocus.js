// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IAbortable } from "./IAbortable.js";

/**
 * Finding the best focus by a series of exposures.
 *
 * Extends IAbortable (their methods are here too).
 */
export class IAutoFocus extends RemoteInterface {
  /**
   * Abort the current action; the aborted call raises AbortedError.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<null>}
   */
  abort() {
    return this._invoke("abort", arguments);
  }
  /**
   * Take ``count`` images ``step`` mm apart, ``exposure_time`` s each; return (focus, error) in mm.
   *
   * Timeout: announced, 1800 clock seconds.
   * @param {number} count minimum 1 maximum 1000
   * @param {number} step [mm] exclusiveMinimum 0.0 maximum 100.0
   * @param {number} exposure_time [s] minimum 0.0 maximum 86400.0
   * @returns {Promise<[number, number]>}
   */
  auto_focus(count, step, exposure_time) {
    return this._invoke("auto_focus", arguments);
  }
  /**
   * Progress of a running focus series (free-form: e.g. step, count, last measurement).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<object>}
   */
  auto_focus_status() {
    return this._invoke("auto_focus_status", arguments);
  }
}
IAutoFocus.spec = {
  "methods": {
    "auto_focus": {
      "params": [
        {
          "name": "count",
          "required": true,
          "schema": {
            "maximum": 1000,
            "minimum": 1,
            "type": "integer"
          }
        },
        {
          "name": "step",
          "required": true,
          "schema": {
            "exclusiveMinimum": 0.0,
            "maximum": 100.0,
            "type": "number",
            "x-unit": "mm"
          }
        },
        {
          "name": "exposure_time",
          "required": true,
          "schema": {
            "maximum": 86400.0,
            "minimum": 0.0,
            "type": "number",
            "x-unit": "s"
          }
        }
      ],
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
        "announced": true,
        "seconds": 1800.0
      }
    },
    "auto_focus_status": {
      "params": [],
      "result": {
        "additionalProperties": true,
        "type": "object"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IAutoFocus",
  "schemas": {},
  "version": 1
};
IAutoFocus.bases = [IAbortable];
