// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * Purpose of an image; written to the FITS header (IMAGETYP) and used to file it.
 * @typedef {"object"|"bias"|"dark"|"skyflat"|"domeflat"|"focus"|"acquisition"|"guiding"} ImageType
 */
/**
 * A settable image type, written to the header of the next frames.
 */
export class IImageType extends RemoteInterface {
  /**
   * Image type of the next frames.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<ImageType>}
   */
  get_image_type() {
    return this._invoke("get_image_type", arguments);
  }
  /**
   * Set the image type of the next frames.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {ImageType} image_type
   * @returns {Promise<null>}
   */
  set_image_type(image_type) {
    return this._invoke("set_image_type", arguments);
  }
}
IImageType.spec = {
  "methods": {
    "get_image_type": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/ImageType"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "set_image_type": {
      "params": [
        {
          "name": "image_type",
          "required": true,
          "schema": {
            "$ref": "#/components/schemas/ImageType"
          }
        }
      ],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IImageType",
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
IImageType.bases = [];
