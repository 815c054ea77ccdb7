// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Purpose of an image; written to the FITS header (IMAGETYP) and used to file it.
 * @typedef {"object"|"bias"|"dark"|"skyflat"|"domeflat"|"focus"|"acquisition"|"guiding"} ImageType
 */
/**
 * A device that produces data files (images, spectra, video frames).
 *
 * ``grab_data(broadcast, image_type)``: with ``broadcast`` false no NewImageEvent is sent, so only
 * the caller learns of the frame (an acquisition or focus frame no image pipeline should take);
 * ``image_type`` None takes the one set with IImageType. Its announced timeout is at most 3600 s;
 * nightcrew's cameras announce the exposure time set plus read-out, header round and margins
 * (docs/protocol.md, section 4).
 */
export class IData extends RemoteInterface {
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
IData.spec = {
  "methods": {
    "grab_data": {
      "params": [
        {
          "name": "broadcast",
          "required": false,
          "schema": {
            "default": true,
            "type": "boolean"
          }
        },
        {
          "name": "image_type",
          "required": false,
          "schema": {
            "anyOf": [
              {
                "$ref": "#/components/schemas/ImageType"
              },
              {
                "type": "null"
              }
            ],
            "default": null
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
  "name": "IData",
  "schemas": {
    "ImageType": {
      "description": "Purpose of an image; written to the FITS header (IMAGETYP) and used to file it.",
      "enum": [
        "object",
        "bias",
        "dark",
        "skyflat",
        "domeflat",
        "focus",
        "acquisition",
        "guiding"
      ],
      "title": "ImageType",
      "type": "string"
    }
  },
  "version": 1
};
IData.bases = [];
