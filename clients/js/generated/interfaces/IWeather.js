// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { RemoteInterface } from "../../src/remote.js";

/**
 * One measurement; units are those of :class:`WeatherSensor`. None if the sensor has no value.
 * @typedef {{time: Date|string, value: number|null}} SensorValue
 */
/**
 * The current weather as the weather module sees it.
 * @typedef {{good: boolean, sensors: Object<string, number|null>, time: Date|string}} WeatherReport
 */
/**
 * Kinds of weather measurements, with their units in the comments.
 * @typedef {"temperature"|"humidity"|"pressure"|"wind_speed"|"wind_direction"|"rain"|"sky_temperature"|"dew_point"|"sun_altitude"|"particles"|"sky_brightness"|"safe"} WeatherSensor
 */
/**
 * A weather module combining one or more stations into a verdict.
 *
 * A *station* is named as in the weather module's configuration (the keys of its ``stations:``,
 * e.g. ``roof``; its ``checks`` name them as ``station.sensor``), not as a module.
 */
export class IWeather extends RemoteInterface {
  /**
   * The verdict with the current measurements.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<WeatherReport>}
   */
  get_current_weather() {
    return this._invoke("get_current_weather", arguments);
  }
  /**
   * Latest ``sensor`` value at ``station`` (a key of the module's ``stations:``); None: no reading.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @param {string} station
   * @param {WeatherSensor} sensor
   * @returns {Promise<SensorValue>}
   */
  get_sensor_value(station, sensor) {
    return this._invoke("get_sensor_value", arguments);
  }
  /**
   * Whether the weather allows the observatory to be open.
   *
   * Timeout: 10 clock seconds (the default, not announced).
   * @returns {Promise<boolean>}
   */
  is_weather_good() {
    return this._invoke("is_weather_good", arguments);
  }
}
IWeather.spec = {
  "methods": {
    "get_current_weather": {
      "params": [],
      "result": {
        "$ref": "#/components/schemas/WeatherReport"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "get_sensor_value": {
      "params": [
        {
          "name": "station",
          "required": true,
          "schema": {
            "type": "string"
          }
        },
        {
          "name": "sensor",
          "required": true,
          "schema": {
            "$ref": "#/components/schemas/WeatherSensor"
          }
        }
      ],
      "result": {
        "$ref": "#/components/schemas/SensorValue"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    },
    "is_weather_good": {
      "params": [],
      "result": {
        "type": "boolean"
      },
      "timeout": {
        "announced": false,
        "seconds": 10.0
      }
    }
  },
  "name": "IWeather",
  "schemas": {
    "SensorValue": {
      "description": "One measurement; units are those of :class:`WeatherSensor`. None if the sensor has no value.",
      "properties": {
        "time": {
          "format": "date-time",
          "title": "Time",
          "type": "string"
        },
        "value": {
          "anyOf": [
            {
              "type": "number"
            },
            {
              "type": "null"
            }
          ],
          "title": "Value"
        }
      },
      "required": [
        "time",
        "value"
      ],
      "title": "SensorValue",
      "type": "object"
    },
    "WeatherReport": {
      "description": "The current weather as the weather module sees it.",
      "properties": {
        "good": {
          "title": "Good",
          "type": "boolean"
        },
        "sensors": {
          "additionalProperties": {
            "anyOf": [
              {
                "type": "number"
              },
              {
                "type": "null"
              }
            ]
          },
          "title": "Sensors",
          "type": "object"
        },
        "time": {
          "format": "date-time",
          "title": "Time",
          "type": "string"
        }
      },
      "required": [
        "time",
        "good",
        "sensors"
      ],
      "title": "WeatherReport",
      "type": "object"
    },
    "WeatherSensor": {
      "description": "Kinds of weather measurements, with their units in the comments.",
      "enum": [
        "temperature",
        "humidity",
        "pressure",
        "wind_speed",
        "wind_direction",
        "rain",
        "sky_temperature",
        "dew_point",
        "sun_altitude",
        "particles",
        "sky_brightness",
        "safe"
      ],
      "title": "WeatherSensor",
      "type": "string"
    }
  },
  "version": 1
};
IWeather.bases = [];
