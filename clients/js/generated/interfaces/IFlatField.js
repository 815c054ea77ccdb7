// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IAbortable } from "./IAbortable.js";

/**
 * Binning factors along the detector's x and y axes.
 * @typedef {{x: number, y: number}} Binning
 */
/**
 * Taking flat fields (twilight or dome).
 *
 * Extends IAbortable (their methods are here too).
 */
export class IFlatField extends RemoteInterface {
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
   * Take ``count`` flats (binning, filter_name None: current); return (frames, total exposure s).
   *
   * Timeout: announced, 3600 clock seconds.
   * @param {number} count
   * @param {Binning|null} [binning] default null
   * @param {string|null} [filter_name] default null
   * @returns {Promise<[number, number]>}
   */
  flat_field(count, binning, filter_name) {
    return this._invoke("flat_field", arguments);
  }
}
IFlatField.spec = {
  "methods": {
    "flat_field": {
      "params": [
        {
          "name": "count",
          "required": true,
          "schema": {
            "type": "integer"
          }
        },
        {
          "name": "binning",
          "required": false,
          "schema": {
            "anyOf": [
              {
                "$ref": "#/components/schemas/Binning"
              },
              {
                "type": "null"
              }
            ],
            "default": null
          }
        },
        {
          "name": "filter_name",
          "required": false,
          "schema": {
            "anyOf": [
              {
                "type": "string"
              },
              {
                "type": "null"
              }
            ],
            "default": null
          }
        }
      ],
      "result": {
        "maxItems": 2,
        "minItems": 2,
        "prefixItems": [
          {
            "type": "integer"
          },
          {
            "type": "number"
          }
        ],
        "type": "array"
      },
      "timeout": {
        "announced": true,
        "seconds": 3600.0
      }
    }
  },
  "name": "IFlatField",
  "schemas": {
    "Binning": {
      "description": "Binning factors along the detector's x and y axes.",
      "properties": {
        "x": {
          "title": "X",
          "type": "integer"
        },
        "y": {
          "title": "Y",
          "type": "integer"
        }
      },
      "required": [
        "x",
        "y"
      ],
      "title": "Binning",
      "type": "object"
    }
  },
  "version": 1
};
IFlatField.bases = [IAbortable];
