// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Detector gain and offset (bias level), in the camera's own units.
 */
export class IGain extends RemoteInterface {
  /**
   * Current gain.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_gain() {
    return this._invoke("get_gain", arguments);
  }
  /**
   * Current offset.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_offset() {
    return this._invoke("get_offset", arguments);
  }
  /**
   * Set the gain for the next frames.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} gain minimum 0.0 maximum 1000000.0
   * @returns {Promise<null>}
   */
  set_gain(gain) {
    return this._invoke("set_gain", arguments);
  }
  /**
   * Set the offset (bias level) for the next frames.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} offset minimum -1000000.0 maximum 1000000.0
   * @returns {Promise<null>}
   */
  set_offset(offset) {
    return this._invoke("set_offset", arguments);
  }
}
IGain.spec = {
  "methods": {
    "get_gain": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_offset": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_gain": {
      "params": [
        {
          "name": "gain",
          "required": true,
          "schema": {
            "maximum": 1000000.0,
            "minimum": 0.0,
            "type": "number"
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
    },
    "set_offset": {
      "params": [
        {
          "name": "offset",
          "required": true,
          "schema": {
            "maximum": 1000000.0,
            "minimum": -1000000.0,
            "type": "number"
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
  "name": "IGain",
  "schemas": {},
  "version": 1
};
IGain.bases = [];
