// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * What a camera or spectrograph is doing.
 * @typedef {"idle"|"exposing"|"readout"|"error"} ExposureStatus
 */
/**
 * A device whose exposures can be watched while they run.
 */
export class IExposure extends RemoteInterface {
  /**
   * Progress of the current exposure in percent (0-100); 0 when idle.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<number>}
   */
  get_exposure_progress() {
    return this._invoke("get_exposure_progress", arguments);
  }
  /**
   * What the device is doing now.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<ExposureStatus>}
   */
  get_exposure_status() {
    return this._invoke("get_exposure_status", arguments);
  }
}
IExposure.spec = {
  "methods": {
    "get_exposure_progress": {
      "params": [],
      "result": {
        "type": "number"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_exposure_status": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/ExposureStatus"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IExposure",
  "schemas": {
    "ExposureStatus": {
      "description": "What a camera or spectrograph is doing.",
      "enum": [
        "idle",
        "exposing",
        "readout",
        "error"
      ],
      "title": "ExposureStatus",
      "type": "string"
    }
  },
  "version": 1
};
IExposure.bases = [];
