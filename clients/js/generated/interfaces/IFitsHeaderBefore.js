// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Provides header cards at the start of an exposure (e.g. telescope position).
 *
 * ``namespaces`` (here and in IFitsHeaderAfter) are the groups of cards a caller wants, pyobs'
 * convention (a camera may ask by name); None for all. nightcrew's cameras ask with None, and
 * nightcrew's providers give all their cards whatever it says.
 */
export class IFitsHeaderBefore extends RemoteInterface {
  /**
   * Keyword → (value, comment); ``namespaces``: card groups (None: all; see IFitsHeaderBefore).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {Array<string>|null} [namespaces] default null
   * @returns {Promise<Object<string, [boolean|number|number|string|null, string]>>}
   */
  get_fits_header_before(namespaces) {
    return this._invoke("get_fits_header_before", arguments);
  }
}
IFitsHeaderBefore.spec = {
  "methods": {
    "get_fits_header_before": {
      "params": [
        {
          "name": "namespaces",
          "required": false,
          "schema": {
            "anyOf": [
              {
                "items": {
                  "type": "string"
                },
                "type": "array"
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
        "additionalProperties": {
          "maxItems": 2,
          "minItems": 2,
          "prefixItems": [
            {
              "anyOf": [
                {
                  "type": "boolean"
                },
                {
                  "type": "integer"
                },
                {
                  "type": "number"
                },
                {
                  "type": "string"
                },
                {
                  "type": "null"
                }
              ]
            },
            {
              "type": "string"
            }
          ],
          "type": "array"
        },
        "type": "object"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IFitsHeaderBefore",
  "schemas": {},
  "version": 1
};
IFitsHeaderBefore.bases = [];
