// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * A module that may act on its own (mastermind, scheduler); others yield to it.
 */
export class IAutonomous extends RemoteInterface {
  /**
   * Whether the module is currently acting on its own.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<boolean>}
   */
  is_autonomous() {
    return this._invoke("is_autonomous", arguments);
  }
}
IAutonomous.spec = {
  "methods": {
    "is_autonomous": {
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
  "name": "IAutonomous",
  "schemas": {},
  "version": 1
};
IAutonomous.bases = [];
