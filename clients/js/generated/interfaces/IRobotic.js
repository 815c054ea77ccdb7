// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * What a robotic module (the mastermind) is doing now, and why.
 *
 * ``action`` is one of ``run_task``, ``open_up``, ``focus``, ``close_and_park``, ``wait``,
 * ``stopping`` (robotic mode is off and the roof not yet closed or the telescope not yet parked
 * since) or ``stopped``; ``waiting_for`` says why it waits (None unless ``wait``). The conditions
 * are those of its last look at the world (None before the first).
 * @typedef {{action: string, description: string, roof?: string|null, running: boolean, sun_altitude?: number|null, task?: RoboticTask|null, telescope_ready?: boolean|null, time: Date|string, waiting_for?: string|null, waiting_until?: Date|string|null, weather_good?: boolean|null}} RoboticStatus
 */
/**
 * The task a robotic module is running, and how far it got.
 * @typedef {{eta: Date|string|null, exposures_done: number, exposures_total: number, id: string, name: string, started: Date|string|null}} RoboticTask
 */
/**
 * A module running the night on its own, which can say what it does and why.
 */
export class IRobotic extends RemoteInterface {
  /**
   * The current action, the running task with its progress, the reason for waiting.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<RoboticStatus>}
   */
  get_robotic_status() {
    return this._invoke("get_robotic_status", arguments);
  }
}
IRobotic.spec = {
  "methods": {
    "get_robotic_status": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/RoboticStatus"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IRobotic",
  "schemas": {
    "RoboticStatus": {
      "description": "What a robotic module (the mastermind) is doing now, and why.\n\n``action`` is one of ``run_task``, ``open_up``, ``focus``, ``close_and_park``, ``wait``,\n``stopping`` (robotic mode is off and the roof not yet closed or the telescope not yet parked\nsince) or ``stopped``; ``waiting_for`` says why it waits (None unless ``wait``). The conditions\nare those of its last look at the world (None before the first).",
      "properties": {
        "action": {
          "title": "Action",
          "type": "string"
        },
        "description": {
          "title": "Description",
          "type": "string"
        },
        "roof": {
          "anyOf": [
            {
              "type": "string"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Roof"
        },
        "running": {
          "title": "Running",
          "type": "boolean"
        },
        "sun_altitude": {
          "anyOf": [
            {
              "type": "number"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Sun Altitude"
        },
        "task": {
          "anyOf": [
            {
              "$ref": "#/components/schemas/RoboticTask"
            },
            {
              "type": "null"
            }
          ],
          "default": null
        },
        "telescope_ready": {
          "anyOf": [
            {
              "type": "boolean"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Telescope Ready"
        },
        "time": {
          "format": "date-time",
          "title": "Time",
          "type": "string"
        },
        "waiting_for": {
          "anyOf": [
            {
              "type": "string"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Waiting For"
        },
        "waiting_until": {
          "anyOf": [
            {
              "format": "date-time",
              "type": "string"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Waiting Until"
        },
        "weather_good": {
          "anyOf": [
            {
              "type": "boolean"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Weather Good"
        }
      },
      "required": [
        "time",
        "running",
        "action",
        "description"
      ],
      "title": "RoboticStatus",
      "type": "object"
    },
    "RoboticTask": {
      "description": "The task a robotic module is running, and how far it got.",
      "properties": {
        "eta": {
          "anyOf": [
            {
              "format": "date-time",
              "type": "string"
            },
            {
              "type": "null"
            }
          ],
          "title": "Eta"
        },
        "exposures_done": {
          "title": "Exposures Done",
          "type": "integer"
        },
        "exposures_total": {
          "title": "Exposures Total",
          "type": "integer"
        },
        "id": {
          "title": "Id",
          "type": "string"
        },
        "name": {
          "title": "Name",
          "type": "string"
        },
        "started": {
          "anyOf": [
            {
              "format": "date-time",
              "type": "string"
            },
            {
              "type": "null"
            }
          ],
          "title": "Started"
        }
      },
      "required": [
        "id",
        "name",
        "started",
        "eta",
        "exposures_done",
        "exposures_total"
      ],
      "title": "RoboticTask",
      "type": "object"
    }
  },
  "version": 1
};
IRobotic.bases = [];
