// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Runs observing scripts given as text.
 */
export class IScriptRunner extends RemoteInterface {
  /**
   * Run ``script`` (the YAML configuration of a script) and return when it ends.
   *
   * Timeout: announced, 3600 clock seconds.
   * @param {string} script
   * @returns {Promise<null>}
   */
  run_script(script) {
    return this._invoke("run_script", arguments);
  }
}
IScriptRunner.spec = {
  "methods": {
    "run_script": {
      "params": [
        {
          "name": "script",
          "required": true,
          "schema": {
            "type": "string"
          }
        }
      ],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": true,
        "seconds": 3600.0
      }
    }
  },
  "name": "IScriptRunner",
  "schemas": {},
  "version": 1
};
IScriptRunner.bases = [];
