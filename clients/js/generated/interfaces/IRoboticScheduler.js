// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * A scheduler's latest plan of the night, with the solver's objective and proven bound.
 * @typedef {{bound: number|null, gap: number|null, night_end: Date|string, night_start: Date|string, objective: number, planned_at: Date|string, slots: Array<PlannedTask>, solver: string, status: string, unplanned?: Array<UnplannedTask>, wall_time_s: number}} Plan
 */
/**
 * One task placed in a plan; ``name`` when the planner knows it.
 * @typedef {{end: Date|string, name?: string|null, priority?: number|null, start: Date|string, task_id: string}} PlannedTask
 */
/**
 * A task the plan leaves out, and why (for a person: the constraint that keeps it out).
 * @typedef {{name?: string|null, reason: string, task_id: string}} UnplannedTask
 */
/**
 * A module planning the night, which can show its plan.
 */
export class IRoboticScheduler extends RemoteInterface {
  /**
   * The latest plan; None before the first.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<Plan|null>}
   */
  get_plan() {
    return this._invoke("get_plan", arguments);
  }
}
IRoboticScheduler.spec = {
  "methods": {
    "get_plan": {
      "params": [],
      "result": {
        "anyOf": [
          {
            "$ref": "#/components/schemas/Plan"
          },
          {
            "type": "null"
          }
        ]
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IRoboticScheduler",
  "schemas": {
    "Plan": {
      "description": "A scheduler's latest plan of the night, with the solver's objective and proven bound.",
      "properties": {
        "bound": {
          "anyOf": [
            {
              "type": "number"
            },
            {
              "type": "null"
            }
          ],
          "title": "Bound"
        },
        "gap": {
          "anyOf": [
            {
              "type": "number"
            },
            {
              "type": "null"
            }
          ],
          "title": "Gap"
        },
        "night_end": {
          "format": "date-time",
          "title": "Night End",
          "type": "string"
        },
        "night_start": {
          "format": "date-time",
          "title": "Night Start",
          "type": "string"
        },
        "objective": {
          "title": "Objective",
          "type": "number"
        },
        "planned_at": {
          "format": "date-time",
          "title": "Planned At",
          "type": "string"
        },
        "slots": {
          "items": {
            "$ref": "#/components/schemas/PlannedTask"
          },
          "title": "Slots",
          "type": "array"
        },
        "solver": {
          "title": "Solver",
          "type": "string"
        },
        "status": {
          "title": "Status",
          "type": "string"
        },
        "unplanned": {
          "default": [],
          "items": {
            "$ref": "#/components/schemas/UnplannedTask"
          },
          "title": "Unplanned",
          "type": "array"
        },
        "wall_time_s": {
          "title": "Wall Time S",
          "type": "number"
        }
      },
      "required": [
        "planned_at",
        "night_start",
        "night_end",
        "solver",
        "status",
        "objective",
        "bound",
        "gap",
        "wall_time_s",
        "slots"
      ],
      "title": "Plan",
      "type": "object"
    },
    "PlannedTask": {
      "description": "One task placed in a plan; ``name`` when the planner knows it.",
      "properties": {
        "end": {
          "format": "date-time",
          "title": "End",
          "type": "string"
        },
        "name": {
          "anyOf": [
            {
              "type": "string"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Name"
        },
        "priority": {
          "anyOf": [
            {
              "type": "number"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Priority"
        },
        "start": {
          "format": "date-time",
          "title": "Start",
          "type": "string"
        },
        "task_id": {
          "title": "Task Id",
          "type": "string"
        }
      },
      "required": [
        "task_id",
        "start",
        "end"
      ],
      "title": "PlannedTask",
      "type": "object"
    },
    "UnplannedTask": {
      "description": "A task the plan leaves out, and why (for a person: the constraint that keeps it out).",
      "properties": {
        "name": {
          "anyOf": [
            {
              "type": "string"
            },
            {
              "type": "null"
            }
          ],
          "default": null,
          "title": "Name"
        },
        "reason": {
          "title": "Reason",
          "type": "string"
        },
        "task_id": {
          "title": "Task Id",
          "type": "string"
        }
      },
      "required": [
        "task_id",
        "reason"
      ],
      "title": "UnplannedTask",
      "type": "object"
    }
  },
  "version": 1
};
IRoboticScheduler.bases = [];
