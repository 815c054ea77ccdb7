// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * An exposure that can be ended early and still read out (ASCOM's StopExposure, not AbortExposure).
 *
 * The running ``grab_data`` then returns its frame as usual, with EXPTIME the seconds really
 * exposed, EXPREQ the seconds asked for and ``CUTSHORT = T``; an abort, by contrast, keeps nothing.
 */
export class IStoppableExposure extends RemoteInterface {
  /**
   * Close the shutter now, read out and keep the frame; nothing happens when not exposing.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<null>}
   */
  stop_exposure() {
    return this._invoke("stop_exposure", arguments);
  }
}
IStoppableExposure.spec = {
  "methods": {
    "stop_exposure": {
      "params": [],
      "result": {
        "type": "null"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IStoppableExposure",
  "schemas": {},
  "version": 1
};
IStoppableExposure.bases = [];
