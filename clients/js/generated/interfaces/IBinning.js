// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Binning factors along the detector's x and y axes.
 * @typedef {{x: number, y: number}} Binning
 */
/**
 * Pixel binning.
 */
export class IBinning extends RemoteInterface {
  /**
   * Current binning.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Binning>}
   */
  get_binning() {
    return this._invoke("get_binning", arguments);
  }
  /**
   * Binnings the camera supports.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Array<Binning>>}
   */
  list_binnings() {
    return this._invoke("list_binnings", arguments);
  }
  /**
   * Bin ``x`` by ``y`` pixels in the next frames.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} x
   * @param {number} y
   * @returns {Promise<null>}
   */
  set_binning(x, y) {
    return this._invoke("set_binning", arguments);
  }
}
IBinning.spec = {
  "methods": {
    "get_binning": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/Binning"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "list_binnings": {
      "params": [],
      "result": {
        "items": {
          "$ref": "#/components/schemas/Binning"
        },
        "type": "array"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_binning": {
      "params": [
        {
          "name": "x",
          "required": true,
          "schema": {
            "type": "integer"
          }
        },
        {
          "name": "y",
          "required": true,
          "schema": {
            "type": "integer"
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
  "name": "IBinning",
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
IBinning.bases = [];
