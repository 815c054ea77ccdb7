// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * What a simulated sky is like, beyond what weather sensors report.
 */
export class ISimWeatherTruth extends RemoteInterface {
  /**
   * Fraction of the sky covered by clouds now (0..1).
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_cloud_cover() {
    return this._invoke("get_cloud_cover", arguments);
  }
}
ISimWeatherTruth.spec = {
  "methods": {
    "get_cloud_cover": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "ISimWeatherTruth",
  "schemas": {},
  "version": 1
};
ISimWeatherTruth.bases = [];
