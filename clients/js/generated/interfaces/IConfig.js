// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Configuration options that can be read or changed while the module runs.
 */
export class IConfig extends RemoteInterface {
  /**
   * Option name → (has getter, has setter, has a list of allowed values).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Object<string, [boolean, boolean, boolean]>>}
   */
  get_config_caps() {
    return this._invoke("get_config_caps", arguments);
  }
  /**
   * Current value of option ``name`` (a name from :meth:`get_config_caps`).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {string} name
   * @returns {Promise<*>}
   */
  get_config_value(name) {
    return this._invoke("get_config_value", arguments);
  }
  /**
   * Allowed values of option ``name``.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {string} name
   * @returns {Promise<Array<string>>}
   */
  get_config_value_options(name) {
    return this._invoke("get_config_value_options", arguments);
  }
  /**
   * Set option ``name`` to ``value``.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {string} name
   * @param {*} value
   * @returns {Promise<null>}
   */
  set_config_value(name, value) {
    return this._invoke("set_config_value", arguments);
  }
}
IConfig.spec = {
  "methods": {
    "get_config_caps": {
      "params": [],
      "result": {
        "additionalProperties": {
          "maxItems": 3,
          "minItems": 3,
          "prefixItems": [
            {
              "type": "boolean"
            },
            {
              "type": "boolean"
            },
            {
              "type": "boolean"
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
    },
    "get_config_value": {
      "params": [
        {
          "name": "name",
          "required": true,
          "schema": {
            "type": "string"
          }
        }
      ],
      "result": {},
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_config_value_options": {
      "params": [
        {
          "name": "name",
          "required": true,
          "schema": {
            "type": "string"
          }
        }
      ],
      "result": {
        "items": {
          "type": "string"
        },
        "type": "array"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_config_value": {
      "params": [
        {
          "name": "name",
          "required": true,
          "schema": {
            "type": "string"
          }
        },
        {
          "name": "value",
          "required": true,
          "schema": {}
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
  "name": "IConfig",
  "schemas": {},
  "version": 1
};
IConfig.bases = [];
