// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * What a flat-field light source is doing.
 * @typedef {"not_present"|"off"|"not_ready"|"ready"|"unknown"|"error"} CalibratorState
 */
/**
 * Where a telescope cover is.
 * @typedef {"not_present"|"closed"|"moving"|"open"|"unknown"|"error"} CoverState
 */
/**
 * A cover in front of the telescope and/or a light for flat fields (a flip-flat, a dome panel).
 *
 * A part the device does not have reports NOT_PRESENT and refuses to be driven.
 */
export class ICoverCalibrator extends RemoteInterface {
  /**
   * Switch the light off; return when it is off.
   *
   * Timeout: announced, 60 clock seconds.
   * @returns {Promise<null>}
   */
  calibrator_off() {
    return this._invoke("calibrator_off", arguments);
  }
  /**
   * Switch the light on at ``brightness`` (0..max brightness); return when it is stable.
   *
   * Timeout: announced, 120 clock seconds.
   * @param {number} brightness
   * @returns {Promise<null>}
   */
  calibrator_on(brightness) {
    return this._invoke("calibrator_on", arguments);
  }
  /**
   * Close the cover; return when it is closed.
   *
   * Timeout: announced, 120 clock seconds.
   * @returns {Promise<null>}
   */
  close_cover() {
    return this._invoke("close_cover", arguments);
  }
  /**
   * Current brightness of the light, 0 when off.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_brightness() {
    return this._invoke("get_brightness", arguments);
  }
  /**
   * What the light is doing.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<CalibratorState>}
   */
  get_calibrator_state() {
    return this._invoke("get_calibrator_state", arguments);
  }
  /**
   * Where the cover is.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<CoverState>}
   */
  get_cover_state() {
    return this._invoke("get_cover_state", arguments);
  }
  /**
   * Highest brightness the light can be set to.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_max_brightness() {
    return this._invoke("get_max_brightness", arguments);
  }
  /**
   * Stop a moving cover where it is.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<null>}
   */
  halt_cover() {
    return this._invoke("halt_cover", arguments);
  }
  /**
   * Open the cover; return when it is open.
   *
   * Timeout: announced, 120 clock seconds.
   * @returns {Promise<null>}
   */
  open_cover() {
    return this._invoke("open_cover", arguments);
  }
}
ICoverCalibrator.spec = {
  "methods": {
    "calibrator_off": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 60.0
      }
    },
    "calibrator_on": {
      "params": [
        {
          "name": "brightness",
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
        "announced": true,
        "seconds": 120.0
      }
    },
    "close_cover": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 120.0
      }
    },
    "get_brightness": {
      "params": [],
      "result": {
        "type": "integer"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_calibrator_state": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/CalibratorState"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_cover_state": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/CoverState"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_max_brightness": {
      "params": [],
      "result": {
        "type": "integer"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "halt_cover": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "open_cover": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 120.0
      }
    }
  },
  "name": "ICoverCalibrator",
  "schemas": {
    "CalibratorState": {
      "description": "What a flat-field light source is doing.",
      "enum": [
        "not_present",
        "off",
        "not_ready",
        "ready",
        "unknown",
        "error"
      ],
      "title": "CalibratorState",
      "type": "string"
    },
    "CoverState": {
      "description": "Where a telescope cover is.",
      "enum": [
        "not_present",
        "closed",
        "moving",
        "open",
        "unknown",
        "error"
      ],
      "title": "CoverState",
      "type": "string"
    }
  },
  "version": 1
};
ICoverCalibrator.bases = [];
