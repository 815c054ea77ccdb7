// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * One switch of a switch device.
 *
 * An on/off switch has ``min_value`` 0, ``max_value`` 1 and ``step`` 1; an analog one (a dew
 * heater's power, a dimmer) any range, set in multiples of ``step`` from ``min_value``.
 * @typedef {{can_write: boolean, description: string, index: number, max_value: number, min_value: number, name: string, step: number}} SwitchInfo
 */
/**
 * A device with numbered switches, each with a value between its min and max (on/off = 1/0).
 *
 * ``switch`` in every method is a switch's index: its position in :meth:`get_switches`, from 0.
 */
export class ISwitch extends RemoteInterface {
  /**
   * Whether switch ``switch`` is on (its value is above its minimum).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} switch_ minimum 0 maximum 1000000
   * @returns {Promise<boolean>}
   */
  get_switch(switch_) {
    return this._invoke("get_switch", arguments);
  }
  /**
   * Value of switch ``switch``, between its min_value and max_value.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} switch_ minimum 0 maximum 1000000
   * @returns {Promise<number>}
   */
  get_switch_value(switch_) {
    return this._invoke("get_switch_value", arguments);
  }
  /**
   * Every switch of the device, in index order.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Array<SwitchInfo>>}
   */
  get_switches() {
    return this._invoke("get_switches", arguments);
  }
  /**
   * Turn switch ``switch`` on (its maximum) or off (its minimum).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} switch_ minimum 0 maximum 1000000
   * @param {boolean} state
   * @returns {Promise<null>}
   */
  set_switch(switch_, state) {
    return this._invoke("set_switch", arguments);
  }
  /**
   * Set switch ``switch`` to ``value`` (within min..max, a multiple of step from min).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {number} switch_ minimum 0 maximum 1000000
   * @param {number} value
   * @returns {Promise<null>}
   */
  set_switch_value(switch_, value) {
    return this._invoke("set_switch_value", arguments);
  }
}
ISwitch.spec = {
  "methods": {
    "get_switch": {
      "params": [
        {
          "name": "switch",
          "required": true,
          "schema": {
            "maximum": 1000000,
            "minimum": 0,
            "type": "integer"
          }
        }
      ],
      "result": {
        "type": "boolean"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_switch_value": {
      "params": [
        {
          "name": "switch",
          "required": true,
          "schema": {
            "maximum": 1000000,
            "minimum": 0,
            "type": "integer"
          }
        }
      ],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_switches": {
      "params": [],
      "result": {
        "items": {
          "$ref": "#/components/schemas/SwitchInfo"
        },
        "type": "array"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_switch": {
      "params": [
        {
          "name": "switch",
          "required": true,
          "schema": {
            "maximum": 1000000,
            "minimum": 0,
            "type": "integer"
          }
        },
        {
          "name": "state",
          "required": true,
          "schema": {
            "type": "boolean"
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
    "set_switch_value": {
      "params": [
        {
          "name": "switch",
          "required": true,
          "schema": {
            "maximum": 1000000,
            "minimum": 0,
            "type": "integer"
          }
        },
        {
          "name": "value",
          "required": true,
          "schema": {
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
  "name": "ISwitch",
  "schemas": {
    "SwitchInfo": {
      "description": "One switch of a switch device.\n\nAn on/off switch has ``min_value`` 0, ``max_value`` 1 and ``step`` 1; an analog one (a dew\nheater's power, a dimmer) any range, set in multiples of ``step`` from ``min_value``.",
      "properties": {
        "can_write": {
          "title": "Can Write",
          "type": "boolean"
        },
        "description": {
          "title": "Description",
          "type": "string"
        },
        "index": {
          "title": "Index",
          "type": "integer"
        },
        "max_value": {
          "title": "Max Value",
          "type": "number"
        },
        "min_value": {
          "title": "Min Value",
          "type": "number"
        },
        "name": {
          "title": "Name",
          "type": "string"
        },
        "step": {
          "title": "Step",
          "type": "number"
        }
      },
      "required": [
        "index",
        "name",
        "description",
        "can_write",
        "min_value",
        "max_value",
        "step"
      ],
      "title": "SwitchInfo",
      "type": "object"
    }
  },
  "version": 1
};
ISwitch.bases = [];
