// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Lifecycle state of a module.
 * @typedef {"starting"|"ready"|"error"|"closing"|"closed"} ModuleState
 */
/**
 * A module: the one interface every module offers.
 */
export class IModule extends RemoteInterface {
  /**
   * Why the module is in error state; empty if it is not.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<string>}
   */
  get_error_string() {
    return this._invoke("get_error_string", arguments);
  }
  /**
   * Human-readable name of the module.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<string>}
   */
  get_label() {
    return this._invoke("get_label", arguments);
  }
  /**
   * Current lifecycle state.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<ModuleState>}
   */
  get_state() {
    return this._invoke("get_state", arguments);
  }
  /**
   * Software version of the module (nightcrew's version unless the module says otherwise).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<string>}
   */
  get_version() {
    return this._invoke("get_version", arguments);
  }
  /**
   * Try to leave error state; True if the module is ready afterwards.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<boolean>}
   */
  reset_error() {
    return this._invoke("reset_error", arguments);
  }
}
IModule.spec = {
  "methods": {
    "get_error_string": {
      "params": [],
      "result": {
        "type": "string"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_label": {
      "params": [],
      "result": {
        "type": "string"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_state": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/ModuleState"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_version": {
      "params": [],
      "result": {
        "type": "string"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "reset_error": {
      "params": [],
      "result": {
        "type": "boolean"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IModule",
  "schemas": {
    "ModuleState": {
      "description": "Lifecycle state of a module.",
      "enum": [
        "starting",
        "ready",
        "error",
        "closing",
        "closed"
      ],
      "title": "ModuleState",
      "type": "string"
    }
  },
  "version": 1
};
IModule.bases = [];
