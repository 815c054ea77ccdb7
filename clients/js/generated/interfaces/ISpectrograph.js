// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IAbortable } from "./IAbortable.js";
import { IExposure } from "./IExposure.js";

/**
 * What a camera or spectrograph is doing.
 * @typedef {"idle"|"exposing"|"readout"|"error"} ExposureStatus
 */
/**
 * A spectrograph: takes spectra, can be aborted and watched.
 *
 * Extends IAbortable, IExposure (their methods are here too).
 */
export class ISpectrograph extends RemoteInterface {
  /**
   * Abort the current action; the aborted call raises AbortedError.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<null>}
   */
  abort() {
    return this._invoke("abort", arguments);
  }
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
  /**
   * Take one spectrum and return its VFS path; broadcast a NewSpectrumEvent if asked.
   *
   * Timeout: announced, 3600 clock seconds.
   * @param {boolean} [broadcast] default true
   * @returns {Promise<string>}
   */
  grab_spectrum(broadcast) {
    return this._invoke("grab_spectrum", arguments);
  }
}
ISpectrograph.spec = {
  "methods": {
    "grab_spectrum": {
      "params": [
        {
          "name": "broadcast",
          "required": false,
          "schema": {
            "default": true,
            "type": "boolean"
          }
        }
      ],
      "result": {
        "type": "string"
      },
      "timeout": {
        "announced": true,
        "seconds": 3600.0
      }
    }
  },
  "name": "ISpectrograph",
  "schemas": {},
  "version": 1
};
ISpectrograph.bases = [IAbortable, IExposure];
