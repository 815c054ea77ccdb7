// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { Event } from "../src/event.js";

/**
 * What a camera or spectrograph is doing.
 * @typedef {"idle"|"exposing"|"readout"|"error"} ExposureStatus
 */
/**
 * Purpose of an image; written to the FITS header (IMAGETYP) and used to file it.
 * @typedef {"object"|"bias"|"dark"|"skyflat"|"domeflat"|"focus"|"acquisition"|"guiding"} ImageType
 */
/**
 * Lifecycle state of a module.
 * @typedef {"starting"|"ready"|"error"|"closing"|"closed"} ModuleState
 */
/**
 * What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.
 * @typedef {"parked"|"initializing"|"idle"|"slewing"|"tracking"|"moving"|"parking"|"aborting"|"error"|"unknown"} MotionStatus
 */
/**
 * The weather became bad: close and park now.
 */
export class BadWeatherEvent extends Event {
  static eventName = "BadWeatherEvent";
  /**
   * @param {{reason?: string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string} */
    this.reason = fields.reason ?? "";
  }
}

/**
 * A camera's or spectrograph's exposure status changed.
 */
export class ExposureStatusChangedEvent extends Event {
  static eventName = "ExposureStatusChangedEvent";
  /**
   * @param {{current: ExposureStatus, last: ExposureStatus|null}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {ExposureStatus} */
    this.current = fields.current ?? undefined;
    /** @type {ExposureStatus|null} */
    this.last = fields.last ?? undefined;
  }
}

/**
 * A filter wheel moved a new filter into the beam.
 */
export class FilterChangedEvent extends Event {
  static eventName = "FilterChangedEvent";
  /**
   * @param {{filter_name: string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string} */
    this.filter_name = fields.filter_name ?? undefined;
  }
}

/**
 * A focus series gave no best focus (e.g. no clear V); the focuser goes back where it was.
 */
export class FocusFailedEvent extends Event {
  static eventName = "FocusFailedEvent";
  /**
   * @param {{filter_name?: string|null, reason: string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string|null} */
    this.filter_name = fields.filter_name ?? null;
    /** @type {string} */
    this.reason = fields.reason ?? undefined;
  }
}

/**
 * A focus series found the best focus (e.g. for a focus model to learn from).
 */
export class FocusFoundEvent extends Event {
  static eventName = "FocusFoundEvent";
  /**
   * @param {{error: number, filter_name?: string|null, focus: number}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {number} */
    this.error = fields.error ?? undefined;
    /** @type {string|null} */
    this.filter_name = fields.filter_name ?? null;
    /** @type {number} */
    this.focus = fields.focus ?? undefined;
  }
}

/**
 * The weather became good.
 */
export class GoodWeatherEvent extends Event {
  static eventName = "GoodWeatherEvent";
  /**
   * @param {{eta?: Date|string|null}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {Date|string|null} */
    this.eta = fields.eta ?? null;
  }
}

/**
 * One log record of level INFO or higher.
 */
export class LogEvent extends Event {
  static eventName = "LogEvent";
  /**
   * @param {{filename?: string|null, level: string, line?: number|null, logger: string, message: string, time: Date|string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string|null} */
    this.filename = fields.filename ?? null;
    /** @type {string} */
    this.level = fields.level ?? undefined;
    /** @type {number|null} */
    this.line = fields.line ?? null;
    /** @type {string} */
    this.logger = fields.logger ?? undefined;
    /** @type {string} */
    this.message = fields.message ?? undefined;
    /** @type {Date|string} */
    this.time = fields.time ?? undefined;
  }
}

/**
 * A module went offline.
 */
export class ModuleClosedEvent extends Event {
  static eventName = "ModuleClosedEvent";
  /**
   * @param {{}} [fields]
   */
  constructor(fields = {}) {
    super();
  }
}

/**
 * A module came online.
 */
export class ModuleOpenedEvent extends Event {
  static eventName = "ModuleOpenedEvent";
  /**
   * @param {{}} [fields]
   */
  constructor(fields = {}) {
    super();
  }
}

/**
 * A module's lifecycle state changed.
 */
