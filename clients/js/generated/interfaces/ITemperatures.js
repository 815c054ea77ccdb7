// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * A device with thermometers (detector, mirror, focuser, ...), e.g. for focus models and FITS headers.
 */
export class ITemperatures extends RemoteInterface {
  /**
   * Sensor name → temperature in °C.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Object<string, number>>}
   */
  get_temperatures() {
    return this._invoke("get_temperatures", arguments);
  }
}
ITemperatures.spec = {
  "methods": {
    "get_temperatures": {
      "params": [],
      "result": {
        "additionalProperties": {
          "type": "number"
        },
        "type": "object"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "ITemperatures",
  "schemas": {},
  "version": 1
};
ITemperatures.bases = [];
