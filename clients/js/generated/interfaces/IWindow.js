// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * A detector region in unbinned pixels; left/top are 0-based.
 * @typedef {{height: number, left: number, top: number, width: number}} Window
 */
/**
 * Reading out a sub-frame of the detector.
 */
export class IWindow extends RemoteInterface {
  /**
   * The whole detector.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Window>}
   */
  get_full_frame() {
    return this._invoke("get_full_frame", arguments);
  }
  /**
   * Region read out in the next frames.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Window>}
   */
  get_window() {
    return this._invoke("get_window", arguments);
  }
  /**
   * Read out only this region (unbinned pixels, 0-based) in the next frames.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} left
   * @param {number} top
   * @param {number} width
   * @param {number} height
   * @returns {Promise<null>}
   */
  set_window(left, top, width, height) {
    return this._invoke("set_window", arguments);
  }
}
IWindow.spec = {
  "methods": {
    "get_full_frame": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/Window"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_window": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/Window"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_window": {
      "params": [
        {
          "name": "left",
          "required": true,
          "schema": {
            "type": "integer"
          }
        },
        {
          "name": "top",
          "required": true,
          "schema": {
            "type": "integer"
          }
        },
        {
          "name": "width",
          "required": true,
          "schema": {
            "type": "integer"
          }
        },
        {
          "name": "height",
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
  "name": "IWindow",
  "schemas": {
    "Window": {
      "description": "A detector region in unbinned pixels; left/top are 0-based.",
      "properties": {
        "height": {
          "title": "Height",
          "type": "integer"
        },
        "left": {
          "title": "Left",
          "type": "integer"
        },
        "top": {
          "title": "Top",
          "type": "integer"
        },
        "width": {
          "title": "Width",
          "type": "integer"
        }
      },
      "required": [
        "left",
        "top",
        "width",
        "height"
      ],
      "title": "Window",
      "type": "object"
    }
  },
  "version": 1
};
IWindow.bases = [];