export class ModuleStateChangedEvent extends Event {
  static eventName = "ModuleStateChangedEvent";
  /**
   * @param {{current: ModuleState, error?: string, last: ModuleState}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {ModuleState} */
    this.current = fields.current ?? undefined;
    /** @type {string} */
    this.error = fields.error ?? "";
    /** @type {ModuleState} */
    this.last = fields.last ?? undefined;
  }
}

/**
 * The motion status of a module, or of one of its devices, changed.
 */
export class MotionStatusChangedEvent extends Event {
  static eventName = "MotionStatusChangedEvent";
  /**
   * @param {{devices?: Object<string, MotionStatus>, status: MotionStatus}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {Object<string, MotionStatus>} */
    this.devices = fields.devices ?? undefined;
    /** @type {MotionStatus} */
    this.status = fields.status ?? undefined;
  }
}

/**
 * The telescope started moving to horizontal coordinates.
 */
export class MoveAltAzEvent extends Event {
  static eventName = "MoveAltAzEvent";
  /**
   * @param {{alt: number, az: number}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {number} */
    this.alt = fields.alt ?? undefined;
    /** @type {number} */
    this.az = fields.az ?? undefined;
  }
}

/**
 * The telescope started moving to equatorial coordinates.
 */
export class MoveRaDecEvent extends Event {
  static eventName = "MoveRaDecEvent";
  /**
   * @param {{dec: number, ra: number}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {number} */
    this.dec = fields.dec ?? undefined;
    /** @type {number} */
    this.ra = fields.ra ?? undefined;
  }
}

/**
 * A camera wrote a new image.
 */
export class NewImageEvent extends Event {
  static eventName = "NewImageEvent";
  /**
   * @param {{filename: string, image_type?: ImageType|null}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string} */
    this.filename = fields.filename ?? undefined;
    /** @type {ImageType|null} */
    this.image_type = fields.image_type ?? null;
  }
}

/**
 * A spectrograph wrote a new spectrum.
 */
export class NewSpectrumEvent extends Event {
  static eventName = "NewSpectrumEvent";
  /**
   * @param {{filename: string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string} */
    this.filename = fields.filename ?? undefined;
  }
}

/**
 * New offsets along the altitude and azimuth axes.
 */
export class OffsetsAltAzEvent extends Event {
  static eventName = "OffsetsAltAzEvent";
  /**
   * @param {{dalt: number, daz: number}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {number} */
    this.dalt = fields.dalt ?? undefined;
    /** @type {number} */
    this.daz = fields.daz ?? undefined;
  }
}

/**
 * New offsets along the RA axis (not scaled by cos dec) and the Dec axis.
 */
export class OffsetsRaDecEvent extends Event {
  static eventName = "OffsetsRaDecEvent";
  /**
   * @param {{ddec: number, dra: number}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {number} */
    this.ddec = fields.ddec ?? undefined;
    /** @type {number} */
    this.dra = fields.dra ?? undefined;
  }
}

/**
 * Rapid-response tasks were submitted: a mastermind stops a running task of lower priority for
 * them (its frame in flight kept) and runs them at once. It moves the telescope off its task, so
 * it is trusted only from the senders the access policy names for it (docs/rapid-response.md).
 */
export class RapidResponseEvent extends Event {
  static eventName = "RapidResponseEvent";
  /**
   * @param {{ids: Array<string>}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {Array<string>} */
    this.ids = fields.ids ?? undefined;
  }
}

/**
 * The roof is fully closed.
 */
export class RoofClosedEvent extends Event {
  static eventName = "RoofClosedEvent";
  /**
   * @param {{}} [fields]
   */
  constructor(fields = {}) {
    super();
  }
}

/**
 * The roof started closing.
 */
export class RoofClosingEvent extends Event {
  static eventName = "RoofClosingEvent";
  /**
   * @param {{}} [fields]
   */
  constructor(fields = {}) {
    super();
  }
}

/**
 * The roof is fully open.
 */
export class RoofOpenedEvent extends Event {
  static eventName = "RoofOpenedEvent";
  /**
   * @param {{}} [fields]
   */
  constructor(fields = {}) {
    super();
  }
}

/**
 * A module that keeps the observatory safe went silent or into error: close, park, stay closed.
 */
export class SafetyAlarmEvent extends Event {
  static eventName = "SafetyAlarmEvent";
  /**
   * @param {{reason?: string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string} */
    this.reason = fields.reason ?? "";
  }
}

