// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * State of a detector's cooling.
 * @typedef {{enabled: boolean, power: number, setpoint: number, temperature?: number|null}} CoolingStatus
 */
/**
 * Detector cooling.
 */
export class ICooling extends RemoteInterface {
  /**
   * Cooling state, setpoint, power and the detector's temperature.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<CoolingStatus>}
   */
  get_cooling() {
    return this._invoke("get_cooling", arguments);
  }
  /**
   * Switch cooling on or off and set its target temperature in °C.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {boolean} enabled
   * @param {number} setpoint [degC] minimum -273.15 maximum 100.0
   * @returns {Promise<null>}
   */
  set_cooling(enabled, setpoint) {
    return this._invoke("set_cooling", arguments);
  }
}
ICooling.spec = {
  "methods": {
    "get_cooling": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/CoolingStatus"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_cooling": {
      "params": [
        {
          "name": "enabled",
          "required": true,
          "schema": {
            "type": "boolean"
          }
        },
        {
          "name": "setpoint",
          "required": true,
          "schema": {
            "maximum": 100.0,
            "minimum": -273.15,
            "type": "number",
            "x-unit": "degC"
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
  "name": "ICooling",
  "schemas": {
    "CoolingStatus": {
      "description": "State of a detector's cooling.",
      "properties": {
        "enabled": {
          "title": "Enabled",
          "type": "boolean"
        },
        "power": {
          "title": "Power",
          "type": "number"
        },
        "setpoint": {
          "title": "Setpoint",
          "type": "number"
        },
        "temperature": {
          "anyOf": [
            {
              "type": "number"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Temperature"
        }
      },
      "required": [
        "enabled",
        "setpoint",
        "power"
      ],
      "title": "CoolingStatus",
      "type": "object"
    }
  },
  "version": 1
};
ICooling.bases = [];
