// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";
import { IData } from "./IData.js";

/**
 * Purpose of an image; written to the FITS header (IMAGETYP) and used to file it.
 * @typedef {"object"|"bias"|"dark"|"skyflat"|"domeflat"|"focus"|"acquisition"|"guiding"} ImageType
 */
/**
 * A camera with a live video stream; grab_data saves the current frame.
 *
 * Extends IData (their methods are here too).
 */
export class IVideo extends RemoteInterface {
  /**
   * URL of the video stream.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<string>}
   */
  get_video() {
    return this._invoke("get_video", arguments);
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
IVideo.spec = {
  "methods": {
    "get_video": {
      "params": [],
      "result": {
        "type": "string"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IVideo",
  "schemas": {},
  "version": 1
};
IVideo.bases = [IData];