/**
 * Every safety heartbeat is back and the weather is good: the roof may open again.
 */
export class SafetyClearedEvent extends Event {
  static eventName = "SafetyClearedEvent";
  /**
   * @param {{}} [fields]
   */
  constructor(fields = {}) {
    super();
  }
}

/**
 * The scheduler wrote a new schedule: whoever runs it reads it now instead of at the next poll
 * (a task that ended before its slot leaves no idle gap until then).
 */
export class ScheduleChangedEvent extends Event {
  static eventName = "ScheduleChangedEvent";
  /**
   * @param {{ids: Array<string>}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {Array<string>} */
    this.ids = fields.ids ?? undefined;
  }
}

/**
 * A task ended early.
 */
export class TaskFailedEvent extends Event {
  static eventName = "TaskFailedEvent";
  /**
   * @param {{device_fault?: boolean, id: string, name: string, reason: string, retryable?: boolean}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {boolean} */
    this.device_fault = fields.device_fault ?? false;
    /** @type {string} */
    this.id = fields.id ?? undefined;
    /** @type {string} */
    this.name = fields.name ?? undefined;
    /** @type {string} */
    this.reason = fields.reason ?? undefined;
    /** @type {boolean} */
    this.retryable = fields.retryable ?? false;
  }
}

/**
 * A task ended as planned.
 */
export class TaskFinishedEvent extends Event {
  static eventName = "TaskFinishedEvent";
  /**
   * @param {{id: string, name: string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string} */
    this.id = fields.id ?? undefined;
    /** @type {string} */
    this.name = fields.name ?? undefined;
  }
}

/**
 * A task started.
 */
export class TaskStartedEvent extends Event {
  static eventName = "TaskStartedEvent";
  /**
   * @param {{eta?: Date|string|null, id: string, name: string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {Date|string|null} */
    this.eta = fields.eta ?? null;
    /** @type {string} */
    this.id = fields.id ?? undefined;
    /** @type {string} */
    this.name = fields.name ?? undefined;
  }
}

/**
 * Tasks were added to, changed in or withdrawn from a task archive: planners look again now
 * instead of at their next poll.
 */
export class TasksChangedEvent extends Event {
  static eventName = "TasksChangedEvent";
  /**
   * @param {{change: string, ids: Array<string>}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string} */
    this.change = fields.change ?? undefined;
    /** @type {Array<string>} */
    this.ids = fields.ids ?? undefined;
  }
}

/**
 * Sent by tests and by ``nightcrew`` diagnostics.
 */
export class TestEvent extends Event {
  static eventName = "TestEvent";
  /**
   * @param {{message?: string}} [fields]
   */
  constructor(fields = {}) {
    super();
    /** @type {string} */
    this.message = fields.message ?? "";
  }
}

/**
 * The safety watchdog is alive and watching (sent every round): the dead-man's switch of roofs
 * and telescopes that name it releases when these stop (nightcrew.modules.motion.base). Trusted
 * only from its senders, since a forged one would hold a roof open under a frozen watchdog.
 */
export class WatchdogHeartbeatEvent extends Event {
  static eventName = "WatchdogHeartbeatEvent";
  /**
   * @param {{}} [fields]
   */
  constructor(fields = {}) {
    super();
  }
}

/** Every event class, by the name it travels under. */
export const EVENTS = {BadWeatherEvent, ExposureStatusChangedEvent, FilterChangedEvent, FocusFailedEvent, FocusFoundEvent, GoodWeatherEvent, LogEvent, ModuleClosedEvent, ModuleOpenedEvent, ModuleStateChangedEvent, MotionStatusChangedEvent, MoveAltAzEvent, MoveRaDecEvent, NewImageEvent, NewSpectrumEvent, OffsetsAltAzEvent, OffsetsRaDecEvent, RapidResponseEvent, RoofClosedEvent, RoofClosingEvent, RoofOpenedEvent, SafetyAlarmEvent, SafetyClearedEvent, ScheduleChangedEvent, TaskFailedEvent, TaskFinishedEvent, TaskStartedEvent, TasksChangedEvent, TestEvent, WatchdogHeartbeatEvent};

