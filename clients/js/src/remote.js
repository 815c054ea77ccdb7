// The base of the generated interface classes: a proxy for one module, calling through a client.
import { checkArguments } from "./schema.js";

export class RemoteInterface {
  /** The catalogue entry of the interface (set by the generated class). */
  static spec = { name: "", version: 0, methods: {}, schemas: {} };
  /** @type {Array<typeof RemoteInterface>} the interfaces it extends (set by the generated class) */
  static bases = [];

  /**
   * Where a method is declared: its catalogue entry and the schemas its `$ref`s point into.
   * @param {string} method
   * @returns {{spec: object, schemas: Object<string, object>}|null}
   */
  static declaration(method) {
    if (Object.hasOwn(this.spec.methods, method)) {
      return { spec: this.spec.methods[method], schemas: this.spec.schemas };
    }
    for (const base of this.bases) {
      const found = base.declaration(method);
      if (found) return found;
    }
    return null;
  }

  /**
   * @param {import("./client.js").NightcrewClient} client
   * @param {string} moduleName
   */
  constructor(client, moduleName) {
    this._client = client;
    this._module = moduleName;
  }

  /** The name of the module this proxy calls. */
  get moduleName() {
    return this._module;
  }

  /**
   * Check the arguments against the catalogue, then call the module (generated methods call this).
   * @param {string} method
   * @param {ArrayLike<*>} args all the arguments given (also more than the method has)
   */
  async _invoke(method, args) {
    const { spec, schemas } = this.constructor.declaration(method);
    const checked = checkArguments(method, spec.params, schemas, Array.from(args));
    return this._client.call(this._module, method, checked, { params: spec.params, schemas });
  }
}

/**
 * One proxy class with the methods of all `interfaces` (generated classes): a subclass of the first
 * that finds every method's declaration in whichever interface declares it.
 * @param {Array<typeof RemoteInterface>} interfaces
 * @returns {typeof RemoteInterface}
 */
export function combinedInterface(interfaces) {
  const [first, ...rest] = interfaces;
  if (rest.length === 0) return first;
  class Combined extends first {
    static bases = interfaces;
  }
  for (const Other of rest) {
    // A generated class holds the methods of the interfaces it extends as its own.
    for (const name of Object.getOwnPropertyNames(Other.prototype)) {
      if (name !== "constructor" && !(name in Combined.prototype)) {
        Object.defineProperty(Combined.prototype, name, Object.getOwnPropertyDescriptor(Other.prototype, name));
      }
    }
  }
  return Combined;
}
