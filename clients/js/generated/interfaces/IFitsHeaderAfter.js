// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Provides header cards at the end of an exposure (e.g. averages over the exposure).
 */
export class IFitsHeaderAfter extends RemoteInterface {
  /**
   * Keyword → (value, comment); ``namespaces``: card groups (None: all; see IFitsHeaderBefore).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {Array<string>|null} [namespaces] default null
   * @returns {Promise<Object<string, [boolean|number|number|string|null, string]>>}
   */
  get_fits_header_after(namespaces) {
    return this._invoke("get_fits_header_after", arguments);
  }
}
IFitsHeaderAfter.spec = {
  "methods": {
    "get_fits_header_after": {
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
  "name": "IFitsHeaderAfter",
  "schemas": {},
  "version": 1
};
IFitsHeaderAfter.bases = [];