/** JSON Schema of every event and of the types they use (`$defs`, as in the catalogue). */
export const EVENT_SCHEMAS = {
  "BadWeatherEvent": {
    "description": "The weather became bad: close and park now.",
    "properties": {
      "reason": {
        "default": "",
        "title": "Reason",
        "type": "string"
      }
    },
    "title": "BadWeatherEvent",
    "type": "object",
    "x-persistent": true
  },
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
  },
  "ExposureStatusChangedEvent": {
    "description": "A camera's or spectrograph's exposure status changed.",
    "properties": {
      "current": {
        "$ref": "#/$defs/ExposureStatus"
      },
      "last": {
        "anyOf": [
          {
            "$ref": "#/$defs/ExposureStatus"
          },
          {
            "type": "null"
          }
        ]
      }
    },
    "required": [
      "last",
      "current"
    ],
    "title": "ExposureStatusChangedEvent",
    "type": "object",
    "x-persistent": true
  },
  "FilterChangedEvent": {
    "description": "A filter wheel moved a new filter into the beam.",
    "properties": {
      "filter_name": {
        "title": "Filter Name",
        "type": "string"
      }
    },
    "required": [
      "filter_name"
    ],
    "title": "FilterChangedEvent",
    "type": "object",
    "x-persistent": true
  },
  "FocusFailedEvent": {
    "description": "A focus series gave no best focus (e.g. no clear V); the focuser goes back where it was.",
    "properties": {
      "filter_name": {
        "anyOf": [
          {
            "type": "string"
          },
          {
            "type": "null"
          }
        ],
        "default": null,
        "title": "Filter Name"
      },
      "reason": {
        "title": "Reason",
        "type": "string"
      }
    },
    "required": [
      "reason"
    ],
    "title": "FocusFailedEvent",
    "type": "object",
    "x-persistent": false
  },
  "FocusFoundEvent": {
    "description": "A focus series found the best focus (e.g. for a focus model to learn from).",
    "properties": {
      "error": {
        "title": "Error",
        "type": "number"
      },
      "filter_name": {
        "anyOf": [
          {
            "type": "string"
          },
          {
            "type": "null"
          }
        ],
        "default": null,
        "title": "Filter Name"
      },
      "focus": {
        "title": "Focus",
        "type": "number"
      }
    },
    "required": [
      "focus",
      "error"
    ],
    "title": "FocusFoundEvent",
    "type": "object",
    "x-persistent": false
  },
  "GoodWeatherEvent": {
    "description": "The weather became good.",
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
        "default": null,
        "title": "Eta"
      }
    },
    "title": "GoodWeatherEvent",
    "type": "object",
    "x-persistent": true
  },
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
  },
  "LogEvent": {
    "description": "One log record of level INFO or higher.",
    "properties": {
      "filename": {
        "anyOf": [
          {
            "type": "string"
          },
          {
            "type": "null"
          }
        ],
        "default": null,
        "title": "Filename"
      },
      "level": {
        "title": "Level",
        "type": "string"
      },
      "line": {
        "anyOf": [
          {
            "type": "integer"
          },
          {
            "type": "null"
          }
        ],
        "default": null,
        "title": "Line"
      },
      "logger": {
        "title": "Logger",
        "type": "string"
      },
      "message": {
        "title": "Message",
        "type": "string"
      },
      "time": {
        "format": "date-time",
        "title": "Time",
        "type": "string"
      }
    },
    "required": [
      "time",
      "level",
      "logger",
      "message"
    ],
    "title": "LogEvent",
    "type": "object",
    "x-persistent": false
  },
  "ModuleClosedEvent": {
    "description": "A module went offline.",
    "properties": {},
    "title": "ModuleClosedEvent",
    "type": "object",
    "x-persistent": false
  },
  "ModuleOpenedEvent": {
    "description": "A module came online.",
    "properties": {},
    "title": "ModuleOpenedEvent",
    "type": "object",
    "x-persistent": false
  },
  "ModuleState": {
    "description": "Lifecycle state of a module.",
    "enum": [
      "starting",
      "ready",
      "error",
      "closing",
      "closed"
    ],
    "title": "ModuleState",
    "type": "string"
  },
  "ModuleStateChangedEvent": {
    "description": "A module's lifecycle state changed.",
    "properties": {
      "current": {
        "$ref": "#/$defs/ModuleState"
      },
      "error": {
        "default": "",
        "title": "Error",
        "type": "string"
      },
      "last": {
        "$ref": "#/$defs/ModuleState"
      }
    },
    "required": [
      "last",
      "current"
    ],
    "title": "ModuleStateChangedEvent",
    "type": "object",
    "x-persistent": true
  },
  "MotionStatus": {
    "description": "What a moving device (telescope, roof, focuser, filter wheel, ...) is doing.",
    "enum": [
      "parked",
      "initializing",
      "idle",
      "slewing",
      "tracking",
      "moving",
      "parking",
      "aborting",
      "error",
      "unknown"
    ],
    "title": "MotionStatus",
    "type": "string"
  },
  "MotionStatusChangedEvent": {
    "description": "The motion status of a module, or of one of its devices, changed.",
    "properties": {
      "devices": {
        "additionalProperties": {
          "$ref": "#/$defs/MotionStatus"
        },
        "title": "Devices",
        "type": "object"
      },
      "status": {
        "$ref": "#/$defs/MotionStatus"
      }
    },
    "required": [
      "status"
    ],
    "title": "MotionStatusChangedEvent",
    "type": "object",
    "x-persistent": true
  },
  "MoveAltAzEvent": {
    "description": "The telescope started moving to horizontal coordinates.",
    "properties": {
      "alt": {
        "title": "Alt",
        "type": "number"
      },
      "az": {
        "title": "Az",
        "type": "number"
      }
    },
    "required": [
      "alt",
      "az"
    ],
    "title": "MoveAltAzEvent",
    "type": "object",
    "x-persistent": false
  },
  "MoveRaDecEvent": {
    "description": "The telescope started moving to equatorial coordinates.",
    "properties": {
      "dec": {
        "title": "Dec",
        "type": "number"
      },
      "ra": {
        "title": "Ra",
        "type": "number"
      }
    },
    "required": [
      "ra",
      "dec"
    ],
    "title": "MoveRaDecEvent",
    "type": "object",
    "x-persistent": false
  },
  "NewImageEvent": {
    "description": "A camera wrote a new image.",
    "properties": {
      "filename": {
        "title": "Filename",
        "type": "string"
      },
      "image_type": {
        "anyOf": [
          {
            "$ref": "#/$defs/ImageType"
          },
          {
            "type": "null"
          }
        ],
        "default": null
      }
    },
    "required": [
      "filename"
    ],
    "title": "NewImageEvent",
    "type": "object",
    "x-persistent": false
  },
  "NewSpectrumEvent": {
    "description": "A spectrograph wrote a new spectrum.",
    "properties": {
      "filename": {
        "title": "Filename",
        "type": "string"
      }
    },
    "required": [
      "filename"
    ],
    "title": "NewSpectrumEvent",
    "type": "object",
    "x-persistent": false
  },
  "OffsetsAltAzEvent": {
    "description": "New offsets along the altitude and azimuth axes.",
    "properties": {
      "dalt": {
        "title": "Dalt",
        "type": "number"
      },
      "daz": {
        "title": "Daz",
        "type": "number"
      }
    },
    "required": [
      "dalt",
      "daz"
    ],
    "title": "OffsetsAltAzEvent",
    "type": "object",
    "x-persistent": false
  },
  "OffsetsRaDecEvent": {
    "description": "New offsets along the RA axis (not scaled by cos dec) and the Dec axis.",
    "properties": {
      "ddec": {
        "title": "Ddec",
        "type": "number"
      },
      "dra": {
        "title": "Dra",
        "type": "number"
      }
    },
    "required": [
      "dra",
      "ddec"
    ],
    "title": "OffsetsRaDecEvent",
    "type": "object",
    "x-persistent": false
  },
  "RapidResponseEvent": {
    "description": "Rapid-response tasks were submitted: a mastermind stops a running task of lower priority for\nthem (its frame in flight kept) and runs them at once. It moves the telescope off its task, so\nit is trusted only from the senders the access policy names for it (docs/rapid-response.md).",
    "properties": {
      "ids": {
        "items": {
          "type": "string"
        },
        "title": "Ids",
        "type": "array"
      }
    },
    "required": [
      "ids"
    ],
    "title": "RapidResponseEvent",
    "type": "object",
    "x-persistent": false
  },
  "RoofClosedEvent": {
    "description": "The roof is fully closed.",
    "properties": {},
    "title": "RoofClosedEvent",
    "type": "object",
    "x-persistent": true
  },
  "RoofClosingEvent": {
    "description": "The roof started closing.",
    "properties": {},
    "title": "RoofClosingEvent",
    "type": "object",
    "x-persistent": true
  },
  "RoofOpenedEvent": {
    "description": "The roof is fully open.",
    "properties": {},
    "title": "RoofOpenedEvent",
    "type": "object",
    "x-persistent": true
  },
  "SafetyAlarmEvent": {
    "description": "A module that keeps the observatory safe went silent or into error: close, park, stay closed.",
    "properties": {
      "reason": {
        "default": "",
        "title": "Reason",
        "type": "string"
      }
    },
    "title": "SafetyAlarmEvent",
    "type": "object",
    "x-persistent": true
  },
  "SafetyClearedEvent": {
    "description": "Every safety heartbeat is back and the weather is good: the roof may open again.",
    "properties": {},
    "title": "SafetyClearedEvent",
    "type": "object",
    "x-persistent": true
  },
  "ScheduleChangedEvent": {
    "description": "The scheduler wrote a new schedule: whoever runs it reads it now instead of at the next poll\n(a task that ended before its slot leaves no idle gap until then).",
    "properties": {
      "ids": {
        "items": {
          "type": "string"
        },
        "title": "Ids",
        "type": "array"
      }
    },
    "required": [
      "ids"
    ],
    "title": "ScheduleChangedEvent",
    "type": "object",
    "x-persistent": false
  },
  "TaskFailedEvent": {
    "description": "A task ended early.",
    "properties": {
      "device_fault": {
        "default": false,
        "title": "Device Fault",
        "type": "boolean"
      },
      "id": {
        "title": "Id",
        "type": "string"
      },
      "name": {
        "title": "Name",
        "type": "string"
      },
      "reason": {
        "title": "Reason",
        "type": "string"
      },
      "retryable": {
        "default": false,
        "title": "Retryable",
        "type": "boolean"
      }
    },
    "required": [
      "name",
      "id",
      "reason"
    ],
    "title": "TaskFailedEvent",
    "type": "object",
    "x-persistent": false
  },
  "TaskFinishedEvent": {
    "description": "A task ended as planned.",
    "properties": {
      "id": {
        "title": "Id",
        "type": "string"
      },
      "name": {
        "title": "Name",
        "type": "string"
      }
    },
    "required": [
      "name",
      "id"
    ],
    "title": "TaskFinishedEvent",
    "type": "object",
    "x-persistent": false
  },
  "TaskStartedEvent": {
    "description": "A task started.",
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
        "default": null,
        "title": "Eta"
      },
      "id": {
        "title": "Id",
        "type": "string"
      },
      "name": {
        "title": "Name",
        "type": "string"
      }
    },
    "required": [
      "name",
      "id"
    ],
    "title": "TaskStartedEvent",
    "type": "object",
    "x-persistent": false
  },
  "TasksChangedEvent": {
    "description": "Tasks were added to, changed in or withdrawn from a task archive: planners look again now\ninstead of at their next poll.",
    "properties": {
      "change": {
        "title": "Change",
        "type": "string"
      },
      "ids": {
        "items": {
          "type": "string"
        },
        "title": "Ids",
        "type": "array"
      }
    },
    "required": [
      "ids",
      "change"
    ],
    "title": "TasksChangedEvent",
    "type": "object",
    "x-persistent": false
  },
  "TestEvent": {
    "description": "Sent by tests and by ``nightcrew`` diagnostics.",
    "properties": {
      "message": {
        "default": "",
        "title": "Message",
        "type": "string"
      }
    },
    "title": "TestEvent",
    "type": "object",
    "x-persistent": false
  },
  "WatchdogHeartbeatEvent": {
    "description": "The safety watchdog is alive and watching (sent every round): the dead-man's switch of roofs\nand telescopes that name it releases when these stop (nightcrew.modules.motion.base). Trusted\nonly from its senders, since a forged one would hold a roof open under a frozen watchdog.",
    "properties": {},
    "title": "WatchdogHeartbeatEvent",
    "type": "object",
    "x-persistent": false
  }
};
