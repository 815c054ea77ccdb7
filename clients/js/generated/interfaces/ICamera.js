// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IAbortable } from "./IAbortable.js";
import { IData } from "./IData.js";
import { IExposure } from "./IExposure.js";

/**
 * What a camera or spectrograph is doing.
 * @typedef {"idle"|"exposing"|"readout"|"error"} ExposureStatus
 */
/**
 * Purpose of an image; written to the FITS header (IMAGETYP) and used to file it.
 * @typedef {"object"|"bias"|"dark"|"skyflat"|"domeflat"|"focus"|"acquisition"|"guiding"} ImageType
 */
/**
 * A camera: takes images, can be aborted and watched.
 *
 * Extends IAbortable, IData, IExposure (their methods are here too).
 */
export class ICamera extends RemoteInterface {
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
   * Take a frame and return its VFS path (sent in a NewImageEvent if ``broadcast``).
   *
   * Timeout: announced, 3600 clock seconds.
   * @param {boolean} [broadcast] default true
   * @param {ImageType|null} [image_type] default null
   * @returns {Promise<string>}
   */
  grab_data(broadcast, image_type) {
    return this._invoke("grab_data", arguments);
  }
}
ICamera.spec = {
  "methods": {},
  "name": "ICamera",
  "schemas": {},
  "version": 1
};
ICamera.bases = [IAbortable, IData, IExposure];
